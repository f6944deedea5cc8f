//! The AgileX PiPER: a 6-dof arm with a two-finger parallel gripper.
//!
//! Kinematics and inertials follow AgileX's own URDF (`piper_description`), so joint angles use
//! **AgileX's URDF/SDK joint-zero convention** (the one the real robot and its SDK report), not
//! MuJoCo Menagerie's (which flips joints 4 and 6 and drops joint 5's 5° offset). Joint limits are
//! the SDK defaults, the gripper stroke is the SDK's 0–0.07 m total opening. The URDF masses are
//! CAD exports that omit the motors, so, as Menagerie does, gravity is compensated exactly by the
//! controller (our own inverse dynamics), and the servo gains are Menagerie's.
//!
//! Three ways to drive it: joint-position targets; the 7-D **joint-delta action** a policy sends
//! in a LIBERO-VIFO scene (`[dq1, .., dq6, gripper]`, see [`Piper::command_joint_delta`]); or the
//! same 7-D delta end-effector action as the Panda (`[dx, dy, dz, dax, day, daz, gripper]`,
//! 0.05 m / 0.5 rad per unit, world frame), turned into joint targets by damped least-squares
//! inverse kinematics.

use std::sync::Arc;

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};
use thiserror::Error;
use vifo_physics::{SimParams, World};

use crate::action::Action;
use crate::arm::{ArmInstance, JointState};
use crate::model::{ArmModel, Body, Collider, ContactRole, ContactShape, Inertial, JointKind, JointSpec, Shape, Site, Visual};
use crate::osc::{OscGoal, OscParams, orientation_error};
use crate::spatial::{Coords, Pose, Vec3};

/// Joint limits of the SDK (rad), AgileX convention.
pub const JOINT_LIMITS: [[f64; 2]; 6] =
    [[-2.618, 2.618], [0.0, 3.14], [-2.967, 0.0], [-1.745, 1.745], [-1.22, 1.22], [-2.0944, 2.0944]];
/// Travel of each finger (m); the SDK's total opening is twice this.
pub const FINGER_STROKE: f64 = 0.035;
/// A ready pose: gripper pointing straight down 0.24 m in front of the base, 8 cm above it.
/// (With the SDK's ±1.22 rad wrist pitch the PiPER can only point straight down fairly low.)
pub const READY_QPOS: [f64; 6] = [0.0, 1.4, -1.0, 0.0, 1.1, 0.0];
/// How far the delta controller's goal may run ahead of the tool (m).
pub const GOAL_LEASH: f64 = 0.1;
/// Growth of the servos' integral term per second, as a multiple of kp × error (1/s).
pub const INTEGRAL_RATE: f64 = 5.0;
/// The largest integral torque (N·m): enough to overcome the joints' 0.3 N·m of dry friction.
pub const INTEGRAL_LIMIT: f64 = 0.6;
/// How far a joint target may run ahead of its joint (rad), so a blocked arm cannot wind up.
pub const JOINT_LEASH: f64 = 0.2;
/// The tool point: midway along the fingertip pads, 0.18 m from the flange (link6).
pub const TCP: &str = "tcp";
/// The physics of PiPER scenes: LIBERO's timing with two solver substeps, rapier's 1 m length
/// unit, its 20 mm prediction distance and its 0.5 s sleep delay, the solver settings its
/// gripper servo and the expert's cup stacking were tuned with. The Panda's settings (one
/// substep, see [`SimParams::solver_iterations`]) stack 38 of 50 initial states instead of 48.
pub const SIM_PARAMS: SimParams = SimParams {
    solver_iterations: 2,
    pgs_iterations: 1,
    stabilization_iterations: 2,
    length_unit: 1.0,
    prediction_distance: 0.02,
    sleep_after: 0.5,
    ..SimParams::LIBERO
};

/// Servo gains (MuJoCo Menagerie's PiPER actuators).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoGains {
    pub kp: [f64; 6],
    pub kv: [f64; 6],
    pub torque_limit: f64,
    pub finger_kp: f64,
    pub finger_kv: f64,
    pub finger_force_limit: f64,
}

