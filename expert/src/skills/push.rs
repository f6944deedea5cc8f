//! Pushing a flat object (a plate) across the table to a target.
//!
//! Recipe: rise, cross to behind the object, lower the closed fingers there, push it along the
//! way to its target (following a slide), retreat upward.

use vifo_robots::spatial::{Mat3, Pose, Vec3};
use vifo_scenes::sim::Sim;

use super::Skill;
use crate::arm;
use crate::geometry::{self, cruise_height, support_under, surface_height};
use crate::motion::{self, Servo, Waypoint};
use crate::stages::{self, CLOSE, Leg, Pace, Stages, Step, Tol};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Behind,
    Lower,
    Push,
    Retreat,
    Done,
}

/// Push `object` until its origin is within `tolerance` of `target` (xy). An open vessel (a
/// bowl, a plate) may be pushed from inside, by its far wall, where there is no room behind it.
pub struct Push {
    object: usize,
    /// Pushing from inside: the fingers' height above a solid push's (see [`inside_floor`]).
    inside: Option<f64>,
    target: [f64; 2],
    tolerance: f64,
    stage: Stages<Stage>,
    cruise_z: f64,
    /// The finger yaw, and how far along the push the closed fingers come down: fixed at the
    /// start (see [`Push::start`]).
    start: Option<(f64, f64)>,
}

const STAGE_LIMIT: usize = 120;
/// Grip-site height above the support while pushing: fingertips about a centimetre up.
const PUSH_HEIGHT: f64 = 0.02;
/// How much higher than the object's support the ground behind it may be for a push from there.
const STEP_UP: f64 = 0.01;
/// Pushing a bowl from inside: the closed fingers go down this far behind its centre and stay
/// this much higher, above its floor.
const HOLLOW_OFFSET: f64 = 0.015;
/// What stands this close to where the object ends up (beyond its own radius) is nudged
/// along, not in the way.
const AT_TARGET: f64 = 0.03;
/// Inside a vessel, the closed fingers may come down up to this much further along the push
/// than its start (short of where the push leads them anyway), where the hand clears a fixture
/// beside the vessel there.
const INSIDE_AHEAD: [f64; 4] = [0.0, 0.01, 0.02, 0.03];

/// Push direction from an object centred at `centre` (its current shape moved there) toward
/// `target`, and the object's radius against that direction.
fn aim(sim: &Sim, object: usize, centre: &Vec3, target: [f64; 2]) -> (Vec3, Vec3, f64) {
    let now = sim.entity_pose(object).pos;
    let to = Vec3::new(target[0] - centre.x, target[1] - centre.y, 0.0);
    let dir = if to.norm() > 1e-6 { to.normalize() } else { Vec3::x() };
    let radius = geometry::corners(sim, object, 0).iter().map(|p| -(p - now).dot(&dir)).fold(0.0, f64::max);
    (*centre, dir, radius)
}

/// Fingers side by side across the push (the widest front) unless the hand would then meet
/// something on its way from `from` over `travel`; otherwise the clearest of a few turns away
/// from that, up to fingers along the push (the narrowest hand). Also returns how many
/// obstacle meetings that hand still has along the way.
fn finger_axis(obstacles: &geometry::Obstacles, dir: &Vec3, from: &Vec3, travel: &Vec3) -> (Vec3, usize) {
    const SAMPLES: usize = 6;
    (0..=6)
        .map(|k| {
            let a = std::f64::consts::PI * k as f64 / 12.0;
            let (s, c) = (libm::sin(a), libm::cos(a));
            let axis = Vec3::new(-dir.y, dir.x, 0.0) * c + dir * s;
            let hits = (0..=SAMPLES)
                .map(|i| geometry::gripper_hits(obstacles, &(from + travel * (i as f64 / SAMPLES as f64)), &axis, 0.0))
                .sum::<usize>();
            (axis, hits)
        })
        .min_by_key(|(_, hits)| *hits)
        .expect("seven candidates")
}

