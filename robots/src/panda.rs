//! The Franka Panda exactly as LIBERO uses it: robosuite 1.4's `Panda` arm, `PandaGripper` and,
//! for table scenes, the `RethinkMount` pedestal.
//!
//! All numbers are robosuite 1.4.0's model facts (kinematic chain, placeholder inertials, joint
//! damping/armature/frictionloss, limits, gripper geometry). The links and the hand collide as
//! hulls fitted to robosuite's collision meshes (`panda_hulls`, written by
//! `xval/fit_link_hulls.py`: no mesh files ship with the project) and touch each other as
//! MuJoCo's do; the fingers are boxes following their mesh, and the finger pads, which do the
//! grasping, are robosuite's own boxes. The built-in look draws the links as capsules.

use std::sync::Arc;

use serde::{Deserialize, Serialize};
use vifo_physics::World;

use crate::action::Action;
use crate::arm::{ArmInstance, JointState};
use crate::dynamics::Jacobian;
use crate::fluid::Fluid;
use crate::gripper::{GripperRamp, finger_forces};
use crate::limits::JointLimits;
use crate::soft_contact::{FixedShape, SoftContacts};
use crate::soft::{Constraints, Softness};
use crate::panda_hulls;
use crate::osc::{self, OscGoal, OscInput, OscParams};
use crate::model::{ArmModel, Body, Collider, ContactRole, ContactShape, Inertial, JointKind, JointSpec, Shape, Site, Visual};
use crate::spatial::{Coords, Pose, Vec3};

/// LIBERO's `MountedPanda` / `OnTheGroundPanda` `init_qpos`: the OSC nullspace target and the
/// reset configuration.
pub const LIBERO_INIT_QPOS: [f64; 7] =
    [0.0, -0.161037389, 0.0, -2.44459747, 0.0, 2.22675220, std::f64::consts::FRAC_PI_4];

/// Finger positions at reset (robosuite `PandaGripper.init_qpos`).
pub const GRIPPER_INIT_QPOS: [f64; 2] = [0.020833, -0.020833];

/// Arm motor torque limits (robot.xml `ctrlrange`), N·m.
pub const TORQUE_LIMITS: [f64; 7] = [80.0, 80.0, 80.0, 80.0, 80.0, 12.0, 12.0];

/// The grip site: robosuite's end-effector point (`gripper0_grip_site`).
pub const GRIP_SITE: &str = "grip_site";
/// The body whose orientation robosuite reports as `robot0_eef_quat`.
pub const HAND_BODY: &str = "right_hand";
/// The wrist camera (`robot0_eye_in_hand`).
pub const EYE_IN_HAND: &str = "eye_in_hand";

/// Height of the robot base above the RethinkMount's placement point (`bottom_offset` 0.912 m).
pub const MOUNT_HEIGHT: f64 = 0.912;

/// Whether the arm stands on robosuite's pedestal (tabletop, kitchen, study scenes) or on the
/// ground (floor and living-room scenes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mount {
    Pedestal,
    Ground,
}

const WHITE: [f32; 4] = [0.95, 0.95, 0.95, 1.0];
const DARK: [f32; 4] = [0.15, 0.15, 0.17, 1.0];
const GREY: [f32; 4] = [0.5, 0.5, 0.5, 1.0];

fn q(w: f64, x: f64, y: f64, z: f64) -> [f64; 4] {
    [w, x, y, z]
}

const H: f64 = 0.707107;

/// A link's look in the built-in view: a capsule from `from` to `to`.
fn capsule(radius: f64, from: [f64; 3], to: [f64; 3], rgba: [f32; 4]) -> Visual {
    let (a, b) = (Vec3::from(from), Vec3::from(to));
    let axis = b - a;
    let len = axis.norm();
    let rot = nalgebra::UnitQuaternion::rotation_between(&Vec3::z(), &(axis / len))
        .unwrap_or_else(nalgebra::UnitQuaternion::identity);
    Visual { shape: Shape::Capsule { radius, half_height: len / 2.0 }, local: Pose::new((a + b) / 2.0, rot.to_rotation_matrix().into_inner()), rgba }
}

/// A link's collider: its fitted hull ([`panda_hulls`]), in the body frame.
fn hull(name: &'static str, points: &'static [[f64; 3]]) -> Collider {
    Collider { name, shape: ContactShape::Hull(points), local: Pose::IDENTITY, friction: 1.0, role: ContactRole::Link }
}

fn cuboid(name: &'static str, half: [f64; 3], center: [f64; 3], role: ContactRole, friction: f64) -> Collider {
    Collider { name, shape: ContactShape::Primitive(Shape::Box { half }), local: Pose::from_wxyz(center, q(1.0, 0.0, 0.0, 0.0)), friction, role }
}