impl ServoGains {
    pub const MENAGERIE: ServoGains = ServoGains {
        kp: [80.0, 80.0, 80.0, 40.0, 10.0, 10.0],
        kv: [5.0, 5.0, 5.0, 5.0, 1.5, 1.5],
        torque_limit: 100.0,
        finger_kp: 40.0,
        finger_kv: 5.0,
        finger_force_limit: 10.0,
    };
}

/// A joint command the arm cannot take.
#[derive(Debug, Error, PartialEq)]
pub enum JointCommandError {
    #[error("joint target {index} is {value}; targets must be finite")]
    NotFinite { index: usize, value: f64 },
    #[error("gripper opening {0} m is outside 0..={max} m", max = 2.0 * FINGER_STROKE)]
    Opening(f64),
}

const RED: [f32; 4] = [0.75, 0.1, 0.1, 1.0];
const GREY: [f32; 4] = [0.55, 0.55, 0.57, 1.0];
const DARK: [f32; 4] = [0.15, 0.15, 0.17, 1.0];

fn hinge(name: &'static str, axis: Vec3, range: [f64; 2]) -> JointSpec {
    JointSpec { name, kind: JointKind::Hinge, axis, range, damping: 0.0, armature: 0.005, frictionloss: 0.3, soft: None }
}

fn capsule(radius: f64, from: [f64; 3], to: [f64; 3], rgba: [f32; 4]) -> (Collider, Visual) {
    let (a, b) = (Vec3::from(from), Vec3::from(to));
    let rot = nalgebra::UnitQuaternion::rotation_between(&Vec3::z(), &(b - a).normalize())
        .unwrap_or_else(nalgebra::UnitQuaternion::identity)
        .to_rotation_matrix()
        .into_inner();
    let shape = Shape::Capsule { radius, half_height: (b - a).norm() / 2.0 };
    let local = Pose::new((a + b) / 2.0, rot);
    (Collider { name: "link", shape: ContactShape::Primitive(shape), local, friction: 1.0, role: ContactRole::Link }, Visual { shape, local, rgba })
}

fn link(name: &'static str, parent: usize, origin: Pose, joint: JointSpec, inertial: Inertial, shapes: Vec<(Collider, Visual)>) -> Body {
    let (colliders, visuals) = shapes.into_iter().unzip();
    Body { name, parent: Some(parent), local: origin, joint: Some(joint), inertial, colliders, self_hull: None, visuals }
}

/// One finger on the flange: slides along `side`·x of link6, fingers 0.07 m long from the
/// finger base (0.135 m beyond the flange), with a thin pad on the inner face.
fn finger(name: &'static str, joint: &'static str, side: f64) -> Body {
    let half = [0.0122, 0.028, 0.035];
    let (shell_shape, pad_shape) = (Shape::Box { half }, Shape::Box { half: [0.0025, 0.015, 0.03] });
    let shell = Collider {
        name: "finger",
        shape: ContactShape::Primitive(shell_shape),
        local: Pose::from_wxyz([side * half[0], 0.0, half[2]], [1.0, 0.0, 0.0, 0.0]),
        friction: 1.0,
        role: ContactRole::Finger,
    };
    let pad = Collider {
        name: "finger_pad",
        shape: ContactShape::Primitive(pad_shape),
        local: Pose::from_wxyz([side * 0.002, 0.0, 0.04], [1.0, 0.0, 0.0, 0.0]),
        friction: 1.0,
        role: ContactRole::Pad,
    };
    let visuals = vec![
        Visual { shape: shell_shape, local: shell.local, rgba: DARK },
        Visual { shape: pad_shape, local: pad.local, rgba: GREY },
    ];
    Body {
        name,
        parent: Some(6),
        local: Pose::from_wxyz([0.0, 0.0, 0.13503], [1.0, 0.0, 0.0, 0.0]),
        joint: Some(JointSpec {
            name: joint,
            kind: JointKind::Slide,
            axis: Vec3::new(side, 0.0, 0.0),
            range: [0.0, FINGER_STROKE],
            damping: 0.0,
            armature: 0.005,
            frictionloss: 0.0,
            soft: None,
        }),
        inertial: Inertial::full(0.026482, [side * 0.00921, 0.000278, 0.046767], [9.998e-6, 6.180e-6, 1.4210e-5, 0.0, 0.0, 0.0]),
        colliders: vec![shell, pad],
        self_hull: None,
        visuals,
    }
}

