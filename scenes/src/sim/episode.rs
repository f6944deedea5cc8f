//! One episode's mutable state: the world, the controller state and the step count.

use std::sync::Arc;

use thiserror::Error;
use vifo_physics::rapier::prelude::*;
use vifo_physics::{Snapshot, World};
use vifo_robots::action::Action;
use vifo_robots::convert::{pose, rapier_pose, vec3, vector};
use vifo_robots::joint;
use vifo_robots::model::JointKind as RobotJointKind;
use vifo_robots::spatial::{Pose, Vec3};

use super::guard::{MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED};
use super::model::{RegionPlace, SceneModel};
use super::robot::RobotControl;
use crate::catalog::JointKind;
use crate::init_file::InitState;

/// A state that does not fit the scene.
#[derive(Debug, Error, PartialEq)]
pub enum StateError {
    #[error("state names object {0}, which the scene does not have")]
    UnknownObject(String),
    #[error("state names joint {joint} of {owner}, which the scene does not have")]
    UnknownJoint { owner: String, joint: String },
    #[error("state value {what} is not finite")]
    NotFinite { what: String },
    #[error("state quaternion {what} is zero, not a rotation")]
    ZeroQuaternion { what: String },
    #[error("state value {value} of robot joint {joint} is far outside its range [{}, {}]", .range[0], .range[1])]
    OutOfRange { joint: String, value: f64, range: [f64; 2] },
    #[error("state speed {speed} of robot joint {joint} is past the physics guard's {max}")]
    TooFast { joint: String, speed: f64, max: f64 },
    #[error("the snapshot was taken of another scene model (task {snapshot}); this Sim runs {this}")]
    ForeignSnapshot { snapshot: String, this: String },
}

/// Everything needed to continue an episode bit for bit from the same point.
#[derive(Clone)]
pub struct SimSnapshot {
    /// The model it was taken of: its body and joint handles are the model's.
    model: Arc<SceneModel>,
    world: Snapshot,
    control: RobotControl,
    steps: usize,
}

/// A running episode of a scene.
pub struct Sim {
    model: Arc<SceneModel>,
    world: World,
    control: RobotControl,
    steps: usize,
}

/// The box of a region at the current state: world pose and half-size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionBox {
    pub pose: Pose,
    pub half_size: Vec3,
    /// The entity the region belongs to (fixture or object sites), if any.
    pub owner: Option<usize>,
}

impl Sim {
    /// A fresh episode in the scene's template state.
    pub fn new(model: Arc<SceneModel>) -> Sim {
        let world = World::from_snapshot(&model.template);
        let control = model.robot.reset_control(&world);
        Sim { model, world, control, steps: 0 }
    }

    pub fn model(&self) -> &Arc<SceneModel> {
        &self.model
    }

    pub fn world(&self) -> &World {
        &self.world
    }

    /// The world, to perturb it (a push, a forced fault); the controller state is untouched.
    pub fn world_mut(&mut self) -> &mut World {
        &mut self.world
    }


    /// Control steps since the episode started.
    pub fn steps(&self) -> usize {
        self.steps
    }

    pub fn control(&self) -> &RobotControl {
        &self.control
    }

    /// Moves a fixture's root (and its articulated parts) to `pose`. Fixture placement is not
    /// part of LIBERO's state vectors; scenes sample it (or take it from a reference) per episode.
    pub fn place_fixture(&mut self, entity: usize, at: &Pose) {
        let e = &self.model.entities[entity];
        let r = self.world.rapier_mut();
        for body in std::iter::once(e.bodies[0]).chain(e.anchor) {
            r.bodies[body].set_position(rapier_pose(at), true);
        }
        if let Some(jh) = e.joints.iter().flatten().next() {
            let (mb, _) = r.multibody_joints.get_mut(*jh).expect("fixture joint");
            mb.forward_kinematics(&r.bodies, true);
            mb.update_rigid_bodies(&mut r.bodies, true);
        }
        self.wake(entity);
    }

