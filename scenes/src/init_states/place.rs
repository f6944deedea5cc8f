//! LIBERO's placement rules for movable objects, one init atom at a time.
//!
//! - `(On obj workspace_region)`: x, y from the problem class's region sampler. Tabletop and
//!   Floor use `TableRegionSampler` with `ensure_object_boundary_in_range`: the range shrinks by
//!   the object's horizontal radius on each side, and for regions narrower than the object the
//!   bounds cross, so the draw spans `[max − r, min + r]` (numpy's `uniform(low, high)` with
//!   `low > high`). Kitchen, living room and study sample the range as it is. A draw closer to an
//!   earlier object than the sum of their horizontal radii is rejected (up to [`TRIES`] times).
//! - `(On obj site)`: x, y uniform within ± half the site's half-size around the site, shrunk by
//!   the horizontal radius the same way (world axes, as LIBERO's site sampler adds them).
//! - `(In obj site)`: at the site.
//! - `(On obj other)`: at the other object's x, y.
//!
//! Orientation is the category's spawn rotation ([`super::orientation`]), turned by the
//! region's yaw range if it has one. Height is ours: the object is swept straight down from a
//! little above onto its support only (the table, the site's owner, the object below; see
//! [`super::drop`]) and left [`CLEARANCE`] above it. LIBERO lets footprints overlap (a bowl's
//! rim over a plate's) as long as the shapes do not; so do we: a draw is rejected if the object
//! would intersect anything else where it lands, or its support is not below it.

use rand::{Rng, RngExt};
use vifo_robots::spatial::{Mat3, Pose, Vec3};

use super::drop::{Drop, Obstacle, drop_onto, highest_point, lowest_point, overlaps};
use super::orientation::{spawn_quat, spawn_rotation};
use super::plan::{Placement, Support};
use crate::sim::{RegionPlace, Sim};
use crate::task::ProblemClass;

/// Draws per object before giving up (LIBERO's samplers retry 5000 times).
pub const TRIES: usize = 5000;
/// Gap left under a lowered object; it settles onto its support in the first physics steps.
pub const CLEARANCE: f64 = 0.001;
/// How far above its nominal support an object starts its sweep down.
const LIFT: f64 = 0.05;
/// The longest sweep down.
const REACH: f64 = 0.3;

/// Whose collider an obstacle is.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Owner {
    Arena,
    Entity(usize),
}

/// The objects placed so far in one draw of a state, and what later objects rest on or must
/// keep clear of.
pub struct Layout {
    /// Colliders of the arena, the fixtures and the placed objects.
    obstacles: Vec<(Owner, Obstacle)>,
    /// Workspace-placed objects and fixtures: (x, y, horizontal radius) for LIBERO's overlap test.
    footprints: Vec<(f64, f64, f64)>,
    /// Placed objects: entity and pose.
    pub placed: Vec<(usize, Pose)>,
}

impl Layout {
    /// The arena and every fixture, as posed in `sim` (fixtures and joints set).
    pub fn new(sim: &Sim) -> Layout {
        let model = sim.model();
        let mut obstacles: Vec<(Owner, Obstacle)> = model.arena.iter().map(|&collider| (Owner::Arena, Obstacle { collider, body: None })).collect();
        let mut footprints = Vec::new();
        for (i, e) in model.entities.iter().enumerate().filter(|(_, e)| !e.movable()) {
            obstacles.extend(e.colliders.iter().map(|&collider| (Owner::Entity(i), Obstacle { collider, body: None })));
            let p = sim.entity_pose(i).pos;
            footprints.push((p.x, p.y, e.model.horizontal_radius));
        }
        Layout { obstacles, footprints, placed: Vec::new() }
    }

    fn pose_of(&self, entity: usize) -> Option<Pose> {
        self.placed.iter().find(|(e, _)| *e == entity).map(|(_, p)| *p)
    }

    /// The colliders of `support`, then everything else.
    fn split(&self, support: Owner) -> (Vec<Obstacle>, Vec<Obstacle>) {
        let (on, off): (Vec<_>, Vec<_>) = self.obstacles.iter().copied().partition(|(owner, _)| *owner == support);
        (on.into_iter().map(|(_, o)| o).collect(), off.into_iter().map(|(_, o)| o).collect())
    }