/// Visuals mirroring the primitive colliders, in the Panda's white-and-dark colours (a body with
/// a hull lists its visuals itself).
fn visuals_of(colliders: &[Collider], rgba: [f32; 4]) -> Vec<Visual> {
    colliders
        .iter()
        .filter_map(|c| match c.shape {
            ContactShape::Primitive(shape) => Some(Visual { shape, local: c.local, rgba }),
            ContactShape::Hull(_) => None,
        })
        .collect()
}

fn hinge(name: &'static str, range: [f64; 2], damping: f64, armature: f64) -> JointSpec {
    JointSpec { name, kind: JointKind::Hinge, axis: Vec3::z(), range, damping, armature, frictionloss: 0.1, soft: Some(Softness::MUJOCO_DEFAULT) }
}

fn finger_joint(name: &'static str, range: [f64; 2]) -> JointSpec {
    JointSpec {
        name,
        kind: JointKind::Slide,
        axis: Vec3::y(),
        range,
        damping: 100.0,
        armature: 1.0,
        frictionloss: 1.0,
        soft: Some(Softness::MUJOCO_DEFAULT),
    }
}

/// One finger (body + pad tip). `side` is +1 for the left finger, -1 for the right one.
fn finger(bodies: &mut Vec<Body>, gripper: usize, side: f64) {
    let (name, tip, joint, pad_name, hull) = if side > 0.0 {
        ("leftfinger", "finger1_tip", finger_joint("finger_joint1", [0.0, 0.04]), "finger1_pad", panda_hulls::FINGER1_FULL)
    } else {
        ("rightfinger", "finger2_tip", finger_joint("finger_joint2", [-0.04, 0.0]), "finger2_pad", panda_hulls::FINGER2_FULL)
    };
    // The finger mesh tapers: thick near the hand, thin at the tip (robosuite collides with its
    // convex hull); two boxes follow that profile for rapier, the hull itself touches the arm.
    let shell = vec![
        cuboid("finger_base", [0.0105, 0.0102, 0.0125], [0.0, side * 0.0162, 0.0125], ContactRole::Finger, 1.0),
        cuboid("finger_tip", [0.0095, 0.0072, 0.0145], [0.0, side * 0.0072, 0.0395], ContactRole::Finger, 1.0),
    ];
    let index = bodies.len();
    bodies.push(Body {
        name,
        parent: Some(gripper),
        local: Pose::from_wxyz([0.0, 0.0, 0.0524], q(H, 0.0, 0.0, H)),
        joint: Some(joint),
        inertial: Inertial::diag(0.1, [0.0, 0.0, 0.05], [0.01, 0.01, 0.005]),
        visuals: visuals_of(&shell, GREY),
        colliders: shell,
        self_hull: Some(hull),
    });
    let pad = Collider {
        name: pad_name,
        shape: ContactShape::Primitive(Shape::Box { half: [0.008, 0.004, 0.008] }),
        local: Pose::from_wxyz([0.0, -side * 0.005, -0.015], q(0.0, 0.0, 0.0, 1.0)),
        friction: 2.0,
        role: ContactRole::Pad,
    };
    bodies.push(Body {
        name: tip,
        parent: Some(index),
        local: Pose::from_wxyz([0.0, side * 0.0085, 0.056], q(1.0, 0.0, 0.0, 0.0)),
        joint: None,
        inertial: Inertial::new(0.01, [0.0; 3], [0.01, 0.01, 0.01], q(0.0, 0.0, 0.0, 1.0)),
        visuals: visuals_of(std::slice::from_ref(&pad), DARK),
        colliders: vec![pad],
        self_hull: None,
    });
}

/// robosuite's RethinkMount: static boxes and a cylinder under the base.
fn pedestal() -> Vec<Collider> {
    let z = 0.01;
    vec![
        cuboid("controller_box", [0.11, 0.2, 0.265], [-0.325, 0.0, -0.38 + z], ContactRole::Link, 1.0),
        cuboid("pedestal_feet", [0.385, 0.35, 0.155], [-0.1225, 0.0, -0.758 + z], ContactRole::Link, 1.0),
        Collider {
            name: "pedestal",
            shape: ContactShape::Primitive(Shape::Cylinder { radius: 0.18, half_height: 0.31 }),
            local: Pose::from_wxyz([-0.02, 0.0, -0.29 + z], q(1.0, 0.0, 0.0, 0.0)),
            friction: 1.0,
            role: ContactRole::Link,
        },
    ]
}