/// The PiPER arm with its gripper (8 degrees of freedom: 6 joints, 2 fingers).
pub fn model() -> Arc<ArmModel> {
    let base = vec![capsule(0.045, [-0.01, 0.0, 0.0], [-0.01, 0.0, 0.08], GREY)];
    let (bc, bv) = base.into_iter().unzip();
    let z = Vec3::z();
    let mut bodies = vec![Body {
        name: "base_link",
        parent: None,
        local: Pose::IDENTITY,
        joint: None,
        inertial: Inertial::diag(0.0, [0.0; 3], [0.0; 3]),
        colliders: bc,
        self_hull: None,
        visuals: bv,
    }];
    bodies.push(link("link1", 0, Pose::from_urdf([0.0, 0.0, 0.123], [0.0, 0.0, -1.5708]), hinge("joint1", z, JOINT_LIMITS[0]),
        Inertial::full(0.097868, [0.001317, 0.000310, -0.009229], [7.767e-5, 9.250e-5, 8.246e-5, 1.09e-7, -1.97e-6, 9.91e-7]),
        vec![capsule(0.038, [0.0, 0.0, -0.04], [0.0, 0.0, 0.025], GREY)]));
    bodies.push(link("link2", 1, Pose::from_urdf([0.0; 3], [1.5708, -0.10095, -1.5708]), hinge("joint2", z, JOINT_LIMITS[1]),
        Inertial::full(0.289571, [0.147616, -0.017426, 0.001760], [1.501e-4, 1.7259e-3, 1.7745e-3, 8.59e-5, -1.07e-6, -9.94e-7]),
        vec![capsule(0.032, [0.0, 0.0, 0.0], [0.285, 0.0, 0.0], RED)]));
    bodies.push(link("link3", 2, Pose::from_urdf([0.28503, 0.0, 0.0], [0.0, 0.0, 1.3826]), hinge("joint3", z, JOINT_LIMITS[2]),
        Inertial::full(0.290583, [0.015673, 0.104467, 0.000508], [2.217e-4, 1.009e-4, 2.418e-4, -7.57e-6, -6.37e-7, -8.16e-7]),
        vec![capsule(0.03, [0.0, 0.0, 0.0], [0.021984, 0.21, 0.0], GREY)]));
    bodies.push(link("link4", 3, Pose::from_urdf([0.021984, 0.25075, 0.0], [-1.5708, 0.0, 0.0]), hinge("joint4", -z, JOINT_LIMITS[3]),
        Inertial::full(0.127087, [0.000276, -0.001028, -0.004728], [3.820e-5, 4.871e-5, 4.106e-5, -4.9e-8, 4.9e-8, 6.7e-8]),
        vec![capsule(0.03, [0.0, 0.0, -0.03], [0.0, 0.0, 0.02], GREY)]));
    bodies.push(link("link5", 4, Pose::from_urdf([0.0; 3], [1.5708, -0.087266, 0.0]), hinge("joint5", z, JOINT_LIMITS[4]),
        Inertial::full(0.144711, [0.000088, 0.056683, -0.001961], [4.396e-5, 5.632e-5, 4.887e-5, -3.6e-8, -1.9e-8, -2.15e-7]),
        vec![capsule(0.028, [0.0, 0.0, 0.0], [0.0, 0.08, 0.0], GREY)]));
    bodies.push(link("link6", 5, Pose::from_urdf([0.0, 0.091, 0.0014165], [-1.5708, -1.5708, 0.0]), hinge("joint6", -z, JOINT_LIMITS[5]),
        Inertial::full(0.150196, [0.0, 0.000341, 0.034212], [4.318e-5, 9.998e-5, 1.1828e-4, -2.2e-8, 0.0, 1.10e-7]),
        vec![capsule(0.035, [0.0, 0.0, 0.005], [0.0, 0.0, 0.06], DARK)]));
    bodies.push(finger("finger_a", "joint7", -1.0));
    bodies.push(finger("finger_b", "joint8", 1.0));
    let dofs = (0..bodies.len()).filter(|&i| bodies[i].joint.is_some()).collect();
    let sites = vec![Site { name: TCP, body: 6, local: Pose::from_wxyz([0.0, 0.0, 0.18], [1.0, 0.0, 0.0, 0.0]) }];
    Arc::new(ArmModel { name: "piper", bodies, dofs, arm_dofs: 6, sites, self_contact: false }.validated())
}

