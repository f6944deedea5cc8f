//! Turning the gripper (finger yaws the wrist reaches) and how far it is from a pose target.
//! The targets themselves and the servo's gains are the arm interface's (re-exported here).

use vifo_robots::spatial::{Pose, Vec3, rotation_vector};
use vifo_scenes::sim::Sim;

pub use crate::arm::{Servo, Waypoint, orientation};
use crate::arm;

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

/// Position error (m) and orientation error (rad) between the gripper and a waypoint.
pub fn error(sim: &Sim, target: &Waypoint) -> (f64, f64) {
    let ee = arm::of(sim).grip_site();
    let rot = rotation_vector(&(target.rot * ee.rot.transpose())).norm();
    ((target.pos - ee.pos).norm(), rot)
}