/// The LIBERO Panda with its gripper; `mount` adds the pedestal's static geometry to the base.
pub fn model(mount: Mount) -> Arc<ArmModel> {
    let base_colliders = if mount == Mount::Pedestal { pedestal() } else { Vec::new() };
    let mut bodies = vec![Body {
        name: "base",
        parent: None,
        local: Pose::IDENTITY,
        joint: None,
        inertial: Inertial::diag(0.0, [0.0; 3], [0.0; 3]),
        visuals: visuals_of(&base_colliders, DARK),
        colliders: base_colliders,
        self_hull: None,
    }];
    bodies.push(Body {
        name: "link0",
        parent: Some(0),
        local: Pose::IDENTITY,
        joint: None,
        inertial: Inertial::diag(4.0, [0.0, 0.0, 0.05], [0.4, 0.4, 0.4]),
        visuals: vec![Visual { shape: Shape::Box { half: [0.113, 0.095, 0.07] }, local: Pose::from_wxyz([-0.041, 0.0, 0.07], q(1.0, 0.0, 0.0, 0.0)), rgba: WHITE }],
        colliders: vec![hull("link0", panda_hulls::LINK0)],
        self_hull: Some(panda_hulls::LINK0_FULL),
    });
    let d = 0.1;
    // Links 1-6 collide as their fitted hulls, as MuJoCo does, and are drawn as capsules in the
    // built-in look. Link 7 neither collides (robosuite gives it no collision geom) nor is drawn
    // (the hand hides it).
    let (white, dark) = (|r, a, b| vec![capsule(r, a, b, WHITE)], |r, a, b| vec![capsule(r, a, b, DARK)]);
    type Link = (&'static str, [f64; 3], [f64; 4], JointSpec, Inertial, Option<(&'static [[f64; 3]], &'static [[f64; 3]])>, Vec<Visual>);
    let links: [Link; 7] = [
        ("link1", [0.0, 0.0, 0.333], q(1.0, 0.0, 0.0, 0.0), hinge("joint1", [-2.8973, 2.8973], d, 5.0),
            Inertial::diag(3.0, [0.0, 0.0, -0.07], [0.3; 3]), Some((panda_hulls::LINK1, panda_hulls::LINK1_FULL)), white(0.055, [0.0, 0.0, -0.14], [0.0, 0.0, 0.0])),
        ("link2", [0.0; 3], q(H, -H, 0.0, 0.0), hinge("joint2", [-1.7628, 1.7628], d, 2.5),
            Inertial::diag(3.0, [0.0, -0.1, 0.0], [0.3; 3]), Some((panda_hulls::LINK2, panda_hulls::LINK2_FULL)), dark(0.055, [0.0, 0.0, 0.0], [0.0, -0.14, 0.0])),
        ("link3", [0.0, -0.316, 0.0], q(H, H, 0.0, 0.0), hinge("joint3", [-2.8973, 2.8973], d, 5.0 / 3.0),
            Inertial::diag(2.0, [0.04, 0.0, -0.05], [0.2; 3]), Some((panda_hulls::LINK3, panda_hulls::LINK3_FULL)), white(0.055, [0.0, 0.0, -0.07], [0.0825, 0.0, 0.0])),
        ("link4", [0.0825, 0.0, 0.0], q(H, H, 0.0, 0.0), hinge("joint4", [-3.0718, -0.0698], d, 1.25),
            Inertial::diag(2.0, [-0.04, 0.05, 0.0], [0.2; 3]), Some((panda_hulls::LINK4, panda_hulls::LINK4_FULL)), dark(0.055, [0.0, 0.0, 0.0], [-0.0825, 0.07, 0.0])),
        ("link5", [-0.0825, 0.384, 0.0], q(H, -H, 0.0, 0.0), hinge("joint5", [-2.8973, 2.8973], d, 1.0),
            Inertial::diag(2.0, [0.0, 0.0, -0.15], [0.2; 3]), Some((panda_hulls::LINK5, panda_hulls::LINK5_FULL)), white(0.055, [0.0, 0.0, -0.21], [0.0, 0.0, -0.02])),
        ("link6", [0.0; 3], q(H, H, 0.0, 0.0), hinge("joint6", [-0.0175, 3.7525], 0.01, 5.0 / 6.0),
            Inertial::diag(1.5, [0.06, 0.0, 0.0], [0.1; 3]), Some((panda_hulls::LINK6, panda_hulls::LINK6_FULL)), dark(0.05, [0.0, 0.0, 0.0], [0.088, 0.0, 0.0])),
        ("link7", [0.088, 0.0, 0.0], q(H, H, 0.0, 0.0), hinge("joint7", [-2.8973, 2.8973], 0.01, 5.0 / 7.0),
            Inertial::diag(0.5, [0.0, 0.0, 0.08], [0.05; 3]), None, Vec::new()),
    ];
    for (name, pos, quat, joint, inertial, points, visuals) in links {
        let colliders = points.map(|(corners, _)| hull(name, corners)).into_iter().collect();
        let self_hull = points.map(|(_, full)| full);
        let parent = Some(bodies.len() - 1);
        bodies.push(Body { name, parent, local: Pose::from_wxyz(pos, quat), joint: Some(joint), inertial, colliders, self_hull, visuals });
    }
    let link7 = bodies.len() - 1;
    bodies.push(Body {
        name: HAND_BODY,
        parent: Some(link7),
        local: Pose::from_wxyz([0.0, 0.0, 0.1065], q(0.924, 0.0, 0.0, -0.383)),
        joint: None,
        inertial: Inertial::diag(0.5, [0.0; 3], [0.05; 3]),
        colliders: Vec::new(),
        self_hull: None,
        visuals: vec![Visual {
            shape: Shape::Cylinder { radius: 0.045, half_height: 0.012 },
            local: Pose::from_wxyz([0.0, 0.0, -0.012], q(1.0, 0.0, 0.0, 0.0)),
            rgba: DARK,
        }],
    });
    let hand = bodies.len() - 1;
    bodies.push(Body {
        name: "right_gripper",
        parent: Some(hand),
        local: Pose::from_wxyz([0.0; 3], q(H, 0.0, 0.0, -H)),
        joint: None,
        inertial: Inertial::new(0.3, [0.0, 0.0, 0.17], [0.09, 0.07, 0.05], q(H, H, 0.0, 0.0)),
        // The hand mesh is thinner than its collision box above the finger slots (±1.8 cm from
        // z = 1 cm up instead of ±3.2 cm); the wrist camera looks past that edge, so the visual
        // follows the mesh's two steps.
        visuals: vec![
            Visual { shape: Shape::Box { half: [0.1, 0.0315, 0.018] }, local: Pose::from_wxyz([0.0, 0.0, -0.008], q(1.0, 0.0, 0.0, 0.0)), rgba: WHITE },
            Visual { shape: Shape::Box { half: [0.1, 0.0175, 0.028] }, local: Pose::from_wxyz([0.0, 0.0, 0.038], q(1.0, 0.0, 0.0, 0.0)), rgba: WHITE },
        ],
        colliders: vec![hull("hand", panda_hulls::HAND)],
        self_hull: Some(panda_hulls::HAND_FULL),
    });
    let gripper = bodies.len() - 1;
    finger(&mut bodies, gripper, 1.0);
    finger(&mut bodies, gripper, -1.0);
    let dofs = (0..bodies.len()).filter(|&i| bodies[i].joint.is_some()).collect();
    let sites = vec![
        Site { name: GRIP_SITE, body: gripper, local: Pose::from_wxyz([0.0, 0.0, 0.097], q(1.0, 0.0, 0.0, 0.0)) },
        Site { name: EYE_IN_HAND, body: hand, local: Pose::from_wxyz([0.05, 0.0, 0.0], q(0.0, 0.707108, 0.707108, 0.0)) },
    ];
    Arc::new(ArmModel { name: "panda", bodies, dofs, arm_dofs: 7, sites, self_contact: true }.validated())
}

/// World pose of the robot base when LIBERO places the robot at `xpos` (robosuite
/// `set_base_xpos`): the pedestal lifts the base by [`MOUNT_HEIGHT`].
pub fn base_pose(mount: Mount, xpos: [f64; 3]) -> Pose {
    let lift = if mount == Mount::Pedestal { MOUNT_HEIGHT } else { 0.0 };
    Pose::from_wxyz([xpos[0], xpos[1], xpos[2] + lift], q(1.0, 0.0, 0.0, 0.0))
}

/// The Panda in a world, driven exactly as robosuite drives it.
#[derive(Clone, Debug)]
pub struct Panda {
    arm: ArmInstance<9>,
    limits: JointLimits<9>,
    soft_contacts: SoftContacts,
    params: OscParams,
    grip_site: Site,
    hand: usize,
}

/// The controller's per-episode state, which is not part of the physics state: the OSC goal,
/// the nullspace target and the gripper's hidden ramp. Snapshots must carry it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PandaControl {
    pub goal: OscGoal,
    pub nullspace_target: [f64; 7],
    pub gripper: GripperRamp,
    /// robosuite's controller caches the robot state and refreshes it only after it has run
    /// once; right after a reset its cache still describes the reset configuration (arm at
    /// `init_qpos`, fingers at 0, at rest) even though LIBERO has since loaded an initial state.
    /// While this is set, the next substep computes its goal and torques from that cache
    /// (bias forces excepted, which robosuite reads live), exactly as robosuite does.
    pub stale_cache: bool,
}

