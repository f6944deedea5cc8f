//! Turning a knob (the stove's) by gripping it and twisting about its axis.
//!
//! Recipe: the approach (rise, come over the knob, descend, grasp), twist it round its hinge,
//! release, retreat.

use vifo_robots::spatial::Vec3;
use vifo_scenes::sim::Sim;

use super::Skill;
use crate::approach::{Approach, ApproachPlan, Descent};
use crate::arm;
use crate::geometry::{self, Grasp, Obstacles, cruise_height};
use crate::motion::{self, Waypoint};
use crate::stages::{self, CLOSE, Leg, OPEN, Pace, Progress, Stages, Step, Tol, gripper_toward};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Approach(Approach),
    Twist,
    Release,
    Retreat,
    Done,
}

/// Turn the knob of `entity` (its body `body`, joint `joint`) until the joint passes `target`.
pub struct Knob {
    entity: usize,
    body: usize,
    joint: String,
    target: f64,
    stage: Stages<Stage>,
    grasp: Option<Grasp>,
    /// Knob angle when the grip closed.
    q_grip: f64,
    cruise_z: f64,
    /// The knob's angle while twisting.
    angles: Progress,
}

const STAGE_LIMIT: usize = 90;

impl Knob {
    pub fn new(entity: usize, body: usize, joint: String, target: f64) -> Self {
        Knob { entity, body, joint, target, stage: Stages::new(Stage::Approach(Approach::Rise), STAGE_LIMIT), grasp: None, q_grip: 0.0, cruise_z: 0.0, angles: Progress::default() }
    }

    fn q(&self, sim: &Sim) -> f64 {
        sim.joint_position(self.entity, &self.joint).unwrap_or(0.0)
    }

    /// The knob's turning axis point (its body origin).
    fn axis_point(&self, sim: &Sim) -> Vec3 {
        sim.body_pose(self.entity, self.body).pos
    }

    fn plan(&self, sim: &Sim) -> Grasp {
        let points = geometry::corners(sim, self.entity, self.body);
        let obstacles = Obstacles::around(sim, usize::MAX);
        let g = geometry::solid_grasp(&points, 0.012, &obstacles).unwrap_or_else(|| {
            let (_, hi) = geometry::bounds(&points);
            let o = self.axis_point(sim);
            Grasp { pos: Vec3::new(o.x, o.y, hi.z - 0.012), yaw: 0.0, width: 0.0, half_gap: 0.03 }
        });
        Grasp { yaw: motion::reachable_yaw(sim, g.yaw), half_gap: g.half_gap.max(0.025), ..g }
    }

    /// The grasp carried around the knob axis by `angle`.
    fn turned(&self, sim: &Sim, g: &Grasp, angle: f64) -> Waypoint {
        let o = self.axis_point(sim);
        Waypoint::down(stages::swing(&o, &Vec3::z(), angle, &(g.pos - o)), g.yaw + angle)
    }
}

impl Skill for Knob {
    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a knob stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        if self.grasp.is_none() {
            self.grasp = Some(self.plan(sim));
        }
        let g = self.grasp.expect("planned");
        let grip = gripper_toward(sim, g.half_gap);
        let steps = self.stage.steps;
        let (leg, then) = match self.stage.now {
            Stage::Approach(a) => {
                if a == Approach::Rise {
                    self.cruise_z = cruise_height(sim, &g.pos, 0.06, g.pos.z + 0.08, None);
                }
                let plan = ApproachPlan {
                    grasp: Waypoint::down(g.pos, g.yaw),
                    cruise_z: self.cruise_z,
                    low: g.pos.z + 0.06,
                    above: (Pace::Fine, Tol::pose(0.003, 0.03)),
                    descent: Descent::Direct,
                    grip,
                };
                let (leg, next) = a.leg(sim, steps, &plan);
                if next.is_none() && leg.is_last() {
                    self.q_grip = self.q(sim);
                    self.angles.clear();
                }
                (leg, next.map_or(Stage::Twist, Stage::Approach))
            }
            // Follow the hinge, leading the knob by a quarter radian around its axis.
            Stage::Twist => {
                let q = self.q(sim);
                if q >= self.target {
                    (Leg::Over, Stage::Release)
                } else {
                    self.angles.record(q);
                    if self.angles.change(9, 15).is_some_and(|c| c < 0.005) {
                        return Step::Failed("the knob stopped turning");
                    }
                    let wp = self.turned(sim, &g, (q - self.q_grip) + 0.25);
                    (Leg::Go(stages::Move { to: wp, servo: motion::Servo::FINE, grip: CLOSE }), Stage::Release)
                }
            }
            Stage::Release => (stages::release(steps, 8, self.turned(sim, &g, self.q(sim) - self.q_grip)), Stage::Retreat),
            Stage::Retreat => {
                let up = Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.08), motion::current_yaw(&ee));
                (stages::retreat(steps, 8, up, OPEN), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }

    fn describe(&self) -> String {
        format!("knob {}", self.stage)
    }
}
