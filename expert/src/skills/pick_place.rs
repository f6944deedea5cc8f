//! Pick an object and put it on or into something.
//!
//! Recipe: rise, come over the grasp, descend, grasp, lift, carry over the target, (for a
//! tilted region: turn the object and approach along the surface's normal), set down,
//! release, retreat.

use vifo_robots::action::Action;
use vifo_robots::spatial::Vec3;
use vifo_scenes::sim::Sim;

use super::lean::{self, LeanPlan};
use super::{Skill, drawer};
use crate::arm;
use crate::geometry::{self, Grasp, cruise_height, path_height, surface_height};
use crate::motion::{self, Servo, Waypoint};
use crate::stages::{self, CLOSE, Leg, OPEN, Pace, Progress, Stages, Step, Tol, gripper_toward};

/// Where a picked object must go.
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// Put the object's origin over the spot, resting on whatever is below (a plate, a region,
    /// a burner), released from just above the surface.
    On(Spot),
    /// Drop the object into a container whose opening is centred on the spot.
    Into(Spot),
}

/// A place looked up in the current state, so a target that moved since planning (a drawer
/// opened by an earlier skill, a plate nudged) is still hit.
#[derive(Clone, Debug, PartialEq)]
pub enum Spot {
    /// An object's or fixture's origin.
    Entity(usize),
    /// A region's (or site's) centre, moved by `offset` (world xy) where several objects
    /// share the region.
    Region { name: String, offset: [f64; 2] },
}

impl Spot {
    /// The spot's horizontal position now (a region that vanished falls back to the origin).
    pub fn xy(&self, sim: &Sim) -> [f64; 2] {
        let p = match self {
            Spot::Entity(i) => sim.entity_pose(*i).pos,
            Spot::Region { name, offset } => {
                sim.region_box(name).map_or(Vec3::zeros(), |r| r.pose.pos) + Vec3::new(offset[0], offset[1], 0.0)
            }
        };
        [p.x, p.y]
    }
}

/// Pick an object and put it somewhere.
pub struct PickPlace {
    pub object: usize,
    pub placement: Placement,
    stage: Stages<Stage>,
    grasp: Option<Grasp>,
    /// Grip site minus object origin while carried (world frame).
    carry_offset: Option<Vec3>,
    /// Object bottom below its origin while carried.
    carry_depth: f64,
    attempts: usize,
    lift_start_z: f64,
    /// Altitude for the carry, fixed when the carry starts.
    cruise_z: f64,
    /// Where the placement's spot was when the carry started.
    target: [f64; 2],
    /// Recent grip-site heights while lowering, to notice a stall.
    lowering: Progress,
    /// Where the object lies on a tilted region, planned when the carry starts.
    lean: Option<LeanPlan>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Above,
    Descend,
    Close,
    Lift,
    Travel,
    /// Turn the carried object to lie along a tilted region, coming down over where it is laid.
    Tilt,
    /// Bring the turned object over where it is laid, off the surface along its normal.
    Approach,
    Lower,
    Release,
    Retreat,
    Done,
}

/// The object comes up this far at the fine servo's speed before the lift speeds up.
const GENTLE_LIFT: f64 = 0.02;

/// How long any stage may last before the skill gives up on it (control steps).
const STAGE_LIMIT: usize = 80;
/// Turn still left (rad) above which the hand keeps over what it sweeps.
const TURNING: f64 = 0.1;
/// How far below its top an object laid on a tilted region is pinched.
const LEAN_GRASP_DEPTH: f64 = 0.015;
/// Height over the approach point to which the carried object comes down as it is turned.
const TILT_HEIGHT: f64 = 0.10;
/// Distance from the laid pose, along the surface's normal, from which it is approached.
const LEAN_APPROACH: f64 = 0.04;

impl PickPlace {
    pub fn new(object: usize, placement: Placement) -> Self {
        PickPlace {
            object,
            placement,
            stage: Stages::new(Stage::Rise, STAGE_LIMIT),
            grasp: None,
            carry_offset: None,
            carry_depth: 0.0,
            attempts: 0,
            lift_start_z: 0.0,
            cruise_z: 0.0,
            target: [0.0; 2],
            lowering: Progress::default(),
            lean: None,
        }
    }

    /// The tilted region's z axis, when the object is to lie on one.
    fn tilted_up(&self, sim: &Sim) -> Option<Vec3> {
        match &self.placement {
            Placement::On(Spot::Region { name, .. }) => lean::tilted_up(sim, name),
            _ => None,
        }
    }