impl Panda {
    /// Builds the arm into `world` with its base at `base` (see [`base_pose`]).
    pub fn insert(world: &mut World, mount: Mount, base: Pose) -> Self {
        let model = model(mount);
        let grip_site = model.site(GRIP_SITE).expect("grip site").clone();
        let hand = model.body_index(HAND_BODY).expect("hand body");
        let arm = ArmInstance::insert(world, model, base);
        let limits = JointLimits::new(arm.dynamics());
        let soft_contacts = SoftContacts::new(arm.dynamics());
        Panda { arm, limits, soft_contacts, params: OscParams::ROBOSUITE, grip_site, hand }
    }

    /// Gives the arm the fixed colliders of `world`'s scene its links touch with MuJoCo's soft
    /// contact (rapier leaves the arena and the fixtures' still bodies to it,
    /// [`crate::contact::groups`]).
    pub fn with_fixed(mut self, world: &World, fixed: &[FixedShape]) -> Self {
        self.soft_contacts = self.soft_contacts.with_fixed(world, fixed);
        self
    }

    pub fn arm(&self) -> &ArmInstance<9> {
        &self.arm
    }

    /// The controller state right after robosuite's reset: goal at the end-effector pose of
    /// LIBERO's `init_qpos`, nullspace target `init_qpos`, gripper ramp at zero. LIBERO then
    /// overwrites the joint state (`set_init_state`) without touching this.
    pub fn reset_control(&self) -> PandaControl {
        let q = Self::coords(&LIBERO_INIT_QPOS, &GRIPPER_INIT_QPOS);
        let poses = self.arm.dynamics().forward(self.arm.base(), &q);
        let site = self.arm.dynamics().frame_pose(&poses, self.grip_site.body, &self.grip_site.local);
        PandaControl {
            goal: OscGoal::new(site.pos, site.rot),
            nullspace_target: LIBERO_INIT_QPOS,
            gripper: GripperRamp::default(),
            stale_cache: true,
        }
    }

