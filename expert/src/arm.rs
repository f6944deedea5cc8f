//! The arm-agnostic interface the skills drive: a grip-site pose target and a gripper command
//! go in, the 7-D action a policy sends comes out, and the arm's state is read back. The Panda
//! implements it, and so does the PiPER of the §4.4 study (its own IK turns the pose target
//! into the joint-delta action it takes); [`of`] gives the scene's arm, and the skills stay
//! as they are.

use vifo_robots::action::Action;
use vifo_robots::osc::OscGoal;
use vifo_robots::spatial::{Mat3, Pose, Vec3, axis_angle, rotation_from_axis_angle_vector, rotation_vector};
use vifo_scenes::sim::{Robot, RobotControl, Sim};

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

/// The arm of the scene.
pub fn of(sim: &Sim) -> Box<dyn Arm + '_> {
    match (&sim.model().robot, sim.control()) {
        (Robot::Piper(piper), RobotControl::Piper(control)) => Box::new(Piper { sim, piper, control }),
        _ => Box::new(Panda { sim }),
    }
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
        let (_, fingers) = self.sim.model().robot.joint_positions(self.sim.world());
        fingers[0] - fingers[1]
    }

    fn base(&self) -> Vec3 {
        self.sim.model().robot.base().pos
    }

    /// The turn about the approach axis is joint 7's own.
    fn wrist_after(&self, rot: &Mat3) -> f64 {
        let ee = self.grip_site();
        let q7 = self.sim.model().robot.joint_positions(self.sim.world()).0[6];
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
        Action::clipped([t(dp.x), t(dp.y), t(dp.z), r(err.x), r(err.y), r(err.z), grip])
    }
}

/// The AgileX PiPER under its joint servos (§4.4 study).
struct Piper<'a> {
    sim: &'a Sim,
    piper: &'a vifo_robots::piper::Piper,
    control: &'a vifo_robots::piper::PiperControl,
}

/// Joint 6's limit (±2.0944 rad) less a margin for the servo's overshoot.
const PIPER_WRIST_LIMIT: f64 = 1.95;
/// How far one step moves the commanded pose at full speed (`Servo::max_speed` 1): 0.2 m/s.
/// Twice that, a cup held in the pinch swings after every stop (11 of 20 states stacked
/// against 16).
const PIPER_STEP: f64 = 0.01;
/// The largest turn of the commanded pose in one step (rad).
const PIPER_TURN: f64 = 0.1;
/// How far the commanded pose may run ahead of the measured one (m, rad): the servos lag a few
/// steps behind a moving target, more is a blocked arm, which must not wind up.
const PIPER_AHEAD: f64 = 0.03;
const PIPER_AHEAD_TURN: f64 = 0.15;

impl Arm for Piper<'_> {
    fn grip_site(&self) -> Pose {
        self.piper.tcp_pose(self.sim.world())
    }

    /// The fingers slide apart symmetrically, each from 0 to 0.035 m.
    fn finger_gap(&self) -> f64 {
        let q = self.piper.joints(self.sim.world()).q;
        q[6] + q[7]
    }

    fn base(&self) -> Vec3 {
        self.piper.arm().base().pos
    }

    /// The turn about the approach axis is joint 6's, whose axis is the flange's −z.
    fn wrist_after(&self, rot: &Mat3) -> f64 {
        let ee = self.grip_site();
        let q6 = self.piper.joints(self.sim.world()).q[5];
        q6 - rotation_vector(&(rot * ee.rot.transpose())).dot(&(ee.rot * Vec3::z()))
    }

    fn wrist_limit(&self) -> f64 {
        PIPER_WRIST_LIMIT
    }

    /// Moves the commanded pose (where the joint targets put the tool) toward `target`, at most
    /// `max_speed` × 1 cm and 0.1 rad a step, turns it into joint targets with the PiPER's IK
    /// and sends the joint-delta action from the current targets. The path is laid out from
    /// the commanded pose, not the measured one: the soft wrist servos lag the targets by a few
    /// steps, and a path re-anchored each step on where the lagging tool is carries that lag
    /// along as drift (centimetres sideways over a lift). The commanded pose is kept within
    /// 3 cm and 0.15 rad of the measured one, so a blocked arm does not wind up.
    fn command(&self, target: &Waypoint, servo: &Servo, grip: f64) -> Action {
        let ee = self.grip_site();
        let commanded = self.piper.tcp_at_joints(&self.control.joint_targets);
        let ahead = commanded.pos - ee.pos;
        let from = if ahead.norm() > PIPER_AHEAD { ee.pos + ahead * (PIPER_AHEAD / ahead.norm()) } else { commanded.pos };
        let lag = rotation_vector(&(commanded.rot * ee.rot.transpose()));
        let from_rot = if lag.norm() > PIPER_AHEAD_TURN { rotation_from_axis_angle_vector(&(lag * (PIPER_AHEAD_TURN / lag.norm()))) * ee.rot } else { commanded.rot };
        let lead = servo.max_speed * PIPER_STEP;
        let dp = (target.pos - from).map(|v| v.clamp(-lead, lead));
        let turn = rotation_vector(&(target.rot * from_rot.transpose()));
        let turn = if turn.norm() > PIPER_TURN { turn * (PIPER_TURN / turn.norm()) } else { turn };
        let goal = OscGoal::new(from + dp, rotation_from_axis_angle_vector(&turn) * from_rot);
        let q = self.piper.solve_ik(&self.control.joint_targets, &goal);
        let d = |i: usize| (q[i] - self.control.joint_targets[i]).clamp(-1.0, 1.0);
        Action::clipped([d(0), d(1), d(2), d(3), d(4), d(5), grip])
    }
}
