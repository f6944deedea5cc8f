//! The catalog's public data model: what one object or fixture category is made of.
//!
//! Conventions (all MuJoCo's, so numbers compare directly with LIBERO):
//! - lengths in metres, angles in radians, quaternions `[w, x, y, z]`, unit length;
//! - every pose is relative to the parent body; body 0 is the object frame, which is LIBERO's
//!   root body `<instance>_main` (the asset XML's `object` body) and the pose the predicates read;
//! - box sizes are half-extents, capsule and cylinder sizes are radius and half-length.

use serde::{Deserialize, Serialize};

/// Damping of the free joint LIBERO gives every movable object (`joints=[free, damping 0.0005]`).
pub const FREE_JOINT_DAMPING: f64 = 0.0005;

/// One category: its rigid bodies, named sites, spawn offsets and procedural look.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ObjectModel {
    /// BDDL category name, e.g. `akita_black_bowl`.
    pub category: String,
    pub kind: ObjectKind,
    /// `bodies[0]` is the root; every other body has a parent earlier in the list and a joint.
    /// Jointless (welded) XML sub-bodies are fused into their parent.
    pub bodies: Vec<BodyModel>,
    pub sites: Vec<SiteModel>,
    /// Position of robosuite's `bottom_site` in the object frame (spawn height).
    pub bottom_offset: [f64; 3],
    /// Position of robosuite's `top_site` in the object frame.
    pub top_offset: [f64; 3],
    /// robosuite's `horizontal_radius` (x of `horizontal_radius_site`), used for overlap rejection.
    pub horizontal_radius: f64,
    /// What to draw; poses are in the frame of `VisualPart::body`.
    pub visuals: Vec<VisualPart>,
}

/// Whether LIBERO gives the object a free joint or places it as a static fixture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ObjectKind {
    /// Free-floating (free joint with [`FREE_JOINT_DAMPING`]).
    Movable,
    /// Root welded to the world where the scene places it; only internal joints move.
    Fixture,
}

/// One rigid body of a category.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyModel {
    /// LIBERO's body name without the instance prefix (`main`, `cabinet_top`, `microdoorroot`).
    pub name: String,
    /// Index into `ObjectModel::bodies`; `None` only for the root.
    pub parent: Option<usize>,
    /// Body frame relative to the parent frame (identity for the root).
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    /// The joint connecting this body to its parent (`None` for the root).
    pub joint: Option<JointModel>,
    pub inertial: Inertial,
    /// Collision shapes (LIBERO's group-0 geoms), in this body's frame.
    pub colliders: Vec<Collider>,
}

/// An articulation joint (always limited in LIBERO's assets).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointModel {
    pub kind: JointKind,
    /// LIBERO's joint name without the instance prefix (`top_level`, `microjoint`, `button`).
    pub name: String,
    /// Unit axis in the body frame.
    pub axis: [f64; 3],
    /// Anchor point in the body frame.
    pub pos: [f64; 3],
    /// Position limits: metres for slides, radians for hinges.
    pub range: [f64; 2],
    pub damping: f64,
    pub armature: f64,
    pub frictionloss: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointKind {
    Hinge,
    Slide,
}

/// Mass properties as MuJoCo compiles them: principal moments in the frame (`com`, `quat_wxyz`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Inertial {
    pub mass: f64,
    /// Centre of mass in the body frame.
    pub com: [f64; 3],
    /// Principal moments of inertia about the axes of `quat_wxyz`.
    pub inertia: [f64; 3],
    /// Orientation of the principal axes in the body frame.
    pub quat_wxyz: [f64; 4],
}

/// One collision geom with MuJoCo's contact parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Collider {
    pub shape: ColliderShape,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    /// Sliding, torsional and rolling friction.
    pub friction: [f64; 3],
    /// MuJoCo `solref` (time constant, damping ratio).
    pub solref: [f64; 2],
    /// MuJoCo `solimp` (dmin, dmax, width, midpoint, power).
    pub solimp: [f64; 5],
    /// Contacts are created below this distance (0 except the microwave's 0.001).
    pub margin: f64,
    pub contype: u32,
    pub conaffinity: u32,
    pub condim: u8,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ColliderShape {
    Box {
        half_size: [f64; 3],
    },
    /// Axis along local z; `half_length` excludes the hemispherical caps.
    Capsule {
        radius: f64,
        half_length: f64,
    },
}

/// A named site; the predicates use its pose and half-size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SiteModel {
    /// LIBERO's site name without the instance prefix (`cook_region`, `top_region`, ...).
    pub name: String,
    /// Index of the body carrying the site (it moves with that body, e.g. with a drawer).
    pub body: usize,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    pub shape: SiteShape,
    /// Half-extents; for a cylinder `[radius, radius, half_height]`.
    pub half_size: [f64; 3],
    /// Display colour; alpha 0 means LIBERO never draws it. The stove's `burner` site is drawn
    /// (red) only while the knob is turned on.
    pub rgba: [f32; 4],
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum SiteShape {
    Box,
    Cylinder,
}

/// One piece of an object's procedural look.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VisualPart {
    /// Index of the body the part moves with.
    pub body: usize,
    pub recipe: Recipe,
    /// Pose of the recipe's local frame in the body frame.
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    /// Per-axis stretch applied to the recipe before the pose (flattened bottles); usually 1.
    pub scale: [f64; 3],
    pub rgba: [f32; 4],
}

/// A mesh recipe the renderer turns into triangles. All are centred on the local origin except
/// `Lathe`, whose profile gives heights directly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Recipe {
    /// Surface of revolution about local z through the `(radius, z)` points in order. A profile
    /// that starts and ends on the axis is a closed solid by itself; `closed` asks for flat discs
    /// on the first and last ring as well (cans, lids).
    Lathe {
        profile: Vec<(f64, f64)>,
        closed: bool,
    },
    Box {
        half: [f64; 3],
    },
    /// Axis along local z.
    Cylinder {
        radius: f64,
        half_height: f64,
    },
    /// Axis along local z; `half_height` excludes the caps.
    Capsule {
        radius: f64,
        half_height: f64,
    },
    Sphere {
        radius: f64,
    },
}

impl ObjectModel {
    /// The site called `name` (without instance prefix), if the category has one.
    pub fn site(&self, name: &str) -> Option<&SiteModel> {
        self.sites.iter().find(|s| s.name == name)
    }

    /// Index of the body called `name` (without instance prefix).
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// Total mass of all bodies (MuJoCo's subtree mass of the root).
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.inertial.mass).sum()
    }
}