    /// Puts a movable entity (a prop such as a cue object) at `at`, at rest.
    pub fn place_object(&mut self, entity: usize, at: &Pose) {
        let body = &mut self.world.rapier_mut().bodies[self.model.entities[entity].bodies[0]];
        body.set_position(rapier_pose(at), true);
        body.set_linvel(Vector::from([0.0; 3]), true);
        body.set_angvel(Vector::from([0.0; 3]), true);
    }

    /// Checks that `state` fits this scene (every object and joint it names exists, every value
    /// is finite, every quaternion non-zero) without changing anything.
    pub fn check_state(&self, state: &InitState) -> Result<(), StateError> {
        self.resolve(state).map(|_| ())
    }

    /// The entity index of each object and joint of `state`, after [`Sim::check_state`]'s checks.
    fn resolve(&self, state: &InitState) -> Result<(Vec<usize>, Vec<usize>), StateError> {
        check_values(state)?;
        let model = &self.model;
        check_robot_range(model.robot.model(), state)?;
        let objects = state.objects.iter().map(|o| model.entity(&o.name).map(|(i, _)| i).ok_or_else(|| StateError::UnknownObject(o.name.clone())));
        let joints = state.joints.iter().map(|j| match model.entity(&j.owner) {
            Some((i, entity)) if entity.joint(&j.joint).is_some() => Ok(i),
            _ => Err(StateError::UnknownJoint { owner: j.owner.clone(), joint: j.joint.clone() }),
        });
        Ok((objects.collect::<Result<_, _>>()?, joints.collect::<Result<_, _>>()?))
    }

    /// Loads a LIBERO state (arm, gripper, object poses and velocities, articulation joints)
    /// and resets the controller as LIBERO's `reset()` + `set_init_state()` leave it. A state
    /// that does not fit ([`Sim::check_state`]) is an error and changes nothing.
    pub fn load_state(&mut self, state: &InitState) -> Result<(), StateError> {
        let (objects, joints) = self.resolve(state)?;
        let model = self.model.clone();
        for (object, i) in state.objects.iter().zip(objects) {
            let at = Pose::from_wxyz(object.pos, object.quat_wxyz);
            let body = &mut self.world.rapier_mut().bodies[model.entities[i].bodies[0]];
            body.set_position(rapier_pose(&at), true);
            let (linvel, angvel) = free_joint_velocity(&at, object.lin_vel, object.ang_vel, vec3(body.local_center_of_mass()));
            body.set_linvel(vector(&linvel), true);
            body.set_angvel(vector(&angvel), true);
        }
        for (j, i) in state.joints.iter().zip(joints) {
            self.set_joint_moving(i, &j.joint, j.qpos, j.qvel);
        }
        model.robot.set_joints(&mut self.world, &state.arm_qpos, &state.gripper_qpos, &state.arm_qvel, &state.gripper_qvel);
        self.control = model.robot.reset_control(&self.world);
        self.steps = 0;
        Ok(())
    }

    /// Sets an articulation joint of an entity (drawer, door, knob) to `value`, at rest.
    pub fn set_joint(&mut self, entity: usize, name: &str, value: f64) {
        self.set_joint_moving(entity, name, value, 0.0);
    }

    /// Sets an articulation joint to `value`, moving at `velocity`.
    fn set_joint_moving(&mut self, entity: usize, name: &str, value: f64, velocity: f64) {
        let Some((_, jh)) = self.model.entities[entity].joint(name) else { return };
        let current = self.joint_position(entity, name).unwrap_or(value);
        let r = self.world.rapier_mut();
        let (mb, link) = r.multibody_joints.get_mut(jh).expect("fixture joint");
        let dof = mb.link(link).expect("link").assembly_id();
        let mut disp = vec![0.0; mb.ndofs()];
        disp[dof] = value - current;
        mb.apply_displacements(&disp);
        mb.generalized_velocity_mut()[dof] = velocity;
        mb.forward_kinematics(&r.bodies, true);
        mb.update_rigid_bodies(&mut r.bodies, true);
        self.wake(entity);
    }

