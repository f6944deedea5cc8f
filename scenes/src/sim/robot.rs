//! The arm of a scene: the Panda of every LIBERO scene, or the PiPER of the §4.4 study. Both
//! take a 7-D action (the Panda's OSC_POSE delta end-effector action, the PiPER's joint-delta
//! action); an all-zero action with gripper −1 holds either arm still with its gripper open, so
//! LIBERO's dummy action settles both.

use vifo_physics::{SimParams, World};
use vifo_robots::action::Action;
use vifo_robots::arm::ArmCollider;
use vifo_robots::dynamics::BodyPoses;
use vifo_robots::model::ArmModel;
use vifo_robots::panda::{GRIPPER_INIT_QPOS, LIBERO_INIT_QPOS, Mount, Panda, PandaControl};
use vifo_robots::piper::{FINGER_STROKE, Piper, PiperControl, READY_QPOS};
use vifo_robots::soft_contact::FixedShape;
use vifo_robots::spatial::Pose;

use crate::scene_class::{ArmKind, SceneClass};

/// A scene's arm.
// One per scene model, shared by its episodes: boxing the Panda would only add an indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum Robot {
    Panda(Panda),
    Piper(Piper),
}

/// The arm controller's per-episode state (snapshots carry it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RobotControl {
    Panda(PandaControl),
    Piper(PiperControl),
}

/// The PiPER's rest configuration in a state vector: [`READY_QPOS`] in the first six arm
/// entries (the seventh, which only the Panda has, stays 0), fingers fully open.
pub const PIPER_INIT_QPOS: [f64; 7] = [READY_QPOS[0], READY_QPOS[1], READY_QPOS[2], READY_QPOS[3], READY_QPOS[4], READY_QPOS[5], 0.0];
pub const PIPER_GRIPPER_INIT_QPOS: [f64; 2] = [FINGER_STROKE, FINGER_STROKE];

fn six(q: &[f64; 7]) -> [f64; 6] {
    std::array::from_fn(|i| q[i])
}

impl Robot {
    /// The physics settings of scenes with this arm.
    pub fn sim_params(arm: ArmKind) -> SimParams {
        match arm {
            ArmKind::Panda => SimParams::LIBERO,
            ArmKind::Piper => vifo_robots::piper::SIM_PARAMS,
        }
    }

    /// The arm whose links touch the `fixed` colliders of `world`'s scene with MuJoCo's soft
    /// contact (the Panda; the PiPER's links keep rapier's).
    pub fn with_fixed(self, world: &World, fixed: &[FixedShape]) -> Robot {
        match self {
            Robot::Panda(panda) => Robot::Panda(panda.with_fixed(world, fixed)),
            piper => piper,
        }
    }

    /// Builds the scene class's arm into `world` at its base, at its rest configuration.
    pub fn insert(world: &mut World, class: &SceneClass) -> Robot {
        let base = Pose::from_wxyz(class.robot_base.pos, class.robot_base.quat_wxyz);
        match class.arm {
            ArmKind::Panda => {
                let mount = if class.robot_on_mount { Mount::Pedestal } else { Mount::Ground };
                let robot = Panda::insert(world, mount, base);
                robot.set_joints(world, &LIBERO_INIT_QPOS, &GRIPPER_INIT_QPOS, &[0.0; 7], &[0.0; 2]);
                Robot::Panda(robot)
            }
            ArmKind::Piper => {
                let robot = Piper::insert(world, base);
                robot.set_state(world, &six(&PIPER_INIT_QPOS), &PIPER_GRIPPER_INIT_QPOS, &[0.0; 6], &[0.0; 2]);
                Robot::Piper(robot)
            }
        }
    }

    /// The rest configuration a state vector starts from (arm 7, fingers 2).
    pub fn init_qpos(&self) -> ([f64; 7], [f64; 2]) {
        match self {
            Robot::Panda(_) => (LIBERO_INIT_QPOS, GRIPPER_INIT_QPOS),
            Robot::Piper(_) => (PIPER_INIT_QPOS, PIPER_GRIPPER_INIT_QPOS),
        }
    }

    pub fn kind(&self) -> ArmKind {
        match self {
            Robot::Panda(_) => ArmKind::Panda,
            Robot::Piper(_) => ArmKind::Piper,
        }
    }

