//! Turning a knob (the stove's) by gripping it and twisting about its axis.

use vifo_robots::spatial::{Vec3, axis_angle};

use crate::geometry::{self, Grasp, Obstacles};
use crate::motion::{self, Servo, Waypoint};
use crate::skill::{CLOSE, OPEN, Step, climb, cruise_height, gripper_toward};
use vifo_scenes::sim::Sim;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Above,
    Descend,
    Grip,
    Twist,
    Release,
    Retreat,
}

/// Turn the knob of `entity` (its body `body`, joint `joint`) until the joint passes `target`.
pub struct Knob {
    entity: usize,
    body: usize,
    joint: String,
    target: f64,
    stage: Stage,
    stage_steps: usize,
    grasp: Option<Grasp>,
    /// Knob angle when the grip closed.
    q_grip: f64,
    cruise_z: f64,
    history: Vec<f64>,
}

const STAGE_LIMIT: usize = 90;

impl Knob {
    pub fn new(entity: usize, body: usize, joint: String, target: f64) -> Self {
        Knob { entity, body, joint, target, stage: Stage::Rise, stage_steps: 0, grasp: None, q_grip: 0.0, cruise_z: 0.0, history: Vec::new() }
    }

    pub fn describe(&self) -> String {
        format!("knob {:?} step {}", self.stage, self.stage_steps)
    }

    fn next(&mut self, stage: Stage) {
        self.stage = stage;
        self.stage_steps = 0;
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
    fn turned(&self, sim: &Sim, angle: f64) -> Waypoint {
        let g = self.grasp.expect("planned");
        let o = self.axis_point(sim);
        let offset = axis_angle(&Vec3::z(), angle) * (g.pos - o);
        Waypoint::down(o + offset, g.yaw + angle)
    }

    pub fn step(&mut self, sim: &Sim) -> Step {
        self.stage_steps += 1;
        if self.stage_steps > STAGE_LIMIT {
            return Step::Failed("a knob stage took too long");
        }
        let ee = sim.model().robot.grip_site_pose(sim.world());
        if self.grasp.is_none() {
            self.grasp = Some(self.plan(sim));
        }
        let g = self.grasp.expect("planned");
        let grip = gripper_toward(sim, g.half_gap);
        match self.stage {
            Stage::Rise => {
                self.cruise_z = cruise_height(sim, &g.pos, 0.06, g.pos.z + 0.08, None);
                let Some(up) = climb(&ee.pos, self.cruise_z) else {
                    self.next(Stage::Above);
                    return self.step(sim);
                };
                Step::Act(Servo::TRAVEL.act(sim, &Waypoint::down(up, g.yaw), grip))
            }
            Stage::Above => {
                let horizontal = ((ee.pos.x - g.pos.x).powi(2) + (ee.pos.y - g.pos.y).powi(2)).sqrt();
                let z = if horizontal > 0.03 { self.cruise_z } else { g.pos.z + 0.06 };
                let wp = Waypoint::down(Vec3::new(g.pos.x, g.pos.y, z), g.yaw);
                let (d, r) = motion::error(sim, &wp);
                if d < 0.003 && r < 0.03 {
                    self.next(Stage::Descend);
                }
                Step::Act(Servo::FINE.act(sim, &wp, grip))
            }
            Stage::Descend => {
                let wp = Waypoint::down(g.pos, g.yaw);
                if (ee.pos - g.pos).norm() < 0.004 {
                    self.next(Stage::Grip);
                }
                Step::Act(Servo::FINE.act(sim, &wp, grip))
            }
            Stage::Grip => {
                if self.stage_steps >= 12 {
                    self.q_grip = self.q(sim);
                    self.history.clear();
                    self.next(Stage::Twist);
                }
                Step::Act(Servo::FINE.act(sim, &Waypoint::down(g.pos, g.yaw), CLOSE))
            }
            Stage::Twist => {
                let q = self.q(sim);
                if q >= self.target {
                    self.next(Stage::Release);
                    return self.step(sim);
                }
                self.history.push(q);
                let n = self.history.len();
                if n > 15 && self.history[n - 1] - self.history[n - 10] < 0.005 {
                    return Step::Failed("the knob stopped turning");
                }
                // Lead the knob by a quarter radian around its axis.
                let wp = self.turned(sim, (q - self.q_grip) + 0.25);
                Step::Act(Servo::FINE.act(sim, &wp, CLOSE))
            }
            Stage::Release => {
                if self.stage_steps >= 8 {
                    self.next(Stage::Retreat);
                }
                let turned = self.q(sim) - self.q_grip;
                Step::Act(Servo::FINE.act(sim, &self.turned(sim, turned), OPEN))
            }
            Stage::Retreat => {
                if self.stage_steps >= 8 {
                    return Step::Done;
                }
                let up = Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.08), motion::current_yaw(&ee));
                Step::Act(Servo::TRAVEL.act(sim, &up, OPEN))
            }
        }
    }
}