    /// Wakes an entity's bodies after a direct write, so that they answer the contacts of their
    /// new pose instead of sleeping through them.
    fn wake(&mut self, entity: usize) {
        let r = self.world.rapier_mut();
        for &body in &self.model.entities[entity].bodies {
            r.bodies[body].wake_up(true);
        }
    }

    /// Position of an entity's articulation joint (m or rad).
    pub fn joint_position(&self, entity: usize, name: &str) -> Option<f64> {
        let e = &self.model.entities[entity];
        let (body, jh) = e.joint(name)?;
        let (mb, link) = self.world.rapier().multibody_joints.get(jh)?;
        let kind = match e.model.bodies[body].joint.as_ref()?.kind {
            JointKind::Hinge => RobotJointKind::Hinge,
            JointKind::Slide => RobotJointKind::Slide,
        };
        Some(joint::coordinate(kind, &mb.link(link)?.joint().coords()))
    }

    /// One 20 Hz control step.
    pub fn step(&mut self, action: &Action) {
        self.model.robot.control_step(&mut self.world, &mut self.control, action);
        self.steps += 1;
    }

    /// World pose of an entity's root (LIBERO's `<name>_main` body: the pose predicates read).
    pub fn entity_pose(&self, entity: usize) -> Pose {
        self.body_pose(entity, 0)
    }

    /// World pose of one of an entity's bodies.
    pub fn body_pose(&self, entity: usize, body: usize) -> Pose {
        pose(self.world.rapier().bodies[self.model.entities[entity].bodies[body]].position())
    }

    /// The box of a region key at the current state.
    pub fn region_box(&self, key: &str) -> Option<RegionBox> {
        let region = self.model.region(key)?;
        Some(match &region.place {
            RegionPlace::Workspace { center, half_size } => RegionBox {
                pose: Pose::from_wxyz(*center, [1.0, 0.0, 0.0, 0.0]),
                half_size: Vec3::from(*half_size),
                owner: None,
            },
            RegionPlace::Site { entity, site } => {
                let s = &self.model.entities[*entity].model.sites[*site];
                let at = self.body_pose(*entity, s.body).mul(&Pose::from_wxyz(s.pos, s.quat_wxyz));
                RegionBox { pose: at, half_size: Vec3::from(s.half_size), owner: Some(*entity) }
            }
        })
    }

    /// Colliders of a name: an entity's shapes, or the arena's for the table/floor.
    pub fn colliders_of(&self, name: &str) -> Option<&[ColliderHandle]> {
        if self.model.is_arena(name) {
            return Some(&self.model.arena);
        }
        self.model.entity(name).map(|(_, e)| e.colliders.as_slice())
    }

    /// MuJoCo-style contact test between two named things (any collider pair touching).
    pub fn touching(&self, a: &str, b: &str) -> bool {
        match (self.colliders_of(a), self.colliders_of(b)) {
            (Some(ca), Some(cb)) => self.world.in_contact(ca, cb),
            _ => false,
        }
    }

    /// Whether any robot shape touches the named entity.
    pub fn robot_touching(&self, name: &str) -> bool {
        let robot: Vec<ColliderHandle> = self.model.robot.colliders().iter().map(|c| c.handle).collect();
        self.colliders_of(name).is_some_and(|c| self.world.in_contact(&robot, c))
    }

    /// Every robot shape touching something, with what it touches (an entity name, `arena`,
    /// or another robot shape): for diagnostics and for tests.
    pub fn robot_contacts(&self) -> Vec<(&'static str, String)> {
        let robot = self.model.robot.colliders();
        let name_of = |h: ColliderHandle| -> String {
            if let Some(e) = self.model.entities.iter().find(|e| e.colliders.contains(&h)) {
                e.name.clone()
            } else if self.model.arena.contains(&h) {
                "arena".to_string()
            } else {
                robot.iter().find(|c| c.handle == h).map_or_else(|| format!("{h:?}"), |c| format!("robot:{}", c.name))
            }
        };
        let np = &self.world.rapier().narrow_phase;
        let mut out = Vec::new();
        for c in robot {
            for pair in np.contact_pairs_with(c.handle) {
                let touching = pair.manifolds().iter().any(|m| m.points.iter().any(|p| p.dist < vifo_physics::TOUCH_DISTANCE));
                if touching {
                    let other = if pair.collider1 == c.handle { pair.collider2 } else { pair.collider1 };
                    out.push((c.name, name_of(other)));
                }
            }
        }
        out
    }

