//! The types LIBERO's visual facts are written in (see `facts.rs`, generated from the asset XMLs).

/// One visual geom of a category: what MuJoCo draws for it (its collision geoms are elsewhere).
pub(crate) struct PartFact {
    /// The catalog body it moves with (`main`, `cabinet_top`, `microdoorroot`, ...).
    pub body: &'static str,
    /// Pose in that body's frame (jointless XML sub-bodies already folded in).
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub shape: Shape,
    pub material: MaterialFact,
}

/// A geom's shape: a mesh file of the asset tree, or one of MuJoCo's primitives.
pub(crate) enum Shape {
    /// Path relative to LIBERO's `assets/` folder, with the `<mesh scale>`.
    Mesh { file: &'static str, scale: [f64; 3] },
    Box { half: [f64; 3] },
    Capsule { radius: f64, half_height: f64 },
}

/// MuJoCo's `<material>` (or the geom's own `rgba` where it has none).
pub(crate) struct MaterialFact {
    pub rgba: [f64; 4],
    pub specular: f64,
    pub shininess: f64,
    /// MuJoCo mirrors the scene in boxes and planes with a reflectance (meshes ignore it).
    pub reflectance: f64,
    pub emission: f64,
    pub texture: Option<TextureFact>,
}

/// MuJoCo's `<texture>` as a material uses it.
pub(crate) struct TextureFact {
    /// Path relative to LIBERO's `assets/` folder.
    pub file: &'static str,
    /// `type="cube"` (MuJoCo maps it by direction, not by the mesh's UVs).
    pub cube: bool,
    /// `texrepeat` (`texuniform` is off on every object texture).
    pub repeat: [f64; 2],
}
