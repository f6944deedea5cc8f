//! The simulation world: stepping, contact queries and exact snapshot/restore.

use rapier3d::prelude::*;

use crate::inert::InertContacts;
use crate::{Fingerprint, SimParams};

/// Contact points closer than this (m) count as touching (soft contacts rest with a small
/// penetration; this tolerates a hair of separation too).
pub const TOUCH_DISTANCE: f64 = 5e-4;

/// A rigid-body world stepped at a fixed rate.
///
/// All rapier state is reachable through [`World::rapier`] / [`World::rapier_mut`] so that the
/// crates above (robots, scenes) can insert bodies, colliders and multibodies. Only rapier's
/// workspace buffers live outside the snapshot; everything that affects the next step is in it.
pub struct World {
    rapier: PhysicsWorld,
    params: SimParams,
    time: f64,
    steps: u64,
}

/// The whole mutable state of a [`World`] at one instant.
///
/// Collision shapes are reference-counted inside rapier, so a snapshot shares them with the world
/// it came from; what is copied is the per-body, per-contact and per-joint state.
#[derive(Clone)]
pub struct Snapshot {
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    params: SimParams,
    time: f64,
    steps: u64,
}

impl World {
    /// An empty world with the given parameters.
    pub fn new(params: SimParams) -> Self {
        let mut rapier = PhysicsWorld::new();
        apply_params(&mut rapier, &params);
        World { rapier, params, time: 0.0, steps: 0 }
    }

    /// The parameters this world steps with.
    pub fn params(&self) -> &SimParams {
        &self.params
    }

    /// Simulated time in seconds since creation (or since the restored snapshot's origin).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of physics steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The underlying rapier world.
    pub fn rapier(&self) -> &PhysicsWorld {
        &self.rapier
    }

    /// The underlying rapier world, mutably (to build scenes or apply forces).
    pub fn rapier_mut(&mut self) -> &mut PhysicsWorld {
        &mut self.rapier
    }

    /// Advances the simulation by one physics step (`params().dt`).
    ///
    /// User forces set on bodies before the call act during this step and are then cleared, so
    /// controllers set them afresh every step, as robosuite writes `ctrl` every substep.
    pub fn step(&mut self) {
        self.rapier.step_with_events(&InertContacts { dt: self.params.dt }, &());
        for (_, body) in self.rapier.bodies.iter_mut() {
            if body.user_force() != Vector::ZERO || body.user_torque() != Vector::ZERO {
                body.reset_forces(false);
                body.reset_torques(false);
            }
        }
        self.steps += 1;
        self.time = self.steps as f64 * self.params.dt;
    }

    /// Captures the whole simulation state.
    pub fn snapshot(&self) -> Snapshot {
        let r = &self.rapier;
        Snapshot {
            islands: r.islands.clone(),
            broad_phase: r.broad_phase.clone(),
            narrow_phase: r.narrow_phase.clone(),
            bodies: r.bodies.clone(),
            colliders: r.colliders.clone(),
            impulse_joints: r.impulse_joints.clone(),
            multibody_joints: r.multibody_joints.clone(),
            soft_bodies: r.soft_bodies.clone(),
            params: self.params,
            time: self.time,
            steps: self.steps,
        }
    }

    /// Puts the world back into a captured state. Stepping afterwards gives bit-identical results
    /// to stepping the world the snapshot was taken from.
    ///
    /// rapier's pipelines hold only workspace buffers, but they memoize some selections against
    /// the sets they last saw; fresh pipelines make a restore independent of what ran before.
    pub fn restore(&mut self, snapshot: &Snapshot) {
        let s = snapshot.clone();
        let mut rapier = PhysicsWorld::new();
        rapier.islands = s.islands;
        rapier.broad_phase = s.broad_phase;
        rapier.narrow_phase = s.narrow_phase;
        rapier.bodies = s.bodies;
        rapier.colliders = s.colliders;
        rapier.impulse_joints = s.impulse_joints;
        rapier.multibody_joints = s.multibody_joints;
        rapier.soft_bodies = s.soft_bodies;
        apply_params(&mut rapier, &s.params);
        self.rapier = rapier;
        self.params = s.params;
        self.time = s.time;
        self.steps = s.steps;
    }

