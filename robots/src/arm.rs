//! An [`ArmModel`] instantiated in a physics [`World`] as a rapier multibody.
//!
//! Bodies welded to their parent (link0 to the base, hand and gripper to link7, pad tips to the
//! fingers) are merged into one rapier body, so the multibody has exactly one link per degree of
//! freedom. Joint damping and armature are rapier's multibody per-dof parameters, which integrate
//! them as MuJoCo's Euler step does (damping implicitly), and so is frictionloss unless the joint
//! is `soft` (then it is MuJoCo's soft row, [`crate::limits`]). Actuator efforts are
//! applied as equal and opposite torque (hinges) or force (slides, at a common point) pairs on the
//! two bodies a joint connects, which is exactly a generalized force on that joint.

use std::sync::Arc;

use vifo_physics::World;
use vifo_physics::inert::INERT_CONTACT_HOOKS;
use vifo_physics::rapier::prelude::*;

use crate::contact;
use crate::convert::{dmat3, rapier_pose, vector};
use crate::joint;
use crate::dynamics::{ArmDynamics, BodyPoses};
use crate::model::{ArmModel, ContactRole, ContactShape, Inertial, JointKind, Shape};
use crate::spatial::{Coords, Mat3, Pose, Vec3};

/// A collider the arm put into the world.
#[derive(Clone, Debug)]
pub struct ArmCollider {
    pub handle: ColliderHandle,
    /// Model body the shape belongs to.
    pub body: usize,
    pub name: &'static str,
    pub role: ContactRole,
}

/// Joint positions and velocities (arm joints then fingers).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointState<const N: usize> {
    pub q: Coords<N>,
    pub qd: Coords<N>,
}

/// An arm living in a world. Holds only handles; the state is in the world.
#[derive(Clone, Debug)]
pub struct ArmInstance<const N: usize> {
    dynamics: ArmDynamics<N>,
    base: Pose,
    /// For each model body, the model body whose rapier body carries it.
    owner: Vec<usize>,
    /// rapier body of each owner (entries of non-owners repeat their owner's).
    rigid_body: Vec<RigidBodyHandle>,
    joints: [MultibodyJointHandle; N],
    /// Index of each dof in the multibody's generalized coordinates.
    assembly: [usize; N],
    colliders: Vec<ArmCollider>,
}

pub(crate) fn shape(s: &ContactShape) -> SharedShape {
    match *s {
        ContactShape::Primitive(s) => primitive(s),
        ContactShape::Hull(points) => hull(points),
    }
}

pub(crate) fn hull(points: &[[f64; 3]]) -> SharedShape {
    let points: Vec<_> = points.iter().map(|p| Vector::new(p[0], p[1], p[2])).collect();
    SharedShape::convex_hull(&points).expect("a fitted hull has volume (robots' tests build every one)")
}

fn primitive(s: Shape) -> SharedShape {
    match s {
        Shape::Box { half } => SharedShape::cuboid(half[0], half[1], half[2]),
        Shape::Capsule { radius, half_height } => SharedShape::capsule_z(half_height, radius),
        Shape::Cylinder { radius, half_height } => {
            // rapier cylinders stand along y; ours along z.
            SharedShape::cylinder(half_height, radius)
        }
        Shape::Sphere { radius } => SharedShape::ball(radius),
    }
}

/// rapier's cylinder axis is y; rotate local frames of z-axis cylinders accordingly.
pub(crate) fn shape_frame(s: &ContactShape, local: &Pose) -> Pose {
    match s {
        ContactShape::Primitive(Shape::Cylinder { .. }) => {
            let x90 = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0);
            Pose::new(local.pos, local.rot * x90)
        }
        _ => *local,
    }
}