    fn coords(arm: &[f64; 7], fingers: &[f64; 2]) -> Coords<9> {
        let mut q = Coords::<9>::zeros();
        q.fixed_rows_mut::<7>(0).copy_from_slice(arm);
        q[7] = fingers[0];
        q[8] = fingers[1];
        q
    }

    /// Sets joint positions and velocities (arm 7, fingers 2).
    pub fn set_joints(&self, world: &mut World, arm: &[f64; 7], fingers: &[f64; 2], arm_vel: &[f64; 7], finger_vel: &[f64; 2]) {
        let state = JointState { q: Self::coords(arm, fingers), qd: Self::coords(arm_vel, finger_vel) };
        self.arm.set_state(world, &state);
    }

    /// Current joint positions and velocities.
    pub fn joints(&self, world: &World) -> JointState<9> {
        self.arm.state(world)
    }

    /// World pose of the grip site (robosuite's `robot0_eef_pos` and the OSC's frame).
    pub fn grip_site_pose(&self, world: &World) -> Pose {
        let poses = self.arm.body_poses(world);
        self.arm.dynamics().frame_pose(&poses, self.grip_site.body, &self.grip_site.local)
    }

    /// World pose of the hand body (robosuite reports its orientation as `robot0_eef_quat`).
    pub fn hand_pose(&self, world: &World) -> Pose {
        self.arm.body_poses(world).poses[self.hand]
    }