/// The pushes that bring `object` to `target`: straight there when the hand fits behind it,
/// else two legs along the world axes (the first order whose two hand positions are clear),
/// else, for an open vessel, pushes from inside it (straight, or in two legs where only they
/// let it slide clear of other objects), so the hand never has to come down between the
/// object and a fixture.
pub fn pushes(sim: &Sim, object: usize, target: [f64; 2], tolerance: f64) -> Vec<Push> {
    if let Some(legs) = legs(sim, object, target, Pusher::Behind) {
        return legs.into_iter().map(|to| Push::new(object, to, tolerance, None)).collect();
    }
    let inside = inside_floor(&sim.model().entities[object].category);
    let legs = match inside {
        Some(_) => legs(sim, object, target, Pusher::Inside).unwrap_or_else(|| vec![target]),
        None => vec![target],
    };
    legs.into_iter().map(|to| Push::new(object, to, tolerance, inside)).collect()
}

/// Where the hand pushes from.
#[derive(Clone, Copy, PartialEq)]
enum Pusher {
    /// Behind the object: the hand must be clear there and on the way.
    Behind,
    /// Inside an open vessel, against its far wall.
    Inside,
}

/// Open vessels pushed from inside by their far wall, with how much higher than a solid push
/// the fingers ride there (clear of the vessel's floor, below its rim).
const HOLLOW: [(&str, f64); 2] = [("akita_black_bowl", 0.01), ("plate", -0.002)];

/// How high above a solid push the fingers ride inside a vessel of this category, if it is one.
pub fn inside_floor(category: &str) -> Option<f64> {
    HOLLOW.iter().find(|(c, _)| *c == category).map(|(_, floor)| *floor)
}

/// Push targets, straight or in two legs along the world axes, if any are fit: pushed from
/// behind, the hand must be clear of everything, and a way along which the object itself
/// slides without running into anything (a bowl beside the way stops a plate) is preferred;
/// pushed from inside, the object must slide clear. The hand must be able to come down behind
/// the object to its own support: something taller there (a cabinet's corner) would leave the
/// fingers pushing the air above the object.
fn legs(sim: &Sim, object: usize, target: [f64; 2], pusher: Pusher) -> Option<Vec<[f64; 2]>> {
    let obstacles = geometry::Obstacles::around(sim, object);
    let c = sim.entity_pose(object).pos;
    let base = support_under(sim, object);
    let parts = geometry::body_boxes(sim, object, 0);
    let reach = geometry::bounds(&geometry::corners(sim, object, 0));
    let radius = 0.5 * (reach.1.x - reach.0.x).max(reach.1.y - reach.0.y);
    let goal = Vec3::new(target[0], target[1], c.z);
    let in_way = obstacles.clone().beyond(&goal, radius + AT_TARGET);
    // The object slid in a straight line from `from` to `to`.
    let slides = |from: Vec3, to: [f64; 2]| {
        let travel = Vec3::new(to[0] - from.x, to[1] - from.y, 0.0);
        let steps = libm::ceil(travel.norm() / 0.01) as usize;
        (0..=steps).all(|i| {
            let at = from - c + travel * (i as f64 / steps.max(1) as f64);
            let by = Pose::new(at, Mat3::identity());
            let moved: Vec<geometry::Obb> = parts.iter().map(|b| b.moved(&by)).collect();
            in_way.hits(&moved, 0.001) == 0
        })
    };
    let hand_clear = |from: Vec3, to: [f64; 2]| {
        let (c, dir, radius) = aim(sim, object, &from, to);
        let behind = c - dir * (radius + 0.025);
        if surface_height(sim, [behind.x, behind.y], 0.02, Some(object)) > base + STEP_UP {
            return false;
        }
        let z = base + PUSH_HEIGHT;
        let travel = Vec3::new(to[0] - c.x, to[1] - c.y, 0.0);
        finger_axis(&obstacles, &dir, &Vec3::new(behind.x, behind.y, z), &travel).1 == 0
    };
    let options = [vec![target], vec![[target[0], c.y], target], vec![[c.x, target[1]], target]];
    let feasible = |legs: &Vec<[f64; 2]>, hand: bool, slide: bool| {
        let mut from = c;
        legs.iter().all(|to| {
            let ok = (!hand || hand_clear(from, *to)) && (!slide || slides(from, *to));
            from = Vec3::new(to[0], to[1], c.z);
            ok
        })
    };
    let find = |hand: bool, slide: bool| options.iter().find(|legs| feasible(legs, hand, slide)).cloned();
    match pusher {
        Pusher::Behind => find(true, true).or_else(|| find(true, false)),
        Pusher::Inside => find(false, true),
    }
}

