//! Skipping the contact constraints that cannot act within the step.
//!
//! rapier keeps a solver contact for every point closer than its prediction distance (5 mm
//! for LIBERO, see `SimParams::prediction_distance`), so that a fast approach is caught
//! before it penetrates. For two rigid bodies such a row is cheap. For a multibody link (the
//! arm's hand and fingers, a cabinet's drawer) every row costs an LU solve of the multibody's
//! mass matrix when it is built, and a pass over all its degrees of freedom at every solver
//! iteration. Around a grasp most of them are far: in the scripted expert's episode of
//! libero_object's first task, at rapier's default 20 mm, 182 multibody solver contacts per
//! step, 25 of them within 1 mm.
//!
//! Rigid bodies keep such rows too, cheaper but many: objects standing a few millimetres apart
//! (bowls beside a plate, a caddy's compartments) pair up at every step. So every collider of
//! a LIBERO scene is flagged, not only the multibody links.
//!
//! [`InertContacts`] drops a manifold of a hooked collider (see [`INERT_CONTACT_HOOKS`]) when
//! all its points stay apart through the step with a margin: their gap exceeds what their
//! approach speed at the start of the step closes, by [`MARGIN`]. Every point that could touch
//! is kept unless the bodies sped up towards each other by more than `MARGIN / dt` (0.25 m/s)
//! within one 2 ms step. Only whole manifolds are dropped: a manifold's friction acts at its
//! points, so dropping some of them would move it.
//!
//! The motion is not bit-identical to keeping them: rapier's speculative rows also push a
//! little before the bodies touch (at rapier's 20 mm, a box falling onto a slab at 0.73 m/s
//! was slowed by 0.016 m/s while still 2.9 mm above it), which MuJoCo, whose contacts start at
//! zero distance, never does. The box then lands and comes to rest within 31 µm of where it did.

use rapier3d::prelude::*;

/// The collider flag that submits a collider's manifolds to [`InertContacts`] (a manifold is
/// submitted when either of its colliders has it).
pub const INERT_CONTACT_HOOKS: ActiveHooks = ActiveHooks::MODIFY_SOLVER_CONTACTS;

/// Gap (m) a manifold's points must keep beyond what their approach speed closes in one step.
pub const MARGIN: f64 = 5e-4;

/// The rapier hook that drops inert manifolds (module docs).
pub struct InertContacts {
    /// The physics step (s).
    pub dt: f64,
}

impl PhysicsHooks for InertContacts {
    fn modify_solver_contacts(&self, context: &mut ContactModificationContext) {
        let (bodies, rb1, rb2) = (context.bodies, context.rigid_body1, context.rigid_body2);
        let Some(manifold) = context.rigid_mut() else { return };
        let normal = *manifold.normal;
        let velocity = |rb: Option<RigidBodyHandle>, at: Vector| rb.and_then(|h| bodies.get(h)).map_or(Vector::ZERO, |b| b.velocity_at_point(at));
        // The gap after the step at the start-of-step velocities, as rapier predicts it
        // (the normal points from the first body to the second: positive speed opens the gap).
        let inert = manifold.solver_contacts.iter().all(|c| {
            let opening = (velocity(rb2, c.anchor2) - velocity(rb1, c.anchor1)).dot(normal);
            c.dist + opening * self.dt > MARGIN
        });
        if inert {
            manifold.solver_contacts.clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{SimParams, World};

    /// A hooked box `gap` above a fixed slab, moving down at `speed`, without gravity; the
    /// solver contacts of its manifold after one step.
    fn solver_contacts_after_one_step(gap: f64, speed: f64) -> usize {
        let mut world = World::new(SimParams::LIBERO);
        let r = world.rapier_mut();
        r.gravity = Vector::ZERO;
        r.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05)), ColliderBuilder::cuboid(1.0, 1.0, 0.05));
        r.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, 0.02 + gap)).linvel(Vector::new(0.0, 0.0, -speed)),
            ColliderBuilder::cuboid(0.02, 0.02, 0.02).active_hooks(INERT_CONTACT_HOOKS),
        );
        world.step();
        let r = world.rapier();
        r.narrow_phase.contact_pairs().flat_map(|p| p.manifolds()).map(|m| m.data.solver_contacts.len()).sum()
    }

    #[test]
    fn a_manifold_that_cannot_close_within_the_step_is_dropped() {
        // 1.5 mm apart at rest: within the 5 mm prediction distance, out of reach.
        assert_eq!(solver_contacts_after_one_step(0.0015, 0.0), 0);
        // Closing at 0.5 m/s: 1 mm within the step, 0.5 mm short of the margin.
        assert_eq!(solver_contacts_after_one_step(0.0015, 0.5), 0);
        assert!(solver_contacts_after_one_step(0.0015, 0.6) > 0, "a point that may touch within the margin was dropped");
        assert!(solver_contacts_after_one_step(0.0003, 0.0) > 0, "a point closer than the margin was dropped");
    }

    /// A box, hooked or not, dropped tumbling onto a slab: its pose 0.8 s later, at rest.
    fn drop_box(hooked: bool) -> Pose {
        let mut world = World::new(SimParams::LIBERO);
        let r = world.rapier_mut();
        r.insert(RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, -0.05)), ColliderBuilder::cuboid(1.0, 1.0, 0.05));
        let hooks = if hooked { INERT_CONTACT_HOOKS } else { ActiveHooks::empty() };
        let (body, _) = r.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.0, 0.05)).angvel(Vector::new(0.4, -0.3, 0.0)),
            ColliderBuilder::cuboid(0.02, 0.02, 0.02).friction(0.8).active_hooks(hooks),
        );
        for _ in 0..400 {
            world.step();
        }
        *world.rapier().bodies[body].position()
    }

    #[test]
    fn a_box_dropped_with_the_hook_comes_to_rest_where_it_did_without() {
        let (with, without) = (drop_box(true), drop_box(false));
        let moved = (with.translation - without.translation).length();
        let turned = with.rotation.angle_between(without.rotation);
        // Measured: 31 µm and 76 µrad at LIBERO's 5 mm prediction distance (5 µm and 4 µrad at
        // rapier's 20 mm): the speculative push before the landing differs, and the tumble
        // carries the difference to the rest pose. The bound is a tenth of the 1 mm fidelity
        // gate against MuJoCo; a hook that ignored the approach speed moves the box by 0.8 mm.
        assert!(moved < 1e-4 && turned < 1e-3, "at rest {moved} m and {turned} rad apart");
    }
}