    /// The Panda, where the scene has one.
    pub fn panda(&self) -> Option<&Panda> {
        match self {
            Robot::Panda(p) => Some(p),
            Robot::Piper(_) => None,
        }
    }

    /// The PiPER, where the scene has one.
    pub fn piper(&self) -> Option<&Piper> {
        match self {
            Robot::Piper(p) => Some(p),
            Robot::Panda(_) => None,
        }
    }

    /// Sets a state vector's joints: the Panda's 7 arm joints and 2 fingers, or the PiPER's
    /// first 6 arm entries and its 2 finger slides.
    pub fn set_joints(&self, world: &mut World, arm: &[f64; 7], fingers: &[f64; 2], arm_vel: &[f64; 7], finger_vel: &[f64; 2]) {
        match self {
            Robot::Panda(p) => p.set_joints(world, arm, fingers, arm_vel, finger_vel),
            Robot::Piper(p) => p.set_state(world, &six(arm), fingers, &six(arm_vel), finger_vel),
        }
    }

    /// Arm joint positions as a state vector stores them (the PiPER's seventh is 0) and the
    /// two finger joints.
    pub fn joint_positions(&self, world: &World) -> ([f64; 7], [f64; 2]) {
        self.joint_values(world, false)
    }

    /// The same joints' velocities (robosuite's `joint_vel` and `gripper_qvel`), in the same
    /// layout.
    pub fn joint_velocities(&self, world: &World) -> ([f64; 7], [f64; 2]) {
        self.joint_values(world, true)
    }

    fn joint_values(&self, world: &World, velocity: bool) -> ([f64; 7], [f64; 2]) {
        match self {
            Robot::Panda(p) => {
                let s = p.joints(world);
                let v = if velocity { s.qd } else { s.q };
                (std::array::from_fn(|i| v[i]), [v[7], v[8]])
            }
            Robot::Piper(p) => {
                let s = p.joints(world);
                let v = if velocity { s.qd } else { s.q };
                (std::array::from_fn(|i| if i < 6 { v[i] } else { 0.0 }), [v[6], v[7]])
            }
        }
    }

    /// The controller state an episode starts with after a state is loaded: robosuite's reset
    /// state for the Panda; for the PiPER, holding the loaded configuration.
    pub fn reset_control(&self, world: &World) -> RobotControl {
        match self {
            Robot::Panda(p) => RobotControl::Panda(p.reset_control()),
            Robot::Piper(p) => RobotControl::Piper(p.hold_control(world)),
        }
    }

    /// One 20 Hz control step of a validated action.
    pub fn control_step(&self, world: &mut World, control: &mut RobotControl, action: &Action) {
        match (self, control) {
            (Robot::Panda(p), RobotControl::Panda(c)) => p.control_step(world, c, action),
            (Robot::Piper(p), RobotControl::Piper(c)) => p.joint_step(world, c, action),
            _ => unreachable!("a scene's controller state is made by its own arm"),
        }
    }

    /// World pose of the grip point between the fingertips (the Panda's `grip_site`, the
    /// PiPER's tool point).
    pub fn grip_site_pose(&self, world: &World) -> Pose {
        match self {
            Robot::Panda(p) => p.grip_site_pose(world),
            Robot::Piper(p) => p.tcp_pose(world),
        }
    }

    /// World pose of the hand (robosuite's `robot0_eef_quat` body for the Panda; the PiPER's
    /// tool frame).
    pub fn hand_pose(&self, world: &World) -> Pose {
        match self {
            Robot::Panda(p) => p.hand_pose(world),
            Robot::Piper(p) => p.tcp_pose(world),
        }
    }

    pub fn model(&self) -> &ArmModel {
        match self {
            Robot::Panda(p) => p.arm().model(),
            Robot::Piper(p) => p.arm().model(),
        }
    }

    pub fn colliders(&self) -> &[ArmCollider] {
        match self {
            Robot::Panda(p) => p.arm().colliders(),
            Robot::Piper(p) => p.arm().colliders(),
        }
    }

    pub fn body_poses(&self, world: &World) -> BodyPoses {
        match self {
            Robot::Panda(p) => p.arm().body_poses(world),
            Robot::Piper(p) => p.arm().body_poses(world),
        }
    }

    pub fn base(&self) -> &Pose {
        match self {
            Robot::Panda(p) => p.arm().base(),
            Robot::Piper(p) => p.arm().base(),
        }
    }
}