impl Push {
    pub fn new(object: usize, target: [f64; 2], tolerance: f64, inside: Option<f64>) -> Self {
        Push { object, inside, target, tolerance, stage: Stages::new(Stage::Rise, STAGE_LIMIT), cruise_z: 0.0, start: None }
    }

    /// Object centre, push direction, and the object's radius in that direction.
    fn geometry(&self, sim: &Sim) -> (Vec3, Vec3, f64) {
        aim(sim, self.object, &sim.entity_pose(self.object).pos, self.target)
    }

    /// The finger yaw and how far along the push `dir` from `behind` the closed fingers come
    /// down, chosen once per push. The yaw: the finger axis with the fewest obstacles around the
    /// hand on its way (see [`finger_axis`]), near the current one. The way ahead: inside a
    /// vessel, the first of [`INSIDE_AHEAD`] where the hand meets nothing (none: at `behind`).
    fn start(&mut self, sim: &Sim, dir: &Vec3, behind: &Vec3, c: &Vec3) -> (f64, f64) {
        if let Some(start) = self.start {
            return start;
        }
        let obstacles = geometry::Obstacles::around(sim, self.object);
        let travel = Vec3::new(self.target[0] - c.x, self.target[1] - c.y, 0.0);
        let (axis, _) = finger_axis(&obstacles, dir, behind, &travel);
        let yaw = motion::reachable_yaw(sim, geometry::yaw_of_axis(&axis));
        let rot = motion::orientation(yaw);
        let clear = |a: &f64| geometry::gripper_hits_at(&obstacles, &Pose::new(behind + dir * *a, rot), 0.0) == 0;
        let ahead = match self.inside {
            None => 0.0,
            Some(_) => INSIDE_AHEAD.into_iter().find(clear).unwrap_or(0.0),
        };
        self.start = Some((yaw, ahead));
        (yaw, ahead)
    }
}

impl Skill for Push {
    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a push stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        let (c, dir, radius) = self.geometry(sim);
        let support = support_under(sim, self.object);
        let (behind, height) = match self.inside {
            // Closed fingers just behind the centre, low inside the vessel.
            Some(floor) => (c - dir * HOLLOW_OFFSET, support + PUSH_HEIGHT + floor),
            None => (c - dir * (radius + 0.025), support + PUSH_HEIGHT),
        };
        let behind = Vec3::new(behind.x, behind.y, height);
        let (yaw, ahead) = self.start(sim, &dir, &behind, &c);
        let down = behind + dir * ahead;
        let remaining = ((self.target[0] - c.x).powi(2) + (self.target[1] - c.y).powi(2)).sqrt();
        let (leg, then) = match self.stage.now {
            Stage::Rise => {
                self.cruise_z = cruise_height(sim, &down, 0.06, down.z + 0.08, None);
                (stages::rise(sim, self.cruise_z, motion::orientation(yaw), CLOSE), Stage::Behind)
            }
            Stage::Behind => (stages::cross(sim, &down, self.cruise_z, motion::orientation(yaw), Tol::pose(0.01, 0.05), CLOSE), Stage::Lower),
            Stage::Lower => (stages::reach(sim, Waypoint::down(down, yaw), Pace::ClosingIn, Tol::pos(0.006), CLOSE), Stage::Push),
            // Follow the slide: keep the fingers at the object's back edge and lead it toward
            // the target. (From inside a bowl the fingers first cross to its far wall.)
            Stage::Push => {
                let lead = (remaining).min(0.03);
                let reach = if self.inside.is_some() { 0.035 } else { 0.02 };
                let m = stages::Move { to: Waypoint::down(behind + dir * (reach + lead), yaw), servo: Servo::FINE, grip: CLOSE };
                (Leg::unless(remaining < self.tolerance, m), Stage::Retreat)
            }
            Stage::Retreat => (stages::retreat(self.stage.steps, 8, Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.08), yaw), CLOSE), Stage::Done),
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }

    fn describe(&self) -> String {
        format!("push {}", self.stage)
    }
}
