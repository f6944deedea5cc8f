//! Gripper poses (where the grip site goes and how the gripper is turned) and the servo gains
//! that move it there.

use vifo_robots::action::Action;
use vifo_robots::spatial::{Mat3, Pose, Vec3, axis_angle, rotation_vector};
use vifo_scenes::sim::Sim;

use crate::arm::{self, Arm};

/// A gripper pose the expert wants: grip-site position and orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    pub pos: Vec3,
    pub rot: Mat3,
}

impl Waypoint {
    /// Gripper pointing down with the finger axis at `yaw` about world z (0 = fingers along world
    /// y, LIBERO's reset orientation).
    pub fn down(pos: Vec3, yaw: f64) -> Self {
        Waypoint { pos, rot: orientation(yaw) }
    }
}

/// The gripper pointing straight down with its fingers along world y (LIBERO's reset pose).
pub fn down() -> Mat3 {
    Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)
}

/// Orientation for a yaw of the finger axis.
pub fn orientation(yaw: f64) -> Mat3 {
    axis_angle(&Vec3::z(), yaw) * down()
}

/// Yaw of the current finger axis.
pub fn current_yaw(ee: &Pose) -> f64 {
    let finger = ee.rot * Vec3::x();
    libm::atan2(-finger.x, finger.y)
}

/// The yaw equivalent to `yaw` (the gripper is symmetric under a half turn) closest to `near`.
pub fn nearest_yaw(yaw: f64, near: f64) -> f64 {
    let pi = std::f64::consts::PI;
    let mut y = yaw;
    while y - near > pi / 2.0 {
        y -= pi;
    }
    while near - y > pi / 2.0 {
        y += pi;
    }
    y
}

/// The yaw equivalent to `yaw` (a half turn apart, the gripper being symmetric) that the wrist
/// reaches, nearest the current one first.
pub fn reachable_yaw(sim: &Sim, yaw: f64) -> f64 {
    let arm = arm::of(sim);
    let now = current_yaw(&arm.grip_site());
    let near = nearest_yaw(yaw, now);
    let pi = std::f64::consts::PI;
    let far = if near > now { near - pi } else { near + pi };
    [near, far].into_iter().find(|y| arm.wrist_reaches(&orientation(*y))).unwrap_or(near)
}

/// Gains of the pose servo.
#[derive(Clone, Copy, Debug)]
pub struct Servo {
    /// Action per metre of position error (an action of 1 asks the OSC for 5 cm).
    pub pos_gain: f64,
    /// Largest translation action per axis.
    pub max_speed: f64,
    /// Action per radian of orientation error.
    pub rot_gain: f64,
}

impl Servo {
    pub const TRAVEL: Servo = Servo { pos_gain: 40.0, max_speed: 1.0, rot_gain: 3.0 };
    pub const FINE: Servo = Servo { pos_gain: 60.0, max_speed: 0.5, rot_gain: 3.0 };

    /// Full speed while more than a few centimetres away, fine near the target: the OSC covers
    /// only about a third of each step's commanded motion, so a fine servo all the way down
    /// costs many steps.
    pub fn closing_in(distance: f64) -> Servo {
        if distance > 0.04 { Servo::TRAVEL } else { Servo::FINE }
    }

    /// The action moving the gripper toward `target` with the gripper command `grip`.
    pub fn act(&self, sim: &Sim, target: &Waypoint, grip: f64) -> Action {
        arm::of(sim).command(target, self, grip)
    }
}

/// Position error (m) and orientation error (rad) between the gripper and a waypoint.
pub fn error(sim: &Sim, target: &Waypoint) -> (f64, f64) {
    let ee = arm::of(sim).grip_site();
    let rot = rotation_vector(&(target.rot * ee.rot.transpose())).norm();
    ((target.pos - ee.pos).norm(), rot)
}