impl<const N: usize> ArmInstance<N> {
    /// Inserts the arm with its base at `base` (world frame), every joint at zero.
    pub fn insert(world: &mut World, model: Arc<ArmModel>, base: Pose) -> Self {
        let gravity = world.params().gravity;
        let dynamics = ArmDynamics::<N>::new(model.clone(), gravity);
        let bodies = &model.bodies;
        let nb = bodies.len();
        let mut owner = vec![0usize; nb];
        for (b, body) in bodies.iter().enumerate() {
            owner[b] = match (body.joint.is_some(), body.parent) {
                (true, _) | (_, None) => b,
                (false, Some(p)) => owner[p],
            };
        }
        // Pose of every body relative to its owner (fixed, since only welds are merged).
        let zero = dynamics.forward(&Pose::IDENTITY, &Coords::<N>::zeros());
        let in_owner = |b: usize| zero.poses[owner[b]].inverse().mul(&zero.poses[b]);

        // Merged mass properties per owner.
        let mut mass: Vec<Inertial> = bodies.iter().map(|_| Inertial::diag(0.0, [0.0; 3], [0.0; 3])).collect();
        for b in 0..nb {
            let o = owner[b];
            mass[o] = mass[o].merged(&bodies[b].inertial, &in_owner(b));
        }

        let r = world.rapier_mut();
        let mut rigid_body = vec![RigidBodyHandle::invalid(); nb];
        let mut joints = Vec::with_capacity(N);
        for b in 0..nb {
            if owner[b] != b {
                rigid_body[b] = rigid_body[owner[b]];
                continue;
            }
            let world_pose = base.mul(&zero.poses[b]);
            let builder = if bodies[b].parent.is_none() { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() };
            let m = &mass[b];
            let mprops = MassProperties::with_inertia_matrix(vector(&m.com), m.mass, dmat3(&m.inertia));
            let handle = r.bodies.insert(
                builder.pose(rapier_pose(&world_pose)).additional_mass_properties(mprops).can_sleep(false),
            );
            rigid_body[b] = handle;
            if let (Some(joint), Some(parent)) = (&bodies[b].joint, bodies[b].parent) {
                let child_in_parent = in_owner(parent).mul(&bodies[b].local);
                let range = joint.soft.is_none().then_some(joint.range);
                let generic = joint::one_dof(joint.kind, &child_in_parent, &Vec3::zeros(), &joint.axis, range);
                let handle = r
                    .multibody_joints
                    .insert(rigid_body[owner[parent]], handle, generic, true)
                    .expect("an arm is a tree");
                joints.push(handle);
            }
        }
        let joints: [MultibodyJointHandle; N] = joints.try_into().expect("one joint per dof");

        // Settle the multibody's root type (a fixed base is a 6-dof free root until told
        // otherwise), so that dof indices are final, then set the passive joint parameters.
        let (mb, _) = r.multibody_joints.get_mut(joints[0]).expect("arm multibody");
        mb.forward_kinematics(&r.bodies, true);
        let mut assembly = [0usize; N];
        for (i, &jh) in joints.iter().enumerate() {
            let spec = model.joint(i);
            let (mb, link) = r.multibody_joints.get_mut(jh).expect("arm joint");
            let dof = mb.link(link).expect("link").assembly_id();
            assembly[i] = dof;
            // Self contacts on: which shapes touch is up to their groups (fingers and pads).
            mb.set_self_contacts_enabled(true);
            mb.damping_mut()[dof] = spec.damping;
            mb.armature_mut()[dof] = spec.armature;
            // A soft joint's dry friction is a row of MuJoCo's constraint instead ([`crate::limits`]).
            mb.frictions_mut()[dof] = if spec.soft.is_some() { 0.0 } else { spec.frictionloss };
        }

        let mut colliders = Vec::new();
        for (b, body) in bodies.iter().enumerate() {
            for c in &body.colliders {
                let local = in_owner(b).mul(&shape_frame(&c.shape, &c.local));
                let collider = ColliderBuilder::new(shape(&c.shape))
                    .position(rapier_pose(&local))
                    .density(0.0)
                    .friction(c.friction)
                    .friction_combine_rule(CoefficientCombineRule::Max)
                    .collision_groups(contact::groups(c.role, model.self_contact))
                    .solver_groups(contact::groups(c.role, model.self_contact))
                    .active_hooks(INERT_CONTACT_HOOKS);
                let handle = r.colliders.insert_with_parent(collider, rigid_body[b], &mut r.bodies);
                colliders.push(ArmCollider { handle, body: b, name: c.name, role: c.role });
            }
        }
        ArmInstance { dynamics, base, owner, rigid_body, joints, assembly, colliders }
    }