/// The controller's per-episode state: joint and gripper targets, and the pose goal of the
/// delta end-effector mode (kept between actions, like the Panda's OSC goal).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PiperControl {
    pub joint_targets: [f64; 6],
    /// Total gripper opening target (m), 0 closed to 0.07 open.
    pub opening: f64,
    pub goal: OscGoal,
    /// The servos' integral terms (N·m), see [`Piper::apply`].
    #[serde(default)]
    pub integral: [f64; 6],
}

impl PiperControl {
    /// The gripper opening a gripper command asks for: −1 fully open (0.07 m), +1 closed,
    /// linear in between (the Panda's convention, so "hold still, gripper open" is the same
    /// action for both arms).
    pub fn opening_for(gripper: f64) -> f64 {
        2.0 * FINGER_STROKE * (1.0 - gripper.clamp(-1.0, 1.0)) / 2.0
    }
}

/// The PiPER in a world.
#[derive(Clone, Debug)]
pub struct Piper {
    arm: ArmInstance<8>,
    gains: ServoGains,
    tcp: Site,
}

impl Piper {
    pub fn insert(world: &mut World, base: Pose) -> Self {
        let model = model();
        let tcp = model.site(TCP).expect("tcp site").clone();
        Piper { arm: ArmInstance::insert(world, model, base), gains: ServoGains::MENAGERIE, tcp }
    }

    pub fn arm(&self) -> &ArmInstance<8> {
        &self.arm
    }

    fn coords(arm: &[f64; 6], opening: f64) -> Coords<8> {
        let mut q = Coords::<8>::zeros();
        q.fixed_rows_mut::<6>(0).copy_from_slice(arm);
        q[6] = opening / 2.0;
        q[7] = opening / 2.0;
        q
    }

    /// Puts the arm at `q` with the gripper at `opening`, at rest.
    pub fn set_joints(&self, world: &mut World, q: &[f64; 6], opening: f64) {
        self.arm.set_state(world, &JointState { q: Self::coords(q, opening), qd: Coords::zeros() });
    }

    pub fn tcp_pose(&self, world: &World) -> Pose {
        self.tcp_at(&self.arm.state(world).q)
    }

    fn tcp_at(&self, q: &Coords<8>) -> Pose {
        let d = self.arm.dynamics();
        d.frame_pose(&d.forward(self.arm.base(), q), self.tcp.body, &self.tcp.local)
    }

    /// Holds the current configuration.
    pub fn hold_control(&self, world: &World) -> PiperControl {
        let q = self.arm.state(world).q;
        let tcp = self.tcp_at(&q);
        PiperControl { joint_targets: std::array::from_fn(|i| q[i]), opening: q[6] + q[7], goal: OscGoal::new(tcp.pos, tcp.rot), integral: [0.0; 6] }
    }

    /// Puts the arm at `q` and the fingers at `fingers` (each finger's slide, 0..0.035 m) with
    /// the given velocities.
    pub fn set_state(&self, world: &mut World, q: &[f64; 6], fingers: &[f64; 2], qd: &[f64; 6], finger_vel: &[f64; 2]) {
        let mut state = JointState { q: Self::coords(q, 0.0), qd: Self::coords(qd, 0.0) };
        state.q[6] = fingers[0];
        state.q[7] = fingers[1];
        state.qd[6] = finger_vel[0];
        state.qd[7] = finger_vel[1];
        self.arm.set_state(world, &state);
    }

    /// Arm joint positions (6) and finger slides (2).
    pub fn joints(&self, world: &World) -> JointState<8> {
        self.arm.state(world)
    }