    pub fn snapshot(&self) -> SimSnapshot {
        SimSnapshot { model: self.model.clone(), world: self.world.snapshot(), control: self.control, steps: self.steps }
    }

    /// Goes back to `snapshot`, which must have been taken of this Sim's model (the same
    /// `Arc`): another model's bodies and joints are not this one's.
    pub fn restore(&mut self, snapshot: &SimSnapshot) -> Result<(), StateError> {
        if !Arc::ptr_eq(&snapshot.model, &self.model) {
            return Err(StateError::ForeignSnapshot { snapshot: snapshot.model.task.label(), this: self.model.task.label() });
        }
        self.world.restore(&snapshot.world);
        self.control = snapshot.control;
        self.steps = snapshot.steps;
        Ok(())
    }

    /// A copy of this episode that can be run forward without touching it (simulated futures).
    pub fn fork(&self) -> Sim {
        Sim { model: self.model.clone(), world: self.world.clone(), control: self.control, steps: self.steps }
    }
}

/// rapier's velocities (the centre of mass's, and the angular one, both in the world frame) from
/// MuJoCo's free-joint velocity (the body origin's, in the world frame, and the angular one in
/// the body frame). At rest they pass through bit for bit.
fn free_joint_velocity(at: &Pose, origin: [f64; 3], body_frame: [f64; 3], local_com: Vec3) -> (Vec3, Vec3) {
    if body_frame == [0.0; 3] {
        return (Vec3::from(origin), Vec3::from(body_frame));
    }
    let angular = at.rot * Vec3::from(body_frame);
    (Vec3::from(origin) + angular.cross(&(at.rot * local_com)), angular)
}

/// A pose a state writes: finite, and a quaternion that is a rotation. `what` names it in the
/// error ("of object plate_1").
pub(crate) fn check_pose(pos: &[f64; 3], quat_wxyz: &[f64; 4], what: impl Fn() -> String) -> Result<(), StateError> {
    if pos.iter().chain(quat_wxyz).any(|v| !v.is_finite()) {
        return Err(StateError::NotFinite { what: what() });
    }
    if *quat_wxyz == [0.0; 4] {
        return Err(StateError::ZeroQuaternion { what: what() });
    }
    Ok(())
}

fn check_robot_range(arm: &vifo_robots::model::ArmModel, state: &InitState) -> Result<(), StateError> {
    let n_arm = arm.ndofs() - 2;
    check_robot_joints(arm, &state.arm_qpos[..n_arm], &state.gripper_qpos, &state.arm_qvel[..n_arm], &state.gripper_qvel)
}

/// Checks a robot joint state (arm joints, then the two fingers) before it is set: a joint far
/// outside its range would have the joint limit's constraint fling the arm apart in the first
/// step (a little outside is what a soft limit allows), and a speed past the physics guard's
/// ([`MAX_ANGULAR_SPEED`], [`MAX_LINEAR_SPEED`] for the fingers) or a value that is not finite
/// turns the dynamics into NaN. For states loaded from outside: initial states, recordings.
pub fn check_robot_joints(
    arm: &vifo_robots::model::ArmModel,
    arm_qpos: &[f64],
    gripper_qpos: &[f64],
    arm_qvel: &[f64],
    gripper_qvel: &[f64],
) -> Result<(), StateError> {
    let positions = arm_qpos.iter().chain(gripper_qpos);
    let speeds = arm_qvel.iter().map(|v| (v, MAX_ANGULAR_SPEED)).chain(gripper_qvel.iter().map(|v| (v, MAX_LINEAR_SPEED)));
    for (i, (&value, (&speed, max_speed))) in positions.zip(speeds).enumerate() {
        let joint = arm.joint(i);
        if !value.is_finite() || !speed.is_finite() {
            return Err(StateError::NotFinite { what: format!("of robot joint {}", joint.name) });
        }
        let [low, high] = joint.range;
        let slack = (high - low) / 4.0;
        if value < low - slack || value > high + slack {
            return Err(StateError::OutOfRange { joint: joint.name.to_string(), value, range: joint.range });
        }
        if speed.abs() > max_speed {
            return Err(StateError::TooFast { joint: joint.name.to_string(), speed, max: max_speed });
        }
    }
    Ok(())
}