    /// Sets the actuator efforts for the next physics substep: OSC torques (goal refreshed when
    /// `policy_step`), clipped to the motor limits, the gripper servos, and the forces of any
    /// joint limit engaged and of the arm touching itself (MuJoCo's soft constraints,
    /// [`crate::limits`], [`crate::soft_contact`]).
    pub fn apply(&self, world: &mut World, control: &mut PandaControl, action: &Action, policy_step: bool) {
        let live = self.arm.state(world);
        let dynamics = self.arm.dynamics();
        let live_poses = dynamics.forward(self.arm.base(), &live.q);
        let bias = dynamics.bias_forces(&live_poses, &live.qd);
        let stale = std::mem::take(&mut control.stale_cache);
        let (state, poses) = if stale {
            let q = Self::coords(&control.nullspace_target, &[0.0; 2]);
            (JointState { q, qd: Coords::<9>::zeros() }, dynamics.forward(self.arm.base(), &q))
        } else {
            (live, live_poses.clone())
        };
        let site = dynamics.frame_pose(&poses, self.grip_site.body, &self.grip_site.local);
        if policy_step {
            control.goal = control.goal.updated(&self.params, &site.pos, &site.rot, action.translation(), action.rotation());
        }
        let jac: Jacobian<9> = dynamics.point_jacobian(&poses, self.grip_site.body, &site.pos);
        let mass = dynamics.mass_matrix(&poses);
        let arm_q = state.q.fixed_rows::<7>(0).into_owned();
        let arm_qd = state.qd.fixed_rows::<7>(0).into_owned();
        let q0 = nalgebra::SVector::<f64, 7>::from(control.nullspace_target);
        let input = OscInput {
            q: &arm_q,
            qd: &arm_qd,
            mass: &mass.fixed_view::<7, 7>(0, 0).into_owned(),
            bias: &bias.fixed_rows::<7>(0).into_owned(),
            jacobian: &jac.fixed_columns::<7>(0).into_owned(),
            ee_pos: &site.pos,
            ee_ori: &site.rot,
            q0: &q0,
        };
        let arm_tau = osc::torques(&self.params, &control.goal, &input);
        let ctrl = control.gripper.step(action.gripper());
        let finger = finger_forces(ctrl, [live.q[7], live.q[8]]);
        let mut tau = Coords::<9>::zeros();
        for i in 0..7 {
            tau[i] = arm_tau[i].clamp(-TORQUE_LIMITS[i], TORQUE_LIMITS[i]);
        }
        tau[7] = finger[0];
        tau[8] = finger[1];
        tau += dynamics.fluid_forces(&Fluid::ROBOSUITE_AIR, &live_poses, &live.qd);
        let dt = world.params().dt;
        let mut constraints = Constraints::default();
        self.limits.rows(&live.q, &live.qd, dt, &mut constraints.rows);
        self.limits.friction(&live.qd, dt, &mut constraints.friction);
        self.soft_contacts.cones(dynamics, &live_poses, &live.qd, world, &mut constraints.cones);
        if !constraints.is_empty() {
            let model = dynamics.model();
            let damping = Coords::<9>::from_fn(|i, _| model.joint(i).damping * live.qd[i]);
            let live_mass = if stale { dynamics.mass_matrix(&live_poses) } else { mass };
            tau += constraints.forces(&live_mass, &(tau - bias - damping));
        }
        self.arm.apply_generalized_forces(world, &live_poses, &tau);
    }

