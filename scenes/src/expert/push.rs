//! Pushing a flat object (a plate) across the table to a target.

use vifo_robots::spatial::Vec3;

use super::geometry;
use super::motion::{self, Servo, Waypoint};
use super::skill::{CLOSE, Step, path_height, surface_height};
use crate::sim::Sim;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Behind,
    Lower,
    Push,
    Retreat,
}

/// Push `object` until its origin is within `tolerance` of `target` (xy). A hollow object
/// (a bowl) is pushed from inside, by its far wall: there may be no room behind it.
pub struct Push {
    object: usize,
    hollow: bool,
    target: [f64; 2],
    tolerance: f64,
    stage: Stage,
    stage_steps: usize,
    cruise_z: f64,
}

const STAGE_LIMIT: usize = 120;
/// Grip-site height above the support while pushing: fingertips about a centimetre up.
const PUSH_HEIGHT: f64 = 0.02;
/// Pushing a bowl from inside: the closed fingers go down this far behind its centre and stay
/// this much higher, above its floor.
const HOLLOW_OFFSET: f64 = 0.015;
const HOLLOW_FLOOR: f64 = 0.01;

impl Push {
    pub fn new(object: usize, target: [f64; 2], tolerance: f64, hollow: bool) -> Self {
        Push { object, hollow, target, tolerance, stage: Stage::Rise, stage_steps: 0, cruise_z: 0.0 }
    }

    pub fn describe(&self) -> String {
        format!("push {:?} step {}", self.stage, self.stage_steps)
    }

    fn next(&mut self, stage: Stage) {
        self.stage = stage;
        self.stage_steps = 0;
    }

    /// Object centre, push direction, and the object's radius in that direction.
    fn geometry(&self, sim: &Sim) -> (Vec3, Vec3, f64) {
        let c = sim.entity_pose(self.object).pos;
        let to = Vec3::new(self.target[0] - c.x, self.target[1] - c.y, 0.0);
        let dir = if to.norm() > 1e-6 { to.normalize() } else { Vec3::x() };
        let points = geometry::corners(sim, self.object, 0);
        let radius = points.iter().map(|p| -(p - c).dot(&dir)).fold(0.0, f64::max);
        (c, dir, radius)
    }

    /// Fingers side by side across the push (the widest front) unless the hand would then
    /// come down on something; otherwise the clearest of a few turns away from that.
    fn yaw(&self, sim: &Sim, dir: &Vec3, at: &Vec3) -> f64 {
        let obstacles = geometry::Obstacles::around(sim, self.object);
        let axis = (0..6)
            .map(|k| {
                let a = std::f64::consts::PI * k as f64 / 12.0;
                let (s, c) = (libm::sin(a), libm::cos(a));
                let across = Vec3::new(-dir.y, dir.x, 0.0);
                across * c + dir * s
            })
            .min_by_key(|axis| geometry::gripper_hits(&obstacles, at, axis, 0.0))
            .expect("six candidates");
        let ee = sim.model().robot.grip_site_pose(sim.world());
        motion::nearest_yaw(geometry::yaw_of_axis(&axis), motion::current_yaw(&ee))
    }

    pub fn step(&mut self, sim: &Sim) -> Step {
        self.stage_steps += 1;
        if self.stage_steps > STAGE_LIMIT {
            return Step::Failed("a push stage took too long");
        }
        let ee = sim.model().robot.grip_site_pose(sim.world());
        let (c, dir, radius) = self.geometry(sim);
        let support = surface_height(sim, [c.x - dir.x * (radius + 0.03), c.y - dir.y * (radius + 0.03)], 0.02, Some(self.object));
        let (behind, height) = if self.hollow {
            // Closed fingers just behind the centre, low inside the bowl.
            (c - dir * HOLLOW_OFFSET, support + PUSH_HEIGHT + HOLLOW_FLOOR)
        } else {
            (c - dir * (radius + 0.025), support + PUSH_HEIGHT)
        };
        let behind = Vec3::new(behind.x, behind.y, height);
        let yaw = self.yaw(sim, &dir, &behind);
        let remaining = ((self.target[0] - c.x).powi(2) + (self.target[1] - c.y).powi(2)).sqrt();
        match self.stage {
            Stage::Rise => {
                let path_top = path_height(sim, [ee.pos.x, ee.pos.y], [behind.x, behind.y], 0.1, None);
                self.cruise_z = (path_top + 0.06).max(behind.z + 0.08);
                if ee.pos.z >= self.cruise_z - 0.02 {
                    self.next(Stage::Behind);
                    return self.step(sim);
                }
                Step::Act(Servo::TRAVEL.act(sim, &Waypoint::down(Vec3::new(ee.pos.x, ee.pos.y, self.cruise_z), yaw), CLOSE))
            }
            Stage::Behind => {
                let wp = Waypoint::down(Vec3::new(behind.x, behind.y, self.cruise_z), yaw);
                let (d, r) = motion::error(sim, &wp);
                if d < 0.01 && r < 0.05 {
                    self.next(Stage::Lower);
                }
                Step::Act(Servo::TRAVEL.act(sim, &wp, CLOSE))
            }
            Stage::Lower => {
                let wp = Waypoint::down(behind, yaw);
                let (d, _) = motion::error(sim, &wp);
                if d < 0.006 {
                    self.next(Stage::Push);
                }
                Step::Act(Servo::closing_in(d).act(sim, &wp, CLOSE))
            }
            Stage::Push => {
                if remaining < self.tolerance {
                    self.next(Stage::Retreat);
                    return self.step(sim);
                }
                // Keep the fingers at the object's back edge and lead it toward the target.
                // (From inside a bowl the fingers first cross to its far wall.)
                let lead = (remaining).min(0.03);
                let reach = if self.hollow { 0.035 } else { 0.02 };
                let wp = Waypoint::down(behind + dir * (reach + lead), yaw);
                Step::Act(Servo::FINE.act(sim, &wp, CLOSE))
            }
            Stage::Retreat => {
                if self.stage_steps >= 8 {
                    return Step::Done;
                }
                Step::Act(Servo::TRAVEL.act(sim, &Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.08), yaw), CLOSE))
            }
        }
    }
}