    pub fn dynamics(&self) -> &ArmDynamics<N> {
        &self.dynamics
    }

    pub fn model(&self) -> &ArmModel {
        self.dynamics.model()
    }

    /// World pose of the base.
    pub fn base(&self) -> &Pose {
        &self.base
    }

    pub fn colliders(&self) -> &[ArmCollider] {
        &self.colliders
    }

    /// The rapier body carrying model body `b`.
    pub fn rigid_body(&self, b: usize) -> RigidBodyHandle {
        self.rigid_body[b]
    }

    /// Current joint positions and velocities, read from the multibody.
    pub fn state(&self, world: &World) -> JointState<N> {
        let (mb, _) = world.rapier().multibody_joints.get(self.joints[0]).expect("arm multibody");
        let velocity = mb.generalized_velocity();
        let mut q = Coords::<N>::zeros();
        let mut qd = Coords::<N>::zeros();
        for (i, &jh) in self.joints.iter().enumerate() {
            let (mb, link_id) = world.rapier().multibody_joints.get(jh).expect("arm joint");
            let coords = mb.link(link_id).expect("link").joint().coords();
            q[i] = joint::coordinate(self.model().joint(i).kind, &coords);
            qd[i] = velocity[self.assembly[i]];
        }
        JointState { q, qd }
    }

    /// Puts the joints at `state` (positions and velocities) and moves the link bodies there.
    pub fn set_state(&self, world: &mut World, state: &JointState<N>) {
        let current = self.state(world);
        let r = world.rapier_mut();
        let (mb, _) = r.multibody_joints.get_mut(self.joints[0]).expect("arm multibody");
        let mut disp = vec![0.0; mb.ndofs()];
        let mut velocity = mb.generalized_velocity_mut();
        for i in 0..N {
            disp[self.assembly[i]] = state.q[i] - current.q[i];
            velocity[self.assembly[i]] = state.qd[i];
        }
        mb.apply_displacements(&disp);
        mb.forward_kinematics(&r.bodies, false);
        mb.update_rigid_bodies(&mut r.bodies, true);
    }

    /// World poses of all model bodies at the world's current joint state (our kinematics).
    pub fn body_poses(&self, world: &World) -> BodyPoses {
        self.dynamics.forward(&self.base, &self.state(world).q)
    }

