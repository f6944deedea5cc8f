//! Stacking a cup into another (the PiPER study, §4.4): take the cup by its body below the rim,
//! carry it over the other cup, and lower its foot into the other's mouth before letting go, so
//! the taper centres it (the fingers, outside the held cup, stay clear of the lower cup's rim).
//!
//! Recipe: the approach (rise, come over the cup, descend, grasp), lift straight up, carry over
//! the target, lower to just above its rim and wait there until the cup's foot stays over the
//! opening, enter the mouth, release, retreat.

use vifo_robots::spatial::Vec3;
use vifo_scenes::sim::Sim;

use super::Skill;
use crate::approach::{Approach, ApproachPlan, Descent};
use crate::arm;
use crate::geometry::{corners, horizontal};
use crate::motion::{self, Waypoint};
use crate::stages::{self, CLOSE, Leg, OPEN, Pace, Progress, Stages, Step, Tol};

const STAGE_LIMIT: usize = 120;
/// The grasp: this far below the rim, where the cup is narrower than the open gripper.
const BELOW_RIM: f64 = 0.02;
/// How high the grip point travels above the table top's highest cup rim.
const CRUISE_CLEARANCE: f64 = 0.065;
/// The PiPER's open fingers around the grip point (its 3.5 cm stroke, 2.4 × 5.6 × 7 cm fingers).
struct Fingers {
    /// How far each reaches out from the grip point along the closing axis.
    reach: f64,
    /// Half their width across it.
    half_width: f64,
    /// How far the fingertips reach below the grip point.
    below: f64,
}

const FINGERS: Fingers = Fingers { reach: 0.059, half_width: 0.028, below: 0.025 };
/// The held cup's foot is centred this far above the target's rim, then lowered to this far
/// below it and let go: inside the target's mouth it cannot tip out, and the fingertips, 1.4 cm
/// above the foot, still clear the rim by 6 mm.
const DROP: f64 = 0.012;
const ENTER: f64 = 0.008;
/// How far the held cup's foot may be off the target's centre when it is let go (m): well
/// inside the 8 mm the taper centres.
const CENTRED: f64 = 0.005;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Approach(Approach),
    Lift,
    Carry,
    Lower,
    Enter,
    Release,
    Retreat,
    Done,
}

/// Put cup `object` into cup `target`.
pub struct Stack {
    object: usize,
    target: usize,
    stage: Stages<Stage>,
    /// Finger yaw, kept from the start (a cup is round: any yaw takes it).
    yaw: Option<f64>,
    /// Measured when the fingers closed.
    held: Held,
    /// Where the fingers opened: the hand leaves straight up from there.
    released_at: Vec3,
    /// For how many steps in a row the held cup's foot has been over the target's opening: it
    /// is let go only once it stays there (it rocks a little in the pinch after the carry).
    centred_for: usize,
    /// Recent grip-site heights while entering, to notice a stall.
    entering: Progress,
}

/// The cup in the hand, as measured when the fingers closed on it (the cup standing on the
/// table).
#[derive(Clone, Copy, Debug, Default)]
struct Held {
    /// The grip point's height above the cup's foot.
    hold: f64,
    /// The cup's height.
    start_z: f64,
    /// Where the fingers closed: the cup is lifted straight up from there.
    at: Vec3,
    /// The grip point's horizontal offset from the cup's centre: the hand carries the cup over
    /// the target by it. Not re-measured from the held cup, which swings a little in the pinch,
    /// and a hand chasing the swinging cup drives the swing.
    offset: Vec3,
}

impl Stack {
    pub fn new(object: usize, target: usize) -> Self {
        Stack { object, target, stage: Stages::new(Stage::Approach(Approach::Rise), STAGE_LIMIT), yaw: None, held: Held::default(), released_at: Vec3::zeros(), centred_for: 0, entering: Progress::default() }
    }

    /// The top of an entity's model (its rim, for a cup) at its current pose.
    fn rim(sim: &Sim, entity: usize) -> Vec3 {
        let pose = sim.entity_pose(entity);
        pose.pos + pose.rot * Vec3::from(sim.model().entities[entity].model.top_offset)
    }

    /// The finger yaw that keeps the open fingers off the other objects near the cup (each
    /// finger reaches 5.9 cm out along the finger axis and 2.8 cm across it; objects lower than
    /// the fingertips, the note lying flat, do not count): of the yaws the wrist reaches in 15°
    /// steps from the current one, the one with the most room, the current one first among
    /// equals. A neighbour's size is its collision boxes' reach from its centre.
    fn choose_yaw(&self, sim: &Sim, current: f64) -> f64 {
        let centre = sim.entity_pose(self.object).pos;
        let fingertips = Self::rim(sim, self.object).z - BELOW_RIM - FINGERS.below;
        let neighbours: Vec<(Vec3, f64)> = (0..sim.model().entities.len())
            .filter(|&e| e != self.object && sim.model().entities[e].movable())
            .filter_map(|e| {
                let corners = corners(sim, e, 0);
                let top = corners.iter().map(|c| c.z).fold(f64::MIN, f64::max);
                let at = sim.entity_pose(e).pos;
                let reach = corners.iter().map(|c| horizontal(c, &at)).fold(0.0, f64::max);
                (top > fingertips).then_some((at, reach))
            })
            .collect();
        let room = |yaw: f64| -> f64 {
            let axis = Vec3::new(-libm::sin(yaw), libm::cos(yaw), 0.0);
            neighbours
                .iter()
                .map(|(at, r)| {
                    let d = at - centre;
                    let along = d.dot(&axis).abs() - (FINGERS.reach + r);
                    let across = (d.x * axis.y - d.y * axis.x).abs() - (FINGERS.half_width + r);
                    along.max(across)
                })
                .fold(f64::MAX, f64::min)
        };
        let candidates = (0..12).map(|k| current + (k as f64 - 5.0) * std::f64::consts::PI / 12.0);
        let reachable: Vec<f64> = candidates.filter(|&y| arm::of(sim).wrist_reaches(&motion::orientation(y))).collect();
        let mut best = current;
        let mut best_room = room(current);
        for y in reachable {
            let r = room(y);
            if r > best_room + 1e-3 {
                (best, best_room) = (y, r);
            }
        }
        best
    }