    /// A new world in the captured state.
    pub fn from_snapshot(snapshot: &Snapshot) -> Self {
        let mut world = World::new(snapshot.params);
        world.restore(snapshot);
        world
    }

    /// A hash of the exact state bits (poses, velocities, joint coordinates).
    pub fn fingerprint(&self) -> Fingerprint {
        Fingerprint::of(&self.rapier.bodies, &self.rapier.multibody_joints)
    }

    /// True if any collider of `a` touches any collider of `b` (contact points closer than
    /// [`TOUCH_DISTANCE`]), as of the last step. (There is deliberately no collision-only
    /// refresh: rapier's collision pipeline would register contacts against the world's island
    /// bookkeeping without the bodies, which breaks the next step's invariants.) rapier also keeps
    /// speculative contacts for shapes that are merely close; those do not count, as MuJoCo only
    /// reports contacts within the (zero) geom margin.
    pub fn in_contact(&self, a: &[ColliderHandle], b: &[ColliderHandle]) -> bool {
        a.iter().any(|&ca| {
            b.iter().any(|&cb| {
                self.rapier.narrow_phase.contact_pair(ca, cb).is_some_and(|pair| {
                    pair.manifolds().iter().any(|m| m.points.iter().any(|p| p.dist < TOUCH_DISTANCE))
                })
            })
        })
    }
}

impl Clone for World {
    fn clone(&self) -> Self {
        World::from_snapshot(&self.snapshot())
    }
}