    /// One 20 Hz control step: the world's substeps, the goal set on the first.
    pub fn control_step(&self, world: &mut World, control: &mut PandaControl, action: &Action) {
        for substep in 0..world.params().substeps {
            self.apply(world, control, action, substep == 0);
            world.step();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::ArmDynamics;

    fn at(qpos: [f64; 7]) -> (ArmDynamics<9>, crate::dynamics::BodyPoses) {
        let dynamics = ArmDynamics::<9>::new(model(Mount::Ground), [0.0, 0.0, -9.81]);
        let mut q = Coords::<9>::zeros();
        q.fixed_rows_mut::<7>(0).copy_from_slice(&qpos);
        q[7] = GRIPPER_INIT_QPOS[0];
        q[8] = GRIPPER_INIT_QPOS[1];
        let poses = dynamics.forward(&Pose::IDENTITY, &q);
        (dynamics, poses)
    }

    fn grip_site(dynamics: &ArmDynamics<9>, poses: &crate::dynamics::BodyPoses) -> Pose {
        let site = dynamics.model().site(GRIP_SITE).unwrap();
        dynamics.frame_pose(poses, site.body, &site.local)
    }

    /// Golden values measured with MuJoCo on robosuite's composed model (research notes, robots §1.3).
    #[test]
    fn matches_mujoco_at_libero_init() {
        let (dynamics, poses) = at(LIBERO_INIT_QPOS);
        let site = grip_site(&dynamics, &poses);
        let expected = Vec3::new(0.451535, 0.0, 0.261279);
        assert!((site.pos - expected).norm() < 2e-6, "grip site {:?}", site.pos);
        let qs = site.quat_wxyz();
        let golden = [-0.020087, 0.706647, 0.706996, -0.020077];
        let dot: f64 = qs.iter().zip(golden).map(|(a, b)| a * b).sum();
        assert!(dot.abs() > 1.0 - 1e-5, "grip site quat {qs:?}");

        let bias = dynamics.bias_forces(&poses, &Coords::<9>::zeros());
        let golden_bias = [0.0, -19.6448, 0.0, 18.0603, 0.0, 2.0677, 0.0];
        for i in 0..7 {
            assert!((bias[i] - golden_bias[i]).abs() < 1e-3, "bias[{i}] = {}", bias[i]);
        }
        let m = dynamics.mass_matrix(&poses);
        let golden_diag = [7.2543, 5.0122, 3.3953, 2.8696, 1.5073, 1.2220, 0.9144, 1.11, 1.11];
        for i in 0..9 {
            assert!((m[(i, i)] - golden_diag[i]).abs() < 1e-3, "M[{i},{i}] = {}", m[(i, i)]);
        }
    }

    #[test]
    fn matches_mujoco_at_other_configurations() {
        let (dynamics, poses) = at([0.0, std::f64::consts::PI / 16.0, 0.0, -std::f64::consts::PI / 2.0 - std::f64::consts::PI / 3.0, 0.0, std::f64::consts::PI - 0.2, std::f64::consts::PI / 4.0]);
        let site = grip_site(&dynamics, &poses);
        assert!((site.pos - Vec3::new(0.457232, 0.0, 0.099044)).norm() < 2e-6, "{:?}", site.pos);
        let bias = dynamics.bias_forces(&poses, &Coords::<9>::zeros());
        for (i, g) in [0.0, -24.6722, 0.0, 12.4923, 0.0, 2.4541, 0.0].into_iter().enumerate() {
            assert!((bias[i] - g).abs() < 1e-3, "bias[{i}] = {}", bias[i]);
        }
        let (dynamics, poses) = at([0.0; 7]);
        let site = grip_site(&dynamics, &poses);
        assert!((site.pos - Vec3::new(0.088, 0.0, 0.8295)).norm() < 2e-6, "{:?}", site.pos);
        let m = dynamics.mass_matrix(&poses);
        for (i, g) in [6.5241, 5.9885, 2.5908, 2.4082, 1.5173, 1.2020, 0.9144].into_iter().enumerate() {
            assert!((m[(i, i)] - g).abs() < 1e-3, "M[{i},{i}] = {}", m[(i, i)]);
        }
    }

    /// Inverse dynamics and the mass matrix must agree: RNEA(q̇, q̈) − RNEA(q̇, 0) = M q̈ (minus
    /// armature, which RNEA does not see).
    #[test]
    fn inverse_dynamics_is_consistent_with_the_mass_matrix() {
        let (dynamics, poses) = at([0.3, -0.4, 0.2, -2.0, 0.5, 2.0, 0.1]);
        let qd = Coords::<9>::from_fn(|i, _| 0.3 * (i as f64) - 1.0);
        let qdd = Coords::<9>::from_fn(|i, _| 0.7 - 0.2 * (i as f64));
        let lhs = dynamics.inverse_dynamics(&poses, &qd, &qdd) - dynamics.bias_forces(&poses, &qd);
        let mut m = dynamics.mass_matrix(&poses);
        for i in 0..9 {
            m[(i, i)] -= dynamics.model().joint(i).armature;
        }
        assert!((lhs - m * qdd).norm() < 1e-10, "{}", (lhs - m * qdd).norm());
    }

    /// The site Jacobian must match finite differences of forward kinematics.
    #[test]
    fn jacobian_matches_finite_differences() {
        let dynamics = ArmDynamics::<9>::new(model(Mount::Ground), [0.0, 0.0, -9.81]);
        let q = Coords::<9>::from_column_slice(&[0.2, -0.3, 0.1, -2.2, 0.4, 2.1, 0.6, 0.02, -0.02]);
        let site = dynamics.model().site(GRIP_SITE).unwrap().clone();
        let poses = dynamics.forward(&Pose::IDENTITY, &q);
        let p0 = dynamics.frame_pose(&poses, site.body, &site.local);
        let jac = dynamics.point_jacobian(&poses, site.body, &p0.pos);
        let h = 1e-7;
        for i in 0..9 {
            let mut qh = q;
            qh[i] += h;
            let p1 = dynamics.frame_pose(&dynamics.forward(&Pose::IDENTITY, &qh), site.body, &site.local);
            let dv = (p1.pos - p0.pos) / h;
            let dw = crate::spatial::rotation_vector(&(p1.rot * p0.rot.transpose())) / h;
            assert!((dv - jac.fixed_view::<3, 1>(0, i)).norm() < 1e-5, "linear column {i}");
            assert!((dw - jac.fixed_view::<3, 1>(3, i)).norm() < 1e-5, "angular column {i}");
        }
    }
}

#[cfg(test)]
mod step_response {
    use super::*;
    use vifo_physics::SimParams;

    /// Holds `action` from LIBERO's init configuration for `steps` control steps and returns the
    /// grip site's base-frame position after each step, and the rotation about world z.
    fn hold(action: [f64; 7], steps: usize) -> Vec<(Vec3, f64)> {
        let mut world = World::new(SimParams::LIBERO);
        let robot = Panda::insert(&mut world, Mount::Ground, Pose::IDENTITY);
        robot.set_joints(&mut world, &LIBERO_INIT_QPOS, &GRIPPER_INIT_QPOS, &[0.0; 7], &[0.0; 2]);
        let mut control = robot.reset_control();
        let start = robot.grip_site_pose(&world).rot;
        let action = Action::new(&action).unwrap();
        (0..steps)
            .map(|_| {
                robot.control_step(&mut world, &mut control, &action);
                let site = robot.grip_site_pose(&world);
                let turned = crate::spatial::rotation_vector(&(site.rot * start.transpose()));
                (site.pos, turned.z)
            })
            .collect()
    }

    /// Step responses measured with MuJoCo on robosuite's model (research notes, robots §1.4):
    /// holding +x, the grip site's x after each of 10 control steps; holding +z rotation, the
    /// cumulative rotation about world z. The rotation rate is limited by MuJoCo's air drag on the
    /// placeholder inertias, so this also checks the fluid model.
    #[test]
    fn matches_mujoco_step_responses() {
        let x = [0.4563, 0.4653, 0.4751, 0.4853, 0.4960, 0.5071, 0.5185, 0.5303, 0.5423, 0.5545];
        for (k, (p, _)) in hold([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0], 10).into_iter().enumerate() {
            assert!((p.x - x[k]).abs() < 1e-3, "step {k}: x = {:.4}, MuJoCo {:.4}", p.x, x[k]);
        }
        let rz = [0.026, 0.080, 0.141, 0.204, 0.268, 0.333, 0.399, 0.465, 0.531, 0.597];
        for (k, (_, r)) in hold([0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -1.0], 10).into_iter().enumerate() {
            assert!((r - rz[k]).abs() < 3e-3, "step {k}: rotation {r:.3}, MuJoCo {:.3}", rz[k]);
        }
    }
}

#[cfg(test)]
mod determinism {
    use super::*;
    use vifo_physics::SimParams;

    /// A lively 200-step action sequence: moves, rotations, gripper open/close.
    fn action(t: usize) -> Action {
        let s = |k: f64| libm::sin(0.13 * t as f64 + k);
        Action::new(&[s(0.0), s(1.0), 0.6 * s(2.0), 0.4 * s(3.0), 0.3 * s(4.0), 0.5 * s(5.0), if (t / 30).is_multiple_of(2) { -1.0 } else { 1.0 }]).unwrap()
    }

    fn start() -> (World, Panda, PandaControl) {
        let mut world = World::new(SimParams::LIBERO);
        let robot = Panda::insert(&mut world, Mount::Pedestal, base_pose(Mount::Pedestal, [-0.66, 0.0, 0.0]));
        robot.set_joints(&mut world, &LIBERO_INIT_QPOS, &GRIPPER_INIT_QPOS, &[0.0; 7], &[0.0; 2]);
        let control = robot.reset_control();
        (world, robot, control)
    }

    #[test]
    fn same_actions_give_bit_identical_states_across_a_snapshot() {
        let (mut a, robot, mut ca) = start();
        let (mut b, _, mut cb) = start();
        for t in 0..200 {
            robot.control_step(&mut a, &mut ca, &action(t));
            robot.control_step(&mut b, &mut cb, &action(t));
        }
        assert_eq!(a.fingerprint(), b.fingerprint(), "two identical runs differ");

        // Run to the middle, snapshot, wander off with other actions, restore, finish.
        let (mut c, _, mut cc) = start();
        for t in 0..100 {
            robot.control_step(&mut c, &mut cc, &action(t));
        }
        let (snap, saved) = (c.snapshot(), cc);
        for t in 0..17 {
            robot.control_step(&mut c, &mut cc, &action(t + 500));
        }
        c.restore(&snap);
        cc = saved;
        for t in 100..200 {
            robot.control_step(&mut c, &mut cc, &action(t));
        }
        assert_eq!(a.fingerprint(), c.fingerprint(), "a run across snapshot/restore differs");
        assert_eq!(ca, cc);
        assert_eq!(robot.joints(&a), robot.joints(&c));
    }
}

#[cfg(test)]
mod probe_low {
    use super::*;
    use vifo_physics::SimParams;

    #[test]
    fn probe_descend_low() {
        let mut world = World::new(SimParams::LIBERO);
        let robot = Panda::insert(&mut world, Mount::Ground, Pose::from_wxyz([-0.6, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]));
        robot.set_joints(&mut world, &[-0.202, 0.45, -0.25, -2.232, 0.232, 2.653, 0.151], &[0.04, -0.04], &[0.0; 7], &[0.0; 2]);
        let mut control = robot.reset_control();
        control.stale_cache = false;
        let site = robot.grip_site_pose(&world);
        control.goal = OscGoal::new(site.pos, site.rot);
        for k in 0..20 {
            let before = robot.grip_site_pose(&world).pos;
            robot.control_step(&mut world, &mut control, &Action::new(&[0.0, 0.0, -0.5, 0.0, 0.0, 0.0, -1.0]).unwrap());
            let after = robot.grip_site_pose(&world).pos;
            let q = robot.joints(&world);
            println!("{k}: z {:.4} -> {:.4} q {:?}", before.z, after.z, q.q.iter().take(7).map(|v| (v * 1000.0).round() / 1000.0).collect::<Vec<_>>());
        }
    }
}
