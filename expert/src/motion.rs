//! Turning a desired gripper pose into the 7-D delta action a policy would send.

use vifo_robots::action::Action;
use vifo_robots::spatial::{Mat3, Pose, Vec3, axis_angle, rotation_vector};

use vifo_scenes::sim::Sim;

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

/// Panda joint 7's limit (±2.8973 rad) less a margin for the servo's overshoot.
const WRIST_LIMIT: f64 = 2.75;

/// Joint 7 once the gripper has turned from where it is to `rot`: the turn about the approach
/// axis is joint 7's own.
pub fn wrist_after(sim: &Sim, rot: &Mat3) -> f64 {
    let ee = sim.model().robot.grip_site_pose(sim.world());
    let q7 = sim.model().robot.joints(sim.world()).q[6];
    q7 + rotation_vector(&(rot * ee.rot.transpose())).dot(&(ee.rot * Vec3::z()))
}

/// Whether the wrist can turn to `rot` without running into its limit.
pub fn wrist_reaches(sim: &Sim, rot: &Mat3) -> bool {
    wrist_after(sim, rot).abs() < WRIST_LIMIT
}

/// The yaw equivalent to `yaw` (a half turn apart, the gripper being symmetric) that the wrist
/// reaches, nearest the current one first.
pub fn reachable_yaw(sim: &Sim, yaw: f64) -> f64 {
    let now = current_yaw(&sim.model().robot.grip_site_pose(sim.world()));
    let near = nearest_yaw(yaw, now);
    let pi = std::f64::consts::PI;
    let far = if near > now { near - pi } else { near + pi };
    [near, far].into_iter().find(|y| wrist_reaches(sim, &orientation(*y))).unwrap_or(near)
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
        let ee = sim.model().robot.grip_site_pose(sim.world());
        let dp = (target.pos - ee.pos) * self.pos_gain;
        let err = rotation_vector(&(target.rot * ee.rot.transpose())) * self.rot_gain;
        // Each axis is limited on its own, as LIBERO clips actions: a diagonal move runs up to
        // √2 faster than a straight one, bending the path toward the diagonal early on.
        let t = |v: f64| v.clamp(-self.max_speed, self.max_speed);
        let r = |v: f64| v.clamp(-1.0, 1.0);
        Action([t(dp.x), t(dp.y), t(dp.z), r(err.x), r(err.y), r(err.z), grip])
    }
}

/// Position error (m) and orientation error (rad) between the gripper and a waypoint.
pub fn error(sim: &Sim, target: &Waypoint) -> (f64, f64) {
    let ee = sim.model().robot.grip_site_pose(sim.world());
    let rot = rotation_vector(&(target.rot * ee.rot.transpose())).norm();
    ((target.pos - ee.pos).norm(), rot)
}