    fn plan_grasp(&self, sim: &Sim) -> Grasp {
        let points = geometry::corners(sim, self.object, 0);
        let obstacles = geometry::Obstacles::around(sim, self.object);
        if let Some(up) = self.tilted_up(sim) {
            // Pinched along the axis it will turn about, high up so the hand ends past the
            // far edge of what it is laid on.
            if let Some(g) = geometry::solid_grasp(&points, LEAN_GRASP_DEPTH, &obstacles) {
                let yaw = geometry::yaw_of_axis(&lean::tilt_axis(&up));
                return Grasp { yaw: motion::reachable_yaw(sim, yaw), ..g };
            }
        }
        if let Some(g) = geometry::solid_grasp(&points, 0.025, &obstacles) {
            return Grasp { yaw: motion::reachable_yaw(sim, g.yaw), ..g };
        }
        let origin = sim.entity_pose(self.object).pos;
        let parts = geometry::body_boxes(sim, self.object, 0);
        if geometry::closed_top(&parts, &origin)
            && let Some(g) = geometry::part_grasp(&parts, &obstacles, &origin)
        {
            return Grasp { yaw: motion::reachable_yaw(sim, g.yaw), ..g };
        }
        let (lo, hi) = geometry::bounds(&points);
        let centre = Vec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), origin.z);
        // Grip the rim on the side facing the robot's base, where the arm comes from.
        let base = arm::of(sim).base();
        let g = geometry::rim_grasp(&points, &centre, &base, &obstacles);
        Grasp { yaw: motion::reachable_yaw(sim, g.yaw), ..g }
    }

    /// Height at which to travel: clear of everything between here and there (the carried
    /// object hanging `carry_depth` below the grip site).
    fn travel_height(&self, sim: &Sim, to: [f64; 2]) -> f64 {
        let ee = arm::of(sim).grip_site();
        path_height(sim, [ee.pos.x, ee.pos.y], to, 0.1, Some(self.object)) + self.carry_depth + 0.06
    }

    fn target_xy(&self, sim: &Sim) -> [f64; 2] {
        match &self.placement {
            Placement::Into(spot @ Spot::Region { name, .. }) => {
                drawer::drop_point(sim, name, self.radius(sim)).unwrap_or_else(|| spot.xy(sim))
            }
            Placement::On(spot) | Placement::Into(spot) => spot.xy(sim),
        }
    }

    /// The carried object's horizontal radius (half its larger horizontal extent).
    fn radius(&self, sim: &Sim) -> f64 {
        let (lo, hi) = geometry::bounds(&geometry::corners(sim, self.object, 0));
        0.5 * (hi.x - lo.x).max(hi.y - lo.y)
    }
}

