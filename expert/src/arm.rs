//! The arm-agnostic interface the skills drive: a grip-site pose target and a gripper command
//! go in, the 7-D action a policy sends comes out, and the arm's state is read back. The Panda
//! implements it; a second arm (the PiPER) plugs in with an implementation of its own and a
//! case in [`of`], and the skills stay as they are.

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
fn down() -> Mat3 {
    Mat3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0)
}

/// Orientation for a yaw of the finger axis.
pub fn orientation(yaw: f64) -> Mat3 {
    axis_angle(&Vec3::z(), yaw) * down()
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
        of(sim).command(target, self, grip)
    }
}

/// What a skill reads of an arm and asks of it.
pub trait Arm {
    /// Where the grip site (between the fingertips) is, and how the gripper is turned: first
    /// column the finger (closing) axis, third the approach axis.
    fn grip_site(&self) -> Pose;
    /// The spread between the two fingers (the difference of their joint positions).
    fn finger_gap(&self) -> f64;
    /// Where the arm stands: the side it reaches an object from.
    fn base(&self) -> Vec3;
    /// The last wrist joint's position once the gripper has turned from where it is to `rot`.
    fn wrist_after(&self, rot: &Mat3) -> f64;
    /// That joint's limit, less a margin for the servo's overshoot.
    fn wrist_limit(&self) -> f64;
    /// The action moving the grip site toward `target` with `servo`'s gains, the gripper
    /// commanded with `grip` (-1 open, 1 close, 0 hold).
    fn command(&self, target: &Waypoint, servo: &Servo, grip: f64) -> Action;

    /// Whether the wrist can turn to `rot` without running into its limit.
    fn wrist_reaches(&self, rot: &Mat3) -> bool {
        self.wrist_after(rot).abs() < self.wrist_limit()
    }
}

/// The arm of the scene (the simulator holds a Panda).
pub fn of(sim: &Sim) -> impl Arm + '_ {
    Panda { sim }
}

/// The Franka Panda under robosuite's OSC_POSE controller, as LIBERO drives it.
struct Panda<'a> {
    sim: &'a Sim,
}

/// Joint 7's limit (±2.8973 rad) less a margin for the servo's overshoot.
const PANDA_WRIST_LIMIT: f64 = 2.75;

impl Arm for Panda<'_> {
    fn grip_site(&self) -> Pose {
        self.sim.model().robot.grip_site_pose(self.sim.world())
    }

    fn finger_gap(&self) -> f64 {
        let q = self.sim.model().robot.joints(self.sim.world()).q;
        q[7] - q[8]
    }

    fn base(&self) -> Vec3 {
        self.sim.model().robot.arm().base().pos
    }

    /// The turn about the approach axis is joint 7's own.
    fn wrist_after(&self, rot: &Mat3) -> f64 {
        let ee = self.grip_site();
        let q7 = self.sim.model().robot.joints(self.sim.world()).q[6];
        q7 + rotation_vector(&(rot * ee.rot.transpose())).dot(&(ee.rot * Vec3::z()))
    }

    fn wrist_limit(&self) -> f64 {
        PANDA_WRIST_LIMIT
    }

    /// A delta action: position and orientation errors times the gains. Each axis is limited on
    /// its own, as LIBERO clips actions: a diagonal move runs up to √2 faster than a straight
    /// one, bending the path toward the diagonal early on.
    fn command(&self, target: &Waypoint, servo: &Servo, grip: f64) -> Action {
        let ee = self.grip_site();
        let dp = (target.pos - ee.pos) * servo.pos_gain;
        let err = rotation_vector(&(target.rot * ee.rot.transpose())) * servo.rot_gain;
        let t = |v: f64| v.clamp(-servo.max_speed, servo.max_speed);
        let r = |v: f64| v.clamp(-1.0, 1.0);
        Action([t(dp.x), t(dp.y), t(dp.z), r(err.x), r(err.y), r(err.z), grip])
    }
}
