//! Objects of the LIBERO-VIFO studies that LIBERO does not have: the PiPER setting's plastic
//! cups and paper note (§4.4). Our own designs, modelled like the catalog's other objects
//! (collision boxes, mass, spawn offsets, a procedural look).
//!
//! **Cups**: a 100 ml plastic cup (6 cm tall, 5.6 cm across the rim, 3.7 cm across the
//! foot, 12 g). The tapered wall is twelve thin boxes leaning out by the wall's 9° taper, so one
//! cup *nests* in another as real cups do: the upper cup's foot comes to rest on the lower
//! cup's wall 1.6 cm above its floor, and the taper centres it. The floor is four crossed
//! boxes. The rim (5.6 cm) fits the PiPER's 7 cm gripper with room to spare.
//!
//! **Note**: a 14 × 10 cm card, 2 mm thick (a paper note on a stiff backing: paper itself is
//! too thin for a rigid-body contact), 4 g. Its picture (the note's text) is the study's, drawn
//! on its top face by the environment.

use crate::catalog::model::ObjectKind;
use crate::catalog::spec::{BodyDef, ExplicitInertial, GeomDef, ObjectDef, IDENTITY, ORIGIN, bx};

/// Cup height (m).
pub(crate) const CUP_HEIGHT: f64 = 0.06;
/// Outer radius at the rim and at the foot (m).
pub(crate) const CUP_RIM_RADIUS: f64 = 0.028;
pub(crate) const CUP_FOOT_RADIUS: f64 = 0.0185;
/// Spawn radius: neighbouring cups stand at least 9 cm apart (centre to centre), so the open
/// gripper finds a way down between them. Its fingers reach 5.9 cm out from the grip point along
/// the closing axis and 2.8 cm across it; with a neighbour's 2.8 cm rim, a cup is taken clear
/// of a neighbour D away only with the closing axis turned within ±acos(5.6 cm / D) of square
/// to it. Two neighbours leave a common turn only when each allows more than 90°, i.e. D above
/// 7.9 cm: at 7 cm apart (the rim plus 7 mm) a fifth of the initial states left none.
const CUP_SPAWN_RADIUS: f64 = 0.045;

/// The cup's wall (origin at the centre of its foot, z up) and floor.
const CUP_GEOMS: [GeomDef; 16] = [
    bx([0.02198, 0.00000, 0.03030], [0.996919, -0.000000, 0.078434, 0.000000], [0.00125, 0.00790, 0.03037]),
    bx([0.01904, 0.01099, 0.03030], [0.962950, -0.020300, 0.075762, 0.258022], [0.00125, 0.00790, 0.03037]),
    bx([0.01099, 0.01904, 0.03030], [0.863357, -0.039217, 0.067926, 0.498460], [0.00125, 0.00790, 0.03037]),
    bx([0.00000, 0.02198, 0.03030], [0.704928, -0.055461, 0.055461, 0.704928], [0.00125, 0.00790, 0.03037]),
    bx([-0.01099, 0.01904, 0.03030], [0.498460, -0.067926, 0.039217, 0.863357], [0.00125, 0.00790, 0.03037]),
    bx([-0.01904, 0.01099, 0.03030], [0.258022, -0.075762, 0.020300, 0.962950], [0.00125, 0.00790, 0.03037]),
    bx([-0.02198, 0.00000, 0.03030], [0.000000, -0.078434, 0.000000, 0.996919], [0.00125, 0.00790, 0.03037]),
    bx([-0.01904, -0.01099, 0.03030], [-0.258022, -0.075762, -0.020300, 0.962950], [0.00125, 0.00790, 0.03037]),
    bx([-0.01099, -0.01904, 0.03030], [-0.498460, -0.067926, -0.039217, 0.863357], [0.00125, 0.00790, 0.03037]),
    bx([-0.00000, -0.02198, 0.03030], [-0.704928, -0.055461, -0.055461, 0.704928], [0.00125, 0.00790, 0.03037]),
    bx([0.01099, -0.01904, 0.03030], [-0.863357, -0.039217, -0.067926, 0.498460], [0.00125, 0.00790, 0.03037]),
    bx([0.01904, -0.01099, 0.03030], [-0.962950, -0.020300, -0.075762, 0.258022], [0.00125, 0.00790, 0.03037]),
    bx([0.0, 0.0, 0.00125], [1.0, 0.0, 0.0, 0.0], [0.01478, 0.00621, 0.00125]),
    bx([0.0, 0.0, 0.00125], [0.707107, 0.0, 0.0, 0.707107], [0.01478, 0.00621, 0.00125]),
    bx([0.0, 0.0, 0.00125], [0.92388, 0.0, 0.0, 0.382683], [0.01478, 0.00621, 0.00125]),
    bx([0.0, 0.0, 0.00125], [0.382683, 0.0, 0.0, 0.92388], [0.01478, 0.00621, 0.00125]),
];

const CUP_BODY: [BodyDef; 1] = [BodyDef {
    name: "main",
    parent: None,
    pos: ORIGIN,
    quat: IDENTITY,
    joint: None,
    // A thin shell: the mass sits in the wall, about 2.3 cm out and halfway up.
    inertial: Some(ExplicitInertial { mass: 0.012, com: [0.0, 0.0, 0.028], diag: [9.0e-6, 9.0e-6, 6.5e-6] }),
    geoms: &CUP_GEOMS,
}];

const fn cup(category: &'static str) -> ObjectDef {
    ObjectDef {
        category,
        kind: ObjectKind::Movable,
        bodies: &CUP_BODY,
        sites: &[],
        bottom: [0.0, 0.0, 0.0],
        top: [0.0, 0.0, CUP_HEIGHT],
        // Room for the gripper's fingers beside the rim when cups are set out.
        horizontal_radius: CUP_SPAWN_RADIUS,
    }
}

pub(crate) const RED_PLASTIC_CUP: ObjectDef = cup("red_plastic_cup");
pub(crate) const BLUE_PLASTIC_CUP: ObjectDef = cup("blue_plastic_cup");
pub(crate) const GREEN_PLASTIC_CUP: ObjectDef = cup("green_plastic_cup");

/// Half-size of the note card (m).
pub(crate) const NOTE_HALF: [f64; 3] = [0.07, 0.05, 0.001];

pub(crate) const PAPER_NOTE: ObjectDef = ObjectDef {
    category: "paper_note",
    kind: ObjectKind::Movable,
    bodies: &[BodyDef {
        name: "main",
        parent: None,
        pos: ORIGIN,
        quat: IDENTITY,
        joint: None,
        inertial: Some(ExplicitInertial { mass: 0.004, com: [0.0, 0.0, 0.0], diag: [3.3e-6, 6.5e-6, 9.8e-6] }),
        geoms: &[bx([0.0, 0.0, 0.0], IDENTITY, NOTE_HALF)],
    }],
    sites: &[],
    bottom: [0.0, 0.0, -0.001],
    top: [0.0, 0.0, 0.001],
    horizontal_radius: 0.07,
};
