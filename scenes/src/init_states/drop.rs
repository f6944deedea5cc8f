//! Lowering a placed object straight down onto whatever is below it, by sweeping its collision
//! shapes (parry's shape casting). This puts an object just above its support whatever that is
//! (table, stove plate, cabinet top, drawer floor, another object) without interpenetration,
//! where LIBERO spawns at a nominal height and lets MuJoCo drop it a few centimetres.

use vifo_physics::rapier::parry::bounding_volume::BoundingVolume;
use vifo_physics::rapier::parry::query::{ShapeCastOptions, ShapeCastStatus, cast_shapes, intersection_test};
use vifo_physics::rapier::math::Pose as RPose;
use vifo_physics::rapier::prelude::*;
use vifo_robots::convert::rapier_pose;
use vifo_robots::spatial::Pose;

use crate::sim::Sim;

/// How an object posed somewhere relates to what is below it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drop {
    /// It can move down this far before touching something.
    Falls(f64),
    /// Nothing below within the search distance.
    NothingBelow,
    /// It already overlaps something.
    Overlaps,
}

/// A collider another object may rest on or must keep clear of.
#[derive(Clone, Copy, Debug)]
pub struct Obstacle {
    pub collider: ColliderHandle,
    /// The pose of the collider's body when it is not (yet) where the world has it: objects
    /// placed earlier in the same draw.
    pub body: Option<Pose>,
}

/// World pose of an obstacle, from its body's pose (a collider's own cached pose lags until
/// the next collision update).
fn obstacle_pose(r: &PhysicsWorld, o: &Obstacle) -> RPose {
    let c = &r.colliders[o.collider];
    let local = c.position_wrt_parent().copied().unwrap_or_default();
    match (o.body, c.parent()) {
        (Some(body), _) => rapier_pose(&body) * local,
        (None, Some(body)) => *r.bodies[body].position() * local,
        (None, None) => *c.position(),
    }
}

/// World poses of an object's colliders with its body at `pose`.
fn posed_colliders<'a>(sim: &'a Sim, entity: usize, pose: &Pose) -> impl Iterator<Item = (&'a Collider, RPose)> + 'a {
    let r = sim.world().rapier();
    let at = rapier_pose(pose);
    sim.model().entities[entity].colliders.iter().map(move |&h| {
        let c = &r.colliders[h];
        (c, at * c.position_wrt_parent().copied().unwrap_or_default())
    })
}

/// Sweeps the colliders of movable `entity`, posed at `pose`, down by at most `max` metres
/// against `obstacles`.
pub fn drop_onto(sim: &Sim, entity: usize, pose: &Pose, obstacles: &[Obstacle], max: f64) -> Drop {
    let r = sim.world().rapier();
    let down = Vector::new(0.0, 0.0, -1.0);
    let options = ShapeCastOptions { max_time_of_impact: max, target_distance: 0.0, stop_at_penetration: true, compute_impact_geometry_on_penetration: false };
    let mut nearest: Option<f64> = None;
    for (c, p1) in posed_colliders(sim, entity, pose) {
        let swept = c.shape().compute_aabb(&p1);
        for obstacle in obstacles {
            let o = &r.colliders[obstacle.collider];
            let p2 = obstacle_pose(r, obstacle);
            let b = o.shape().compute_aabb(&p2);
            // Only what lies under the footprint, from the object's top down to `max` below.
            let apart = b.maxs.x < swept.mins.x || b.mins.x > swept.maxs.x || b.maxs.y < swept.mins.y || b.mins.y > swept.maxs.y;
            if apart || b.mins.z > swept.maxs.z || b.maxs.z < swept.mins.z - max {
                continue;
            }
            match cast_shapes(&p1, down, c.shape(), &p2, Vector::ZERO, o.shape(), options) {
                Ok(Some(hit)) if hit.status == ShapeCastStatus::PenetratingOrWithinTargetDist => return Drop::Overlaps,
                Ok(Some(hit)) => nearest = Some(nearest.map_or(hit.time_of_impact, |n| n.min(hit.time_of_impact))),
                Ok(None) => {}
                // Every shape pair of the catalog (boxes, capsules) is supported.
                Err(_) => return Drop::Overlaps,
            }
        }
    }
    nearest.map_or(Drop::NothingBelow, Drop::Falls)
}

/// Whether the colliders of `entity`, posed at `pose`, intersect any of `others`.
pub fn overlaps(sim: &Sim, entity: usize, pose: &Pose, others: &[Obstacle]) -> bool {
    let r = sim.world().rapier();
    posed_colliders(sim, entity, pose).any(|(c, p1)| {
        let a = c.shape().compute_aabb(&p1);
        others.iter().any(|other| {
            let o = &r.colliders[other.collider];
            let p2 = obstacle_pose(r, other);
            // Unsupported shape pairs count as touching, so nothing is placed into them.
            o.shape().compute_aabb(&p2).intersects(&a) && intersection_test(&p1, c.shape(), &p2, o.shape()).map_or(true, |i| i.intersecting)
        })
    })
}

/// Lowest point of an object's collision shapes with its body at `pose`.
pub fn lowest_point(sim: &Sim, entity: usize, pose: &Pose) -> f64 {
    posed_colliders(sim, entity, pose).map(|(c, p)| c.shape().compute_aabb(&p).mins.z).fold(f64::INFINITY, f64::min)
}

/// Highest point of an object's collision shapes with its body at `pose`.
pub fn highest_point(sim: &Sim, entity: usize, pose: &Pose) -> f64 {
    posed_colliders(sim, entity, pose).map(|(c, p)| c.shape().compute_aabb(&p).maxs.z).fold(f64::NEG_INFINITY, f64::max)
}