    /// Applies generalized forces `tau` (N·m for hinges, N for slides) for the next physics step.
    pub fn apply_generalized_forces(&self, world: &mut World, poses: &BodyPoses, tau: &Coords<N>) {
        let model = self.dynamics.model();
        let bodies = &mut world.rapier_mut().bodies;
        for i in 0..N {
            if tau[i] == 0.0 {
                continue;
            }
            let b = model.dofs[i];
            let parent = model.bodies[b].parent.expect("jointed bodies have a parent");
            let joint = model.joint(i);
            let pose = &poses.poses[b];
            let axis = vector(&(pose.rot * joint.axis));
            let (child_rb, parent_rb) = (self.rigid_body[b], self.rigid_body[self.owner[parent]]);
            match joint.kind {
                JointKind::Hinge => {
                    bodies[child_rb].add_torque(axis * tau[i], true);
                    if bodies[parent_rb].is_dynamic() {
                        bodies[parent_rb].add_torque(-axis * tau[i], true);
                    }
                }
                JointKind::Slide => {
                    let at = vector(&pose.pos);
                    bodies[child_rb].add_force_at_point(axis * tau[i], at, true);
                    if bodies[parent_rb].is_dynamic() {
                        bodies[parent_rb].add_force_at_point(-axis * tau[i], at, true);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panda::{self, Mount};
    use crate::soft_contact::SoftContacts;
    use vifo_physics::SimParams;

    fn pose_of(world: &World, h: RigidBodyHandle) -> Pose {
        let p = world.rapier().bodies[h].position();
        let m = vifo_physics::rapier::glamx::DMat3::from_quat(p.rotation);
        let rot = Mat3::new(m.x_axis.x, m.y_axis.x, m.z_axis.x, m.x_axis.y, m.y_axis.y, m.z_axis.y, m.x_axis.z, m.y_axis.z, m.z_axis.z);
        Pose::new(Vec3::new(p.translation.x, p.translation.y, p.translation.z), rot)
    }

    #[test]
    fn rapier_links_follow_our_kinematics() {
        let mut world = World::new(SimParams::LIBERO);
        let base = panda::base_pose(Mount::Pedestal, [-0.66, 0.0, 0.0]);
        let arm = ArmInstance::<9>::insert(&mut world, panda::model(Mount::Pedestal), base);
        let q = Coords::<9>::from_column_slice(&[0.3, -0.4, 0.2, -2.0, 0.5, 2.0, 0.1, 0.03, -0.01]);
        arm.set_state(&mut world, &JointState { q, qd: Coords::zeros() });
        let read = arm.state(&world);
        assert!((read.q - q).norm() < 1e-12, "{:?}", read.q);
        let poses = arm.dynamics().forward(&base, &q);
        for &b in &arm.model().dofs {
            let ours = poses.poses[b];
            let theirs = pose_of(&world, arm.rigid_body(b));
            assert!((ours.pos - theirs.pos).norm() < 1e-9, "{}: {:?} vs {:?}", arm.model().bodies[b].name, ours.pos, theirs.pos);
            assert!((ours.rot - theirs.rot).norm() < 1e-9, "{} rotation", arm.model().bodies[b].name);
        }
    }

    /// Distance between the hand's and link 5's colliders with the arm at `q` (fingers open), and
    /// the self contacts found there.
    fn hand_to_forearm(q: [f64; 7]) -> (f64, Vec<[&'static str; 2]>) {
        let mut world = World::new(SimParams::LIBERO);
        let base = panda::base_pose(Mount::Pedestal, [-0.66, 0.0, 0.0]);
        let arm = ArmInstance::<9>::insert(&mut world, panda::model(Mount::Pedestal), base);
        let mut full = Coords::<9>::zeros();
        full.fixed_rows_mut::<7>(0).copy_from_slice(&q);
        (full[7], full[8]) = (0.04, -0.04);
        arm.set_state(&mut world, &JointState { q: full, qd: Coords::zeros() });
        let r = world.rapier();
        let at = |name: &str| {
            let c = arm.colliders().iter().find(|c| c.name == name).expect("collider");
            let collider = &r.colliders[c.handle];
            let body = &r.bodies[collider.parent().expect("attached")];
            (*body.position() * *collider.position_wrt_parent().expect("attached"), collider.shared_shape().clone())
        };
        let ((p1, s1), (p2, s2)) = (at("link5"), at("hand"));
        let distance = vifo_physics::rapier::parry::query::distance(&p1, &*s1, &p2, &*s2).expect("convex shapes").distance;
        let bodies = &arm.model().bodies;
        let touching = SoftContacts::new(arm.dynamics()).at(&arm.dynamics().forward(&base, &full), &world);
        (distance, touching.iter().map(|c| c.bodies.map(|b| b.map_or("scene", |b| bodies[b].name))).collect())
    }

    /// MuJoCo's `j5_hi_j2_hi` limit sequence (`xval/record_limits.py`) folds the hand onto the
    /// forearm: at record 62 its hand's hull is 0.5 mm into link 5's and joint 6 stops there; four
    /// records before, nothing touches. Our fitted hulls (a little inside MuJoCo's) meet there too.
    #[test]
    fn the_hand_meets_the_forearm_where_mujocos_hulls_do() {
        let (touching, contacts) = hand_to_forearm([-0.2631, 0.6564, -0.2114, -2.2724, 1.5328, 0.6566, -0.4376]);
        let (before, none) = hand_to_forearm([-0.2315, 0.5651, -0.2683, -2.2925, 1.4757, 0.7891, -0.4364]);
        println!("hand to link 5: {:.2} mm at MuJoCo's first contact, {:.2} mm four records before", touching * 1e3, before * 1e3);
        assert!(touching < 0.001, "{touching}");
        assert!(before > 0.005, "{before}");
        assert!(contacts.contains(&["link5", "right_gripper"]), "{contacts:?}");
        assert!(none.is_empty(), "{none:?}");
    }
}
