//! What every skill shares: the step protocol, gripper commands and scene-height queries.

use vifo_robots::action::Action;
use vifo_robots::spatial::Vec3;

use crate::geometry;
use vifo_scenes::sim::Sim;

/// Gripper commands.
pub const OPEN: f64 = -1.0;
pub const CLOSE: f64 = 1.0;

/// The gripper command that brings the fingers to `half_gap` (finger joint position): open or
/// close toward it, and hold the gripper's ramp (command 0) once there.
pub fn gripper_toward(sim: &Sim, half_gap: f64) -> f64 {
    let q = sim.model().robot.joints(sim.world()).q;
    let opening = 0.5 * (q[7] - q[8]);
    if opening < half_gap - 0.002 {
        OPEN
    } else if opening > half_gap + 0.002 {
        CLOSE
    } else {
        0.0
    }
}

/// What a skill reports each step.
pub enum Step {
    Act(Action),
    Done,
    /// The skill cannot succeed from here (e.g. lost the object); the planner may retry.
    Failed(&'static str),
}

/// Highest point of the scene (objects, fixtures, arena) over a horizontal disc, excluding one
/// entity (the one being carried).
pub fn surface_height(sim: &Sim, centre: [f64; 2], radius: f64, exclude: Option<usize>) -> f64 {
    let mut z = sim.model().class.support_z();
    for (i, e) in sim.model().entities.iter().enumerate() {
        if Some(i) == exclude {
            continue;
        }
        for b in 0..e.model.bodies.len() {
            for p in geometry::corners(sim, i, b) {
                let d = ((p.x - centre[0]).powi(2) + (p.y - centre[1]).powi(2)).sqrt();
                if d < radius {
                    z = z.max(p.z);
                }
            }
        }
    }
    z
}

/// Height at which the hand crosses from where it is to `to`: `clearance` over everything
/// within the hand's half length of the straight way there (but `exclude`), and no lower than
/// `floor`.
pub fn cruise_height(sim: &Sim, to: &Vec3, clearance: f64, floor: f64, exclude: Option<usize>) -> f64 {
    let ee = sim.model().robot.grip_site_pose(sim.world()).pos;
    (path_height(sim, [ee.x, ee.y], [to.x, to.y], 0.1, exclude) + clearance).max(floor)
}

/// The first leg of a crossing: straight up from `ee` to `cruise_z`; `None` once within 2 cm
/// of it (the crossing itself may start there).
pub fn climb(ee: &Vec3, cruise_z: f64) -> Option<Vec3> {
    (ee.z < cruise_z - 0.02).then(|| Vec3::new(ee.x, ee.y, cruise_z))
}

/// Highest point of the scene along a straight horizontal path (within `radius` of it).
pub fn path_height(sim: &Sim, from: [f64; 2], to: [f64; 2], radius: f64, exclude: Option<usize>) -> f64 {
    (0..=10)
        .map(|k| {
            let t = k as f64 / 10.0;
            surface_height(sim, [from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])], radius, exclude)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

