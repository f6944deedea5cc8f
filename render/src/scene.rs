//! What to draw: instances of shared meshes with materials, and MuJoCo-style lights.
//!
//! All types are plain data. Meshes and textures are shared by `Arc`, so cloning a scene (for a
//! second environment or a simulated future) copies only the per-instance poses and materials.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use crate::mesh::Mesh;
use crate::texture::Texture;
use crate::transform::Transform;

/// Surface appearance, with MuJoCo's `<material>` meaning for each field.
///
/// Lighting is OpenGL fixed-function Blinn-Phong as MuJoCo sets it up: ambient and diffuse
/// reflectance are `rgba`, specular reflectance is the scalar `specular` (white), the Phong
/// exponent is `128 × shininess`, and `emission × rgba` is added unlit. A texture multiplies the
/// lit colour (OpenGL `GL_MODULATE`).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Base colour and opacity; `a < 1` draws the instance blended (see [`Instance`]).
    pub rgba: [f32; 4],
    /// Specular reflectance, `[0, 1]` (MuJoCo default 0.5).
    pub specular: f32,
    /// Shininess, `[0, 1]`; the Phong exponent is `128 × shininess` (MuJoCo default 0.5).
    pub shininess: f32,
    /// Self-illumination as a fraction of `rgba` (MuJoCo default 0).
    pub emission: f32,
    /// Optional colour texture, sampled with the mesh's UVs (ignored for meshes without UVs).
    pub texture: Option<Arc<Texture>>,
    /// Texture repeat: `uv' = uv × uv_scale + uv_offset` (MuJoCo's `texrepeat`).
    pub uv_scale: Vec2,
    /// Texture offset added after scaling.
    pub uv_offset: Vec2,
    /// Draw back faces too (for thin open geometry such as signs and sheets); back faces are lit
    /// with the reversed normal.
    pub double_sided: bool,
    /// Skip lighting: the colour is exactly `rgba` (times the texture). For overlays and markers
    /// that must keep their colours.
    pub unlit: bool,
}

impl Default for Material {
    /// MuJoCo's default material: white, specular 0.5, shininess 0.5, no emission.
    fn default() -> Self {
        Material {
            rgba: [1.0, 1.0, 1.0, 1.0],
            specular: 0.5,
            shininess: 0.5,
            emission: 0.0,
            texture: None,
            uv_scale: Vec2::ONE,
            uv_offset: Vec2::ZERO,
            double_sided: false,
            unlit: false,
        }
    }
}

impl Material {
    /// MuJoCo's default material with another colour.
    pub fn rgba(rgba: [f32; 4]) -> Material {
        Material { rgba, ..Material::default() }
    }

    /// An unlit, single-coloured material.
    pub fn unlit(rgba: [f32; 4]) -> Material {
        Material { rgba, unlit: true, ..Material::default() }
    }

    /// True when the instance is drawn with blending instead of as an opaque surface.
    pub fn is_transparent(&self) -> bool {
        self.rgba[3] < 1.0
    }
}

/// One placed mesh.
///
/// Opaque instances write colour, depth and segmentation. Transparent ones (`rgba[3] < 1`) are
/// blended over the opaque image back to front, write segmentation where they pass the depth
/// test, and leave depth unchanged (as MuJoCo does).
#[derive(Clone, Debug)]
pub struct Instance {
    pub mesh: Arc<Mesh>,
    pub material: Material,
    /// Local-to-world placement.
    pub transform: Transform,
    /// Segmentation id written where this instance is visible; 0 means background, so use ids
    /// from 1.
    pub segment: u32,
}

impl Instance {
    /// An instance with MuJoCo's default material.
    pub fn new(mesh: Arc<Mesh>, transform: Transform, segment: u32) -> Instance {
        Instance { mesh, material: Material::default(), transform, segment }
    }

    /// The same instance with another material.
    pub fn with_material(mut self, material: Material) -> Instance {
        self.material = material;
        self
    }
}

/// Where a light is and how it spreads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Parallel rays travelling along `direction` (MuJoCo `directional="true"`).
    Directional { direction: Vec3 },
    /// A positional light shining along `direction` (MuJoCo's default light type). Intensity
    /// falls off as `1 / (a0 + a1 d + a2 d²)` and as `cos^exponent` of the angle off the axis,
    /// and is zero beyond `cutoff_deg`; `cutoff_deg = 180` makes a point light.
    Spot { position: Vec3, direction: Vec3, cutoff_deg: f32, exponent: f32, attenuation: [f32; 3] },
}

/// A scene light with MuJoCo's `<light>` attributes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    pub ambient: [f32; 3],
    pub diffuse: [f32; 3],
    pub specular: [f32; 3],
    /// Casts shadows when the renderer has shadows enabled.
    pub cast_shadow: bool,
}

impl Light {
    /// A spot light with MuJoCo's defaults: ambient 0, diffuse 0.7, specular 0.3, cutoff 45°,
    /// exponent 10, attenuation (1, 0, 0), casting shadows.
    pub fn mujoco_spot(position: Vec3, direction: Vec3) -> Light {
        Light {
            kind: LightKind::Spot { position, direction, cutoff_deg: 45.0, exponent: 10.0, attenuation: [1.0, 0.0, 0.0] },
            ambient: [0.0; 3],
            diffuse: [0.7; 3],
            specular: [0.3; 3],
            cast_shadow: true,
        }
    }

    /// A directional light with MuJoCo's default colours.
    pub fn mujoco_directional(direction: Vec3) -> Light {
        Light { kind: LightKind::Directional { direction }, ..Light::mujoco_spot(Vec3::ZERO, direction) }
    }
}

/// MuJoCo's `<visual><headlight>`: a directional light that travels along the camera's view
/// direction, never casts shadows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Headlight {
    pub active: bool,
    pub ambient: [f32; 3],
    pub diffuse: [f32; 3],
    pub specular: [f32; 3],
}

impl Default for Headlight {
    /// MuJoCo's defaults (robosuite and LIBERO keep them): ambient 0.1, diffuse 0.4,
    /// specular 0.5.
    fn default() -> Self {
        Headlight { active: true, ambient: [0.1; 3], diffuse: [0.4; 3], specular: [0.5; 3] }
    }
}

/// What pixels not covered by any surface show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Background {
    /// One colour (linear RGB in `[0, 1]`).
    Solid([f32; 3]),
    /// A sky-like blend by the world-z of the viewing ray: `up` straight up, `down` straight
    /// down (an approximation of MuJoCo's gradient skybox, `rgb1` / `rgb2`).
    Gradient { up: [f32; 3], down: [f32; 3] },
}

impl Default for Background {
    fn default() -> Self {
        Background::Solid([0.0; 3])
    }
}

/// A flat mirror as MuJoCo draws one (`render_gl3.c`, flag `mjRND_REFLECTION`): the +z face of
/// a box whose material has `reflectance > 0` (MuJoCo keeps only the first such geom). The
/// scene on the face's outer side, lit as it is and with every colour scaled by `reflectance`,
/// is seen mirrored in the face and added to the face's own colour; where the mirror shows
/// nothing it adds nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Index of the reflecting instance in [`Scene::instances`]; it does not see itself.
    pub instance: usize,
    /// Height of the reflecting face in the instance's local frame (a box's half height).
    pub face_z: f32,
    pub reflectance: f32,
}

/// Everything one frame needs besides the camera.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub instances: Vec<Instance>,
    pub lights: Vec<Light>,
    pub headlight: Headlight,
    pub background: Background,
    /// MuJoCo's one reflective surface, if the scene has one.
    pub mirror: Option<Mirror>,
}