    /// Applies a joint-delta action: each of the first six values (rad, the action already
    /// clipped to ±1) moves that joint's target, which accumulates on the previous target (not
    /// the measured joint, whose servo lag would otherwise walk a holding arm away) and is kept
    /// within [`JOINT_LEASH`] of the joint and inside the limits; the seventh is the gripper
    /// command ([`PiperControl::opening_for`]). An all-zero delta holds the arm where it was told.
    pub fn command_joint_delta(&self, world: &World, control: &mut PiperControl, action: &Action) {
        let q = self.arm.state(world).q;
        for i in 0..6 {
            let target = control.joint_targets[i] + action.values()[i];
            let [low, high] = JOINT_LIMITS[i];
            control.joint_targets[i] = target.clamp(q[i] - JOINT_LEASH, q[i] + JOINT_LEASH).clamp(low, high);
        }
        control.opening = PiperControl::opening_for(action.gripper());
    }

    /// One control step (the world's substeps) of a joint-delta action.
    pub fn joint_step(&self, world: &mut World, control: &mut PiperControl, action: &Action) {
        self.command_joint_delta(world, control, action);
        for _ in 0..world.params().substeps {
            self.apply(world, control);
            world.step();
        }
    }

    /// Sets joint-position targets (clamped to the joint limits) and the gripper opening.
    pub fn command_joints(&self, control: &mut PiperControl, q: &[f64; 6], opening: f64) -> Result<(), JointCommandError> {
        if let Some((index, &value)) = q.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(JointCommandError::NotFinite { index, value });
        }
        if !(0.0..=2.0 * FINGER_STROKE).contains(&opening) {
            return Err(JointCommandError::Opening(opening));
        }
        control.joint_targets = std::array::from_fn(|i| q[i].clamp(JOINT_LIMITS[i][0], JOINT_LIMITS[i][1]));
        control.opening = opening;
        Ok(())
    }

    /// Turns a 7-D delta action into joint targets. The scaling and frames are the Panda's
    /// (0.05 m / 0.5 rad per unit, world frame), but the deltas accumulate on the previous goal
    /// rather than on the measured pose: joint servos keep a steady-state error against dry
    /// friction, and re-anchoring on the measured pose would let that error walk the arm away
    /// while the policy asks it to hold. The goal is kept within [`GOAL_LEASH`] of the tool so it
    /// cannot wind up when blocked. Gripper −1 opens fully, +1 closes.
    pub fn command_delta(&self, world: &World, control: &mut PiperControl, action: &Action) {
        let tcp = self.tcp_pose(world);
        let p = OscParams::ROBOSUITE;
        let mut pos = control.goal.pos() + Vec3::from(action.translation()) * p.max_translation;
        let offset = pos - tcp.pos;
        if offset.norm() > GOAL_LEASH {
            pos = tcp.pos + offset * (GOAL_LEASH / offset.norm());
        }
        let rotation = Vec3::from(action.rotation()) * p.max_rotation;
        let ori = crate::spatial::rotation_from_axis_angle_vector(&rotation) * control.goal.ori();
        control.goal = OscGoal::new(pos, ori);
        let seed = Self::coords(&control.joint_targets, control.opening);
        control.joint_targets = self.inverse_kinematics(&seed, &control.goal);
        control.opening = PiperControl::opening_for(action.gripper());
    }

    /// Joint targets that put the tool at `goal`, searched from `seed` (damped least squares,
    /// clamped to the joint limits); where the goal is out of reach, the nearest pose found.
    pub fn solve_ik(&self, seed: &[f64; 6], goal: &OscGoal) -> [f64; 6] {
        self.inverse_kinematics(&Self::coords(seed, 0.0), goal)
    }

    /// The tool pose at arm joints `q` (fingers closed: they do not move the tool point).
    pub fn tcp_at_joints(&self, q: &[f64; 6]) -> Pose {
        self.tcp_at(&Self::coords(q, 0.0))
    }

    /// Damped least-squares IK from `q` toward `goal` (fixed-size maths, deterministic).
    fn inverse_kinematics(&self, q: &Coords<8>, goal: &OscGoal) -> [f64; 6] {
        let d = self.arm.dynamics();
        let mut q = *q;
        let lambda2 = 1e-4;
        for _ in 0..30 {
            let poses = d.forward(self.arm.base(), &q);
            let tcp = d.frame_pose(&poses, self.tcp.body, &self.tcp.local);
            let mut err = SVector::<f64, 6>::zeros();
            err.fixed_rows_mut::<3>(0).copy_from(&(goal.pos() - tcp.pos));
            err.fixed_rows_mut::<3>(3).copy_from(&orientation_error(&goal.ori(), &tcp.rot));
            if err.norm() < 1e-7 {
                break;
            }
            let j: SMatrix<f64, 6, 6> = d.point_jacobian(&poses, self.tcp.body, &tcp.pos).fixed_columns::<6>(0).into_owned();
            let jjt = j * j.transpose() + SMatrix::<f64, 6, 6>::identity() * lambda2;
            let Some(step) = jjt.cholesky().map(|c| j.transpose() * c.solve(&err)) else { break };
            for i in 0..6 {
                q[i] = (q[i] + step[i]).clamp(JOINT_LIMITS[i][0], JOINT_LIMITS[i][1]);
            }
        }
        std::array::from_fn(|i| q[i])
    }

    /// Servo efforts for the next substep: PD toward the targets (Menagerie's gains), plus an
    /// integral term, plus exact gravity/Coriolis compensation, clipped to the actuator limits.
    /// The integral term is ours: against the joints' 0.3 N·m of dry friction Menagerie's PD
    /// alone leaves up to 0.03 rad of steady error at the wrist (kp 10), centimetres at the
    /// fingertips, where the real arm's motor drivers close their position loops. It builds up
    /// at [`INTEGRAL_RATE`] × kp per second of error and is held within [`INTEGRAL_LIMIT`].
    pub fn apply(&self, world: &mut World, control: &mut PiperControl) {
        let s = self.arm.state(world);
        let d = self.arm.dynamics();
        let poses = d.forward(self.arm.base(), &s.q);
        let mut tau = d.bias_forces(&poses, &s.qd);
        let g = &self.gains;
        let dt = world.params().dt;
        for i in 0..6 {
            let error = control.joint_targets[i] - s.q[i];
            control.integral[i] = (control.integral[i] + INTEGRAL_RATE * g.kp[i] * error * dt).clamp(-INTEGRAL_LIMIT, INTEGRAL_LIMIT);
            let pid = g.kp[i] * error - g.kv[i] * s.qd[i] + control.integral[i];
            tau[i] = (tau[i] + pid).clamp(-g.torque_limit, g.torque_limit);
        }
        for k in 6..8 {
            let pd = g.finger_kp * (control.opening / 2.0 - s.q[k]) - g.finger_kv * s.qd[k];
            tau[k] = (tau[k] + pd).clamp(-g.finger_force_limit, g.finger_force_limit);
        }
        self.arm.apply_generalized_forces(world, &poses, &tau);
    }

    /// One control step (the world's substeps) of a delta end-effector action.
    pub fn control_step(&self, world: &mut World, control: &mut PiperControl, action: &Action) {
        self.command_delta(world, control, action);
        for _ in 0..world.params().substeps {
            self.apply(world, control);
            world.step();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ready() -> (World, Piper, PiperControl) {
        let mut world = World::new(SIM_PARAMS);
        let piper = Piper::insert(&mut world, Pose::IDENTITY);
        piper.set_joints(&mut world, &READY_QPOS, 0.07);
        let control = piper.hold_control(&world);
        (world, piper, control)
    }

    /// AgileX's published geometry: at q = 0 the flange (link6) is folded back over the base at
    /// (0.0553, 0.0014, 0.1955) (URDF measured with MuJoCo, research notes §4.1).
    #[test]
    fn urdf_convention_at_zero() {
        let d = crate::dynamics::ArmDynamics::<8>::new(model(), [0.0, 0.0, -9.81]);
        let flange = d.forward(&Pose::IDENTITY, &Coords::<8>::zeros()).poses[6].pos;
        assert!((flange - Vec3::new(0.0553, 0.0014, 0.1955)).norm() < 1e-3, "{flange:?}");
    }

    #[test]
    fn ready_pose_points_down_in_front() {
        let (world, piper, _) = ready();
        let tcp = piper.tcp_pose(&world);
        assert!(tcp.pos.x > 0.2 && tcp.pos.z > 0.05, "{:?}", tcp.pos);
        assert!((tcp.rot * Vec3::z()).z < -0.99, "tool axis {:?}", tcp.rot * Vec3::z());
    }

    #[test]
    fn holds_still_under_gravity() {
        let (mut world, piper, mut control) = ready();
        let start = piper.tcp_pose(&world).pos;
        for _ in 0..40 {
            piper.control_step(&mut world, &mut control, &Action::hold(-1.0));
        }
        let drift = (piper.tcp_pose(&world).pos - start).norm();
        assert!(drift < 2e-3, "drifted {drift} m");
    }

    #[test]
    fn delta_actions_move_the_tool_where_asked() {
        let (mut world, piper, mut control) = ready();
        let start = piper.tcp_pose(&world);
        let push = Action::new(&[0.0, 0.5, -0.3, 0.0, 0.0, 0.0, -1.0]).unwrap();
        for _ in 0..2 {
            piper.control_step(&mut world, &mut control, &push);
        }
        for _ in 0..20 {
            piper.control_step(&mut world, &mut control, &Action::hold(-1.0));
        }
        let end = piper.tcp_pose(&world);
        let moved = end.pos - start.pos;
        // 2 × (0.025 m in y, -0.015 m in z); servo friction leaves a few millimetres.
        assert!((moved.y - 0.05).abs() < 0.01 && (moved.z + 0.03).abs() < 0.01, "moved {moved:?}");
        assert!(moved.x.abs() < 0.01, "moved {moved:?}");
        assert!(crate::spatial::angle_between(&start.rot, &end.rot) < 0.05);
    }

    #[test]
    fn joint_deltas_move_joints_and_zero_holds() {
        let (mut world, piper, mut control) = ready();
        let start = piper.joints(&world).q;
        let turn = Action::new(&[0.1, 0.0, 0.0, 0.0, 0.0, -0.05, -1.0]).unwrap();
        for _ in 0..3 {
            piper.joint_step(&mut world, &mut control, &turn);
        }
        // The wrist servos (kp 10) settle within about three seconds.
        for _ in 0..60 {
            piper.joint_step(&mut world, &mut control, &Action::hold(-1.0));
        }
        let q = piper.joints(&world).q;
        assert!((q[0] - start[0] - 0.3).abs() < 0.01, "joint 1 moved {}", q[0] - start[0]);
        assert!((q[5] - start[5] + 0.15).abs() < 0.01, "joint 6 moved {}", q[5] - start[5]);
        assert!((q[1] - start[1]).abs() < 0.01, "joint 2 moved {}", q[1] - start[1]);
        let before = piper.tcp_pose(&world).pos;
        for _ in 0..40 {
            piper.joint_step(&mut world, &mut control, &Action::hold(-1.0));
        }
        assert!((piper.tcp_pose(&world).pos - before).norm() < 1e-3);
    }

    #[test]
    fn gripper_closes_and_opens() {
        let (mut world, piper, mut control) = ready();
        for _ in 0..20 {
            piper.control_step(&mut world, &mut control, &Action::hold(1.0));
        }
        let s = piper.arm().state(&world).q;
        assert!(s[6] + s[7] < 0.005, "closed opening {}", s[6] + s[7]);
        for _ in 0..20 {
            piper.control_step(&mut world, &mut control, &Action::hold(-1.0));
        }
        let s = piper.arm().state(&world).q;
        assert!(s[6] + s[7] > 0.065, "open opening {}", s[6] + s[7]);
    }

    #[test]
    fn joint_commands_are_validated_and_clamped() {
        let (_, piper, mut control) = ready();
        assert!(piper.command_joints(&mut control, &[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0], 0.03).is_err());
        assert!(piper.command_joints(&mut control, &READY_QPOS, 0.2).is_err());
        piper.command_joints(&mut control, &[9.0, 1.0, -1.0, 0.0, 0.0, 0.0], 0.03).unwrap();
        assert_eq!(control.joint_targets[0], JOINT_LIMITS[0][1]);
    }
}