fn apply_params(rapier: &mut PhysicsWorld, params: &SimParams) {
    let [gx, gy, gz] = params.gravity;
    rapier.gravity = Vector::new(gx, gy, gz);
    let ip = &mut rapier.integration_parameters;
    ip.dt = params.dt;
    ip.num_solver_iterations = params.solver_iterations;
    ip.num_internal_pgs_iterations = params.pgs_iterations;
    ip.num_internal_stabilization_iterations = params.stabilization_iterations;
    // rapier's lengths are "normalized" by the unit; keep them at their defaults for 1 m.
    let d = IntegrationParameters::default();
    ip.normalized_allowed_linear_error = d.normalized_allowed_linear_error / params.length_unit;
    ip.normalized_max_corrective_velocity = d.normalized_max_corrective_velocity / params.length_unit;
    ip.normalized_prediction_distance = params.prediction_distance / params.length_unit;
    ip.normalized_max_linear_velocity = d.normalized_max_linear_velocity / params.length_unit;
    ip.normalized_contact_recycle_distance = d.normalized_contact_recycle_distance / params.length_unit;
    ip.length_unit = params.length_unit;
    ip.contact_softness.natural_frequency = params.contact_frequency;
    ip.contact_softness.damping_ratio = params.contact_damping_ratio;
    ip.static_contact_softness.natural_frequency = params.static_contact_frequency;
    ip.static_contact_softness.damping_ratio = params.contact_damping_ratio;
    // Contact recycling reuses a pair's manifold while the pair barely moves; with a multibody
    // gripper hovering next to an object it left stale constraints that stalled the arm
    // (observed: a Panda unable to lower its open fingers around a can). Fresh contacts every
    // step cost little at LIBERO's scale.
    ip.contact_recycling = false;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few boxes falling on a table and knocking into each other.
    fn pile() -> World {
        let mut world = World::new(SimParams::LIBERO);
        let r = world.rapier_mut();
        r.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05)),
            ColliderBuilder::cuboid(1.0, 1.0, 0.05),
        );
        for i in 0..6 {
            let f = f64::from(i);
            r.insert(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(0.03 * f, 0.02 * f, 0.05 + 0.06 * f))
                    .angvel(Vector::new(0.3 * f, -0.2, 0.1)),
                ColliderBuilder::cuboid(0.025, 0.02, 0.025).friction(0.8),
            );
        }
        world
    }

    #[test]
    fn same_inputs_give_the_same_bits() {
        let (mut a, mut b) = (pile(), pile());
        for _ in 0..300 {
            a.step();
            b.step();
        }
        assert_eq!(a.fingerprint(), b.fingerprint());
    }

    #[test]
    fn restoring_a_snapshot_continues_bit_identically() {
        let mut reference = pile();
        let mut interrupted = pile();
        for _ in 0..150 {
            reference.step();
            interrupted.step();
        }
        let snap = interrupted.snapshot();
        // Wander off, then come back.
        for _ in 0..37 {
            interrupted.step();
        }
        assert_ne!(interrupted.fingerprint(), reference.fingerprint());
        interrupted.restore(&snap);
        let mut copy = World::from_snapshot(&snap);
        for _ in 0..150 {
            reference.step();
            interrupted.step();
            copy.step();
        }
        assert_eq!(interrupted.fingerprint(), reference.fingerprint());
        assert_eq!(copy.fingerprint(), reference.fingerprint());
        assert_eq!(copy.time(), reference.time());
    }

    #[test]
    fn boxes_come_to_rest_on_the_table() {
        let mut world = pile();
        for _ in 0..1500 {
            world.step();
        }
        for (_, body) in world.rapier().bodies.iter() {
            if body.is_dynamic() {
                assert!(body.translation().z > 0.0, "a box fell through the table");
                assert!(body.linvel().length() < 0.05, "a box is still moving: {:?}", body.linvel());
            }
        }
    }

    /// A two-link pendulum on a fixed base, swinging under gravity.
    fn pendulum() -> (World, MultibodyJointHandle) {
        let mut world = World::new(SimParams::LIBERO);
        let r = world.rapier_mut();
        let base = r.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, 1.0)));
        let upper = r.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.0, 1.0)), ColliderBuilder::capsule_x(0.1, 0.02)).0;
        let lower = r.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.4, 0.0, 1.0)), ColliderBuilder::capsule_x(0.1, 0.02)).0;
        let hinge = |x: f64| RevoluteJointBuilder::new(Vector::Y).local_anchor1(Vector::new(x, 0.0, 0.0)).local_anchor2(Vector::new(-0.1, 0.0, 0.0));
        r.multibody_joints.insert(base, upper, hinge(0.0), true).expect("a tree");
        let elbow = r.multibody_joints.insert(upper, lower, hinge(0.1), true).expect("a tree");
        (world, elbow)
    }

    /// The step skips its opening forward kinematics while the last step's still holds (the
    /// vendored rapier's patch): a joint moved through the multibody set between steps must end it.
    #[test]
    fn a_joint_moved_between_steps_is_stepped_from_its_new_pose() {
        let (mut moved, elbow) = pendulum();
        for _ in 0..50 {
            moved.step();
        }
        let mut kinematics_by_hand = World::from_snapshot(&moved.snapshot());
        let displace = |world: &mut World, by_hand: bool| {
            let r = world.rapier_mut();
            let (mb, _) = r.multibody_joints.get_mut(elbow).expect("the elbow");
            let mut disp = vec![0.0; mb.ndofs()];
            disp[1] = 0.3;
            mb.apply_displacements(&disp);
            if by_hand {
                mb.forward_kinematics(&r.bodies, true);
                mb.update_rigid_bodies(&mut r.bodies, true);
            }
        };
        displace(&mut moved, false);
        displace(&mut kinematics_by_hand, true);
        for _ in 0..20 {
            moved.step();
            kinematics_by_hand.step();
        }
        assert_eq!(moved.fingerprint(), kinematics_by_hand.fingerprint());
    }

    #[test]
    fn contact_query_sees_resting_boxes() {
        let mut world = pile();
        for _ in 0..500 {
            world.step();
        }
        let handles: Vec<ColliderHandle> = world.rapier().colliders.iter().map(|(h, _)| h).collect();
        let table = [handles[0]];
        assert!(world.in_contact(&table, &handles[1..]));
        assert!(!world.in_contact(&table, &table));
    }
}