    /// Places one object by its rule; `Err` says why no draw worked.
    pub fn place(&mut self, sim: &Sim, p: &Placement, rng: &mut impl Rng) -> Result<(), String> {
        let model = sim.model().clone();
        let e = &model.entities[p.entity];
        let radius = e.model.horizontal_radius;
        let base = spawn_quat(&e.category).ok_or_else(|| format!("{}: no spawn orientation for category {}", p.atom, e.category))?;
        let site = |key: &str| {
            let place = model.region(key).map(|r| &r.place);
            match (sim.region_box(key), place) {
                (Some(b), Some(RegionPlace::Site { entity, .. })) => Ok((b, Owner::Entity(*entity))),
                _ => Err(format!("{}: {key} is not a site of the scene", p.atom)),
            }
        };
        // Placements inside a site or on an object draw nothing, so one try tells.
        let tries = if matches!(p.support, Support::InSite { .. } | Support::OnObject { .. }) { 1 } else { TRIES };
        let mut last = "no draw";
        for _ in 0..tries {
            let (x, y, rot, floor, support) = match &p.support {
                Support::Workspace { region } => {
                    let region = &model.task.regions[*region];
                    let [x0, y0, x1, y1] = region.ranges[0];
                    let r = if shrinks(model.class.problem) { radius } else { 0.0 };
                    let off = model.class.workspace_offset;
                    let x = off[0] + between(x0 + r, x1 - r, rng);
                    let y = off[1] + between(y0 + r, y1 - r, rng);
                    if self.footprints.iter().any(|&(fx, fy, fr)| ((x - fx).powi(2) + (y - fy).powi(2)).sqrt() <= fr + radius) {
                        last = "too close to an earlier object";
                        continue;
                    }
                    let yaw = match region.yaw_rotation {
                        Some([a, b]) if b > a => between(a, b, rng),
                        Some([a, _]) => a,
                        None => 0.0,
                    };
                    (x, y, spawn_rotation(base, yaw), model.class.support_z(), Owner::Arena)
                }
                Support::OnSite { key } => {
                    let (b, owner) = site(key)?;
                    let (sx, sy) = (b.half_size.x / 2.0, b.half_size.y / 2.0);
                    let x = b.pose.pos.x + between(-sx + radius, sx - radius, rng);
                    let y = b.pose.pos.y + between(-sy + radius, sy - radius, rng);
                    (x, y, spawn_rotation(base, 0.0), b.pose.pos.z, owner)
                }
                Support::InSite { key } => {
                    let (b, owner) = site(key)?;
                    // Start from the middle of the box, below anything that closes it from above.
                    (b.pose.pos.x, b.pose.pos.y, spawn_rotation(base, 0.0), b.pose.pos.z - LIFT, owner)
                }
                Support::OnObject { below } => {
                    let at = self.pose_of(*below).ok_or_else(|| format!("{}: the object below is not placed yet", p.atom))?;
                    (at.pos.x, at.pos.y, spawn_rotation(base, 0.0), highest_point(sim, *below, &at), Owner::Entity(*below))
                }
            };
            match self.lower(sim, p.entity, x, y, rot, floor + LIFT, support) {
                Ok(at) => {
                    if matches!(p.support, Support::Workspace { .. }) {
                        self.footprints.push((x, y, radius));
                    }
                    let placed = Owner::Entity(p.entity);
                    self.obstacles.extend(e.colliders.iter().map(|&collider| (placed, Obstacle { collider, body: Some(at) })));
                    self.placed.push((p.entity, at));
                    return Ok(());
                }
                Err(why) => last = why,
            }
        }
        Err(format!("{}: no valid draw in {tries} tries (last: {last})", p.atom))
    }

    /// Where the object comes to rest when swept down onto `support` from where its lowest point
    /// is at `start_z`, if it touches nothing else there.
    #[allow(clippy::too_many_arguments)]
    fn lower(&self, sim: &Sim, entity: usize, x: f64, y: f64, rot: Mat3, start_z: f64, support: Owner) -> Result<Pose, &'static str> {
        let upright = Pose::new(Vec3::new(x, y, 0.0), rot);
        let start = Pose::new(Vec3::new(x, y, start_z - lowest_point(sim, entity, &upright)), rot);
        let (below, others) = self.split(support);
        match drop_onto(sim, entity, &start, &below, REACH) {
            Drop::Falls(d) => {
                let at = Pose::new(start.pos - Vec3::new(0.0, 0.0, d - CLEARANCE), rot);
                if overlaps(sim, entity, &at, &others) { Err("overlaps another object or fixture") } else { Ok(at) }
            }
            Drop::NothingBelow => Err("its support is not below it"),
            Drop::Overlaps => Err("starts inside its support"),
        }
    }
}

/// Whether the problem class's region sampler keeps the object's footprint inside the range.
fn shrinks(problem: ProblemClass) -> bool {
    matches!(problem, ProblemClass::Tabletop | ProblemClass::Floor | ProblemClass::PiperTabletop)
}

/// numpy's `uniform(low, high)`: `low + (high − low)·u`, also when `low > high`.
fn between(low: f64, high: f64, rng: &mut impl Rng) -> f64 {
    low + (high - low) * rng.random::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn crossed_bounds_sample_the_widened_interval() {
        // A 2 cm region and a 2.5 cm radius: LIBERO draws from [0.045, 0.075].
        let mut rng = rand_pcg::Pcg64::seed_from_u64(1);
        let draws: Vec<f64> = (0..2000).map(|_| between(0.05 + 0.025, 0.07 - 0.025, &mut rng)).collect();
        assert!(draws.iter().all(|&x| (0.045..=0.075).contains(&x)));
        assert!(draws.iter().any(|&x| x < 0.047) && draws.iter().any(|&x| x > 0.073));
        assert!(shrinks(ProblemClass::Floor) && !shrinks(ProblemClass::KitchenTabletop));
    }
}