fn check_values(state: &InitState) -> Result<(), StateError> {
    let bad = |what: &str| Err(StateError::NotFinite { what: what.to_string() });
    if state.arm_qpos.iter().chain(&state.arm_qvel).chain(&state.gripper_qpos).chain(&state.gripper_qvel).any(|v| !v.is_finite()) {
        return bad("of the robot");
    }
    for o in &state.objects {
        let what = || format!("of object {}", o.name);
        check_pose(&o.pos, &o.quat_wxyz, what)?;
        if o.lin_vel.iter().chain(&o.ang_vel).any(|v| !v.is_finite()) {
            return bad(&what());
        }
    }
    for j in &state.joints {
        if !j.qpos.is_finite() || !j.qvel.is_finite() {
            return bad(&format!("of joint {} of {}", j.joint, j.owner));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::init_states;

    fn started(suite: &str, index: usize) -> (Sim, &'static init_states::EpisodeStart) {
        let task = crate::task(suite, index).unwrap();
        let start = &init_states::fixed(task).unwrap()[0];
        let mut sim = Sim::new(SceneModel::build(task).unwrap());
        init_states::apply(&mut sim, start).unwrap();
        (sim, start)
    }

    #[test]
    fn a_snapshot_continues_bit_for_bit_and_only_in_its_own_model() {
        let (mut sim, _) = started("libero_goal", 0);
        let hold = Action::hold(1.0);
        sim.step(&hold);
        let snap = sim.snapshot();
        let mut fork = sim.fork();
        (0..3).for_each(|_| sim.step(&hold));
        (0..3).for_each(|_| fork.step(&hold));
        let after = sim.world().fingerprint().0;
        assert_eq!(fork.world().fingerprint().0, after);
        sim.restore(&snap).unwrap();
        (0..3).for_each(|_| sim.step(&hold));
        assert_eq!((sim.world().fingerprint().0, sim.steps()), (after, 4));

        let (mut other, _) = started("libero_goal", 0);
        let before = other.world().fingerprint().0;
        let err = other.restore(&snap).unwrap_err();
        assert!(matches!(err, StateError::ForeignSnapshot { .. }), "{err}");
        assert_eq!(other.world().fingerprint().0, before);
    }

    /// A robot joint far outside its range (which made the first step's joint-limit forces fling
    /// the arm into NaN, and the controller panic) is refused and changes nothing; a little
    /// outside, as a soft limit allows, is loaded.
    #[test]
    fn a_robot_joint_far_outside_its_range_is_refused() {
        let (mut sim, start) = started("libero_goal", 0);
        for (joint, value, refused) in [(0, 1000.0, true), (0, 10.0, true), (3, -1e20, true), (7, 0.0, false), (8, 1.0, true)] {
            let mut state = start.state.clone();
            if joint < 7 {
                state.arm_qpos[joint] = value;
            } else {
                state.gripper_qpos[joint - 7] = value;
            }
            let before = sim.world().fingerprint().0;
            let result = sim.load_state(&state);
            assert_eq!(result.is_err(), refused, "{joint}: {result:?}");
            if let Err(e) = result {
                assert!(matches!(e, StateError::OutOfRange { .. }) && e.to_string().contains("far outside"), "{e}");
                assert_eq!(sim.world().fingerprint().0, before);
            }
        }
        let mut state = start.state.clone();
        state.arm_qpos[6] = 2.9 + 0.1;
        assert!(sim.load_state(&state).is_ok(), "joint 7 a little past its limit of 2.8973");

        // Speeds past the physics guard's (1e300 rad/s made the soft constraints' Hessian NaN).
        for (joint, speed, refused) in [(0, 1e300, true), (2, -301.0, true), (2, 3.0, false), (8, 21.0, true), (8, 0.5, false)] {
            let mut state = start.state.clone();
            if joint < 7 {
                state.arm_qvel[joint] = speed;
            } else {
                state.gripper_qvel[joint - 7] = speed;
            }
            let result = sim.load_state(&state);
            assert_eq!(result.is_err(), refused, "{joint}: {result:?}");
            if let Err(e) = result {
                assert!(matches!(e, StateError::TooFast { .. }) && e.to_string().contains("past the physics guard"), "{e}");
            }
        }
    }

    /// MuJoCo's free joint moves its body origin at `lin_vel` (world frame) and turns at
    /// `ang_vel` in the body frame; rapier keeps the centre of mass's velocity in the world frame.
    #[test]
    fn loaded_velocities_mean_what_mujoco_means() {
        let (mut sim, start) = started("libero_goal", 0);
        let mut state = start.state.clone();
        let object = &mut state.objects[0];
        object.quat_wxyz = [0.5f64.sqrt(), 0.0, 0.0, 0.5f64.sqrt()]; // 90° about z
        object.lin_vel = [0.1, -0.2, 0.05];
        object.ang_vel = [1.0, 0.0, 0.5];
        state.joints[0].qvel = 0.2;
        sim.load_state(&state).unwrap();
        let (owner, joint) = sim.model().entity(&state.joints[0].owner).unwrap();
        let (mb, link) = sim.world().rapier().multibody_joints.get(joint.joint(&state.joints[0].joint).unwrap().1).unwrap();
        assert_eq!(mb.generalized_velocity()[mb.link(link).unwrap().assembly_id()], 0.2, "joint of entity {owner}");
        let (i, _) = sim.model().entity(&state.objects[0].name).unwrap();
        let body = &sim.world().rapier().bodies[sim.model().entities[i].bodies[0]];
        let angvel = vec3(body.angvel());
        assert!((angvel - Vec3::new(0.0, 1.0, 0.5)).norm() < 1e-12, "{angvel:?}");
        let origin = Vec3::from(state.objects[0].pos);
        let com = origin + Pose::from_wxyz(state.objects[0].pos, state.objects[0].quat_wxyz).rot * vec3(body.local_center_of_mass());
        let at_origin = vec3(body.linvel()) + angvel.cross(&(origin - com));
        assert!((at_origin - Vec3::new(0.1, -0.2, 0.05)).norm() < 1e-12, "{at_origin:?}");
    }

    #[test]
    fn a_state_that_does_not_fit_changes_nothing() {
        let (mut sim, start) = started("libero_goal", 0);
        sim.step(&Action::hold(1.0));
        let before = sim.world().fingerprint().0;
        let mut late = start.state.clone();
        late.objects.last_mut().unwrap().name = "teapot_1".into();
        assert_eq!(sim.load_state(&late).unwrap_err(), StateError::UnknownObject("teapot_1".into()));
        let mut zero = start.state.clone();
        zero.objects[0].quat_wxyz = [0.0; 4];
        assert!(matches!(sim.load_state(&zero), Err(StateError::ZeroQuaternion { .. })));
        let mut joint = start.clone();
        joint.fixtures[0].pos[0] += 0.1;
        joint.state.joints.push(crate::init_file::JointState { owner: "nothing".into(), joint: "x".into(), qpos: 0.0, qvel: 0.0 });
        assert!(matches!(init_states::apply(&mut sim, &joint), Err(StateError::UnknownJoint { .. })));
        assert_eq!((sim.world().fingerprint().0, sim.steps()), (before, 1));
    }
}