impl Skill for PickPlace {
    fn describe(&self) -> String {
        let g = self.grasp.map(|g| format!("grasp ({:.3} {:.3} {:.3}) yaw {:.2} width {:.3} gap {:.3}", g.pos.x, g.pos.y, g.pos.z, g.yaw, g.width, g.half_gap)).unwrap_or_default();
        format!("pick-place {} attempt {} {g}", self.stage, self.attempts)
    }

    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        let object = sim.entity_pose(self.object);
        if self.grasp.is_none() {
            self.grasp = Some(self.plan_grasp(sim));
        }
        let g = self.grasp.expect("planned");
        let steps = self.stage.steps;
        let (leg, then) = match self.stage.now {
            Stage::Rise => {
                // Fly over everything between here and the grasp, fingertips clear.
                self.cruise_z = cruise_height(sim, &g.pos, 0.06, g.pos.z + 0.08, Some(self.object));
                (stages::rise(sim, self.cruise_z, motion::orientation(g.yaw), gripper_toward(sim, g.half_gap)), Stage::Above)
            }
            Stage::Above => {
                // While the hand still turns, it stays over everything its length sweeps.
                let (_, turn) = motion::error(sim, &Waypoint::down(ee.pos, g.yaw));
                let low = if turn > TURNING { self.sweep_floor(sim, &g).max(g.pos.z + 0.08) } else { g.pos.z + 0.08 };
                let wp = Waypoint::down(stages::over(&ee.pos, &g.pos, self.cruise_z, low), g.yaw);
                let (d, r) = motion::error(sim, &wp);
                let servo = if d < 0.03 { Servo::FINE } else { Servo::TRAVEL };
                (Leg::until(stages::Move { to: wp, servo, grip: gripper_toward(sim, g.half_gap) }, d < 0.003 && r < 0.03), Stage::Descend)
            }
            Stage::Descend => (stages::descend(sim, &g.pos, motion::orientation(g.yaw), 0.005, gripper_toward(sim, g.half_gap)), Stage::Close),
            Stage::Close => {
                let leg = stages::grasp(steps, 12, Waypoint::down(g.pos, g.yaw));
                if leg.is_last() {
                    self.lift_start_z = object.pos.z;
                }
                (leg, Stage::Lift)
            }
            Stage::Lift => {
                if let Some(why) = stages::lift_failure(sim, steps, 12, self.lift_start_z, object.pos.z, 0.01) {
                    return self.retry(why);
                }
                let up = Waypoint::down(Vec3::new(g.pos.x, g.pos.y, g.pos.z + 0.12), g.yaw);
                let (d, _) = motion::error(sim, &up);
                let lifted = d < 0.02 && object.pos.z - self.lift_start_z > 0.05;
                if lifted {
                    self.carry_offset = Some(ee.pos - object.pos);
                    let (lo, _) = geometry::bounds(&geometry::corners(sim, self.object, 0));
                    self.carry_depth = ee.pos.z - lo.z;
                }
                // Lift off gently: a rim pinched at full speed swings the vessel out of the fingers.
                let servo = if object.pos.z - self.lift_start_z < GENTLE_LIFT { Servo::FINE } else { Servo::TRAVEL };
                (Leg::until(stages::Move { to: up, servo, grip: CLOSE }, lifted), Stage::Travel)
            }
            Stage::Travel => {
                let offset = self.carry_offset.expect("measured");
                if steps == 1 {
                    self.target = self.target_xy(sim);
                    if let (Some(_), Placement::On(Spot::Region { name, .. })) = (self.tilted_up(sim), &self.placement) {
                        self.lean = lean::plan(sim, self.object, name, &ee);
                        let Some(plan) = self.lean else { return Step::Failed("no room to lay the object on the tilted region") };
                        let hand = plan.hand(LEAN_APPROACH, TILT_HEIGHT);
                        self.target = [hand.pos.x - offset.x, hand.pos.y - offset.y];
                    }
                    self.cruise_z = self.travel_height(sim, self.target).max(ee.pos.z);
                }
                if self.lost(sim) {
                    return self.retry("the object slipped out");
                }
                let over = Vec3::new(self.target[0] + offset.x, self.target[1] + offset.y, self.cruise_z);
                (stages::carry(sim, &over, motion::orientation(g.yaw)), if self.lean.is_some() { Stage::Tilt } else { Stage::Lower })
            }
            Stage::Tilt => {
                let wp = self.lean.expect("planned").hand(LEAN_APPROACH, TILT_HEIGHT);
                (stages::reach(sim, wp, Pace::Travel, Tol::pose(0.01, 0.03), CLOSE), Stage::Approach)
            }
            Stage::Approach => {
                let wp = self.lean.expect("planned").hand(LEAN_APPROACH, 0.0);
                (stages::reach(sim, wp, Pace::Fine, Tol::pose(0.005, 0.03), CLOSE), Stage::Lower)
            }
            Stage::Lower => {
                let (wp, pace) = match self.lean {
                    Some(plan) => (plan.hand(0.0, 0.0), Pace::Fine),
                    None => (self.lower_waypoint(sim), Pace::ClosingIn),
                };
                (stages::set_down(sim, &mut self.lowering, wp, pace, 0.008, 0.002), Stage::Release)
            }
            Stage::Release => {
                let rot = if self.lean.is_some() { ee.rot } else { motion::orientation(g.yaw) };
                (stages::release(steps, 10, Waypoint { pos: ee.pos, rot }), Stage::Retreat)
            }
            Stage::Retreat => {
                let up = match self.lean {
                    // Back out along the object first: the fingers slide off its end.
                    Some(_) => Waypoint { pos: ee.pos - ee.rot.column(2) * 0.06 + Vec3::z() * 0.02, rot: ee.rot },
                    None => Waypoint::down(Vec3::new(ee.pos.x, ee.pos.y, ee.pos.z.max(object.pos.z + self.carry_depth) + 0.06), g.yaw),
                };
                (stages::retreat(steps, 6, up, OPEN), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }
}

impl PickPlace {
    /// The lowest grip-site height at which the hand, turning over the grasp, clears
    /// everything within its half length of it (a bottle beside a bowl).
    fn sweep_floor(&self, sim: &Sim, g: &Grasp) -> f64 {
        let top = surface_height(sim, [g.pos.x, g.pos.y], geometry::HAND_HALF_LENGTH + 0.01, Some(self.object));
        top - geometry::HAND_ABOVE_SITE + 0.01
    }

    /// Where the gripper goes down to, releasing the object just above what it is put on.
    fn lower_waypoint(&self, sim: &Sim) -> Waypoint {
        let offset = self.carry_offset.expect("measured");
        let xy = self.target;
        let surface = surface_height(sim, xy, self.radius(sim).max(0.02), Some(self.object));
        let clearance = match self.placement {
            Placement::On(_) => 0.012,
            Placement::Into(_) => 0.02,
        };
        let z = surface + self.carry_depth + clearance;
        Waypoint::down(Vec3::new(xy[0] + offset.x, xy[1] + offset.y, z), self.grasp.expect("planned").yaw)
    }

    /// Whether the carried object no longer moves with the gripper.
    fn lost(&self, sim: &Sim) -> bool {
        let Some(offset) = self.carry_offset else { return false };
        let ee = arm::of(sim).grip_site().pos;
        let object = sim.entity_pose(self.object).pos;
        ((ee - object) - offset).norm() > 0.03
    }

    fn retry(&mut self, why: &'static str) -> Step {
        self.attempts += 1;
        if self.attempts >= 3 {
            return Step::Failed(why);
        }
        self.grasp = None;
        self.carry_offset = None;
        self.stage.next(Stage::Rise);
        Step::Act(Action::hold(OPEN))
    }
}