    /// Above the highest rim in the scene but the moved cup's, with the fingers (and the held
    /// cup, `hold` below the grip point) clear of it.
    fn cruise_z(&self, sim: &Sim, hold: f64) -> f64 {
        let highest = (0..sim.model().entities.len()).filter(|&e| e != self.object).map(|e| Self::rim(sim, e).z).fold(f64::MIN, f64::max);
        highest + CRUISE_CLEARANCE.max(hold + 0.02)
    }
}

impl Skill for Stack {
    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a stacking stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        // Chosen once, at the first step, from where the hand is then.
        let yaw = match self.yaw {
            Some(yaw) => yaw,
            None => *self.yaw.insert(self.choose_yaw(sim, motion::current_yaw(&ee))),
        };
        let cup = sim.entity_pose(self.object).pos;
        let grasp = Vec3::new(cup.x, cup.y, Self::rim(sim, self.object).z - BELOW_RIM);
        let steps = self.stage.steps;
        let (leg, then) = match self.stage.now {
            Stage::Approach(a) => {
                let plan = ApproachPlan {
                    grasp: Waypoint::down(grasp, yaw),
                    cruise_z: self.cruise_z(sim, 0.0),
                    low: grasp.z + 0.06,
                    above: (Pace::ClosingIn, Tol::pose(0.004, 0.03)),
                    // The open fingers have 7 mm to spare around the rim.
                    descent: Descent::Stepped { step: 0.005, within: 0.003 },
                    grip: OPEN,
                };
                let (leg, next) = a.leg(sim, steps, &plan);
                if next.is_none() && leg.is_last() {
                    self.held = Held { hold: ee.pos.z - cup.z, start_z: cup.z, at: ee.pos, offset: Vec3::new(ee.pos.x - cup.x, ee.pos.y - cup.y, 0.0) };
                }
                (leg, next.map_or(Stage::Lift, Stage::Approach))
            }
            Stage::Lift => {
                let up = Waypoint::down(Vec3::new(self.held.at.x, self.held.at.y, self.cruise_z(sim, self.held.hold)), yaw);
                if let Some(why) = stages::lift_failure(sim, steps, 30, self.held.start_z, cup.z, 0.02) {
                    return Step::Failed(why);
                }
                let (d, _) = motion::error(sim, &up);
                (Leg::until(stages::Move { to: up, servo: motion::Servo::TRAVEL, grip: CLOSE }, d < 0.01), Stage::Carry)
            }
            Stage::Carry => {
                let over = sim.entity_pose(self.target).pos + self.held.offset;
                (stages::carry(sim, &Vec3::new(over.x, over.y, self.cruise_z(sim, self.held.hold)), motion::orientation(yaw)), Stage::Lower)
            }
            // Down to just above the rim, then held until the cup's foot stays over the
            // target's opening (the taper centres a foot up to 8 mm off).
            Stage::Lower => {
                let below = sim.entity_pose(self.target).pos;
                self.centred_for = if horizontal(&cup, &below) < CENTRED { self.centred_for + 1 } else { 0 };
                let over = below + self.held.offset;
                let wp = Waypoint::down(Vec3::new(over.x, over.y, Self::rim(sim, self.target).z + DROP + self.held.hold), yaw);
                let (d, _) = motion::error(sim, &wp);
                let settled = self.centred_for >= 3;
                (Leg::until(stages::Move { to: wp, servo: motion::Servo::FINE, grip: CLOSE }, d < 0.004 && settled), Stage::Enter)
            }
            // Straight down until the foot is inside the target's mouth (or it sits on
            // something): once let go there, the cup cannot tip out of it.
            Stage::Enter => {
                let wp = Waypoint::down(Vec3::new(ee.pos.x, ee.pos.y, Self::rim(sim, self.target).z - ENTER + self.held.hold), yaw);
                (stages::set_down(sim, &mut self.entering, wp, Pace::Fine, 0.002, 0.001), Stage::Release)
            }
            // Held still while the fingers open and the cup settles into the one below.
            Stage::Release => {
                if steps == 1 {
                    self.released_at = ee.pos;
                }
                (stages::release(steps, 15, Waypoint::down(self.released_at, yaw)), Stage::Retreat)
            }
            Stage::Retreat => {
                let up = Waypoint::down(Vec3::new(self.released_at.x, self.released_at.y, self.cruise_z(sim, 0.0)), yaw);
                (stages::retreat(steps, 12, up, OPEN), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }

    fn describe(&self) -> String {
        format!("stack {}", self.stage)
    }
}
