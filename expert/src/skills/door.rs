//! Closing a hinged door (the microwave's) by pushing its outer face shut.
//!
//! Recipe: rise, cross over the push point, lower beside the door, push it round its hinge,
//! back off.

use vifo_robots::spatial::{Vec3, axis_angle};
use vifo_scenes::sim::Sim;

use super::Skill;
use crate::arm;
use crate::geometry::{self, FINGER_HALF_WIDTH, HAND_ABOVE_SITE, Obb, cruise_height};
use crate::motion::{self, Servo, Waypoint};
use crate::stages::{self, CLOSE, Leg, Pace, Progress, Stages, Step, Tol};

/// Where along the door (fraction of the hinge-to-free-edge distance) the fingers push.
const PUSH_AT: f64 = 0.65;
/// Gap between the fingers and the door face while coming down beside it.
const STANDOFF: f64 = 0.03;
/// Pushed until this close to the closed end (LIBERO counts the microwave closed within
/// 0.005 rad).
const CLOSED_WITHIN: f64 = 0.002;
/// The hand's underside ([`HAND_ABOVE_SITE`] over the grip site) stays this much above the
/// door's top edge; the fingers' faces are [`FINGER_HALF_WIDTH`] off the grip site.
const HAND_CLEARANCE: f64 = 0.006;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Over,
    Lower,
    Push,
    Back,
    Done,
}

/// Push the door of `entity` (body `body`, hinge `joint`) to its closed end.
///
/// The closed fingers, pointing down and lined up along the door, press its outer face (the
/// side its handle is on) about two thirds of the way out from the hinge, and follow the arc a
/// little ahead of the door. The hand stays just above the door's top edge, so only the
/// fingers touch it.
pub struct Door {
    entity: usize,
    body: usize,
    joint: String,
    stage: Stages<Stage>,
    cruise_z: f64,
    /// The angle still to go, while pushing.
    to_go: Progress,
}

/// The door's shape at the current angle, in the world.
struct Leaf {
    /// A point on the hinge axis and its direction (rotating about it by +Δ raises q by Δ).
    hinge: Vec3,
    axis: Vec3,
    /// From the hinge toward the free edge (horizontal, unit), and the hinge–free-edge length.
    out: Vec3,
    length: f64,
    /// Outer face normal (unit) and the face's distance from the hinge along it.
    normal: Vec3,
    face: f64,
    /// Height of the top edge.
    top: f64,
}

/// How long a stage may last before the skill gives up (control steps).
const STAGE_LIMIT: usize = 120;

impl Door {
    pub fn new(entity: usize, body: usize, joint: String) -> Self {
        Door { entity, body, joint, stage: Stages::new(Stage::Rise, STAGE_LIMIT), cruise_z: 0.0, to_go: Progress::default() }
    }

    fn q(&self, sim: &Sim) -> f64 {
        sim.joint_position(self.entity, &self.joint).unwrap_or(0.0)
    }

    /// The closed end of the joint's range: the one nearest zero (LIBERO's doors close at 0).
    fn closed_q(&self, sim: &Sim) -> f64 {
        let body = &sim.model().entities[self.entity].model.bodies[self.body];
        body.joint.as_ref().map_or(0.0, |j| if j.range[0].abs() < j.range[1].abs() { j.range[0] } else { j.range[1] })
    }

    /// The door panel (its biggest box), which side is outside (where its other parts, the
    /// handle, stand) and where the hinge is.
    fn leaf(&self, sim: &Sim) -> Leaf {
        let model = &sim.model().entities[self.entity].model.bodies[self.body];
        let pose = sim.body_pose(self.entity, self.body);
        let joint = model.joint.as_ref();
        let hinge = pose.transform_point(&Vec3::from(joint.map_or([0.0; 3], |j| j.pos)));
        let axis = pose.rot * Vec3::from(joint.map_or([0.0, 0.0, 1.0], |j| j.axis));
        let boxes = geometry::body_boxes(sim, self.entity, self.body);
        let volume = |b: &Obb| b.half.x * b.half.y * b.half.z;
        let panel = boxes.iter().copied().max_by(|a, b| volume(a).total_cmp(&volume(b))).expect("doors have boxes");
        let radial = panel.pose.pos - hinge;
        let out = (radial - axis * radial.dot(&axis)).normalize();
        // The panel's thin axis is its normal; the outer side is where the handle is.
        let thin = (0..3).min_by(|&i, &j| panel.half[i].total_cmp(&panel.half[j])).expect("three axes");
        let mut normal: Vec3 = panel.pose.rot.column(thin).into();
        let handle: Vec3 = boxes.iter().map(|b| b.pose.pos - panel.pose.pos).sum();
        if handle.dot(&normal) < 0.0 {
            normal = -normal;
        }
        let along = (0..3).map(|k| panel.half[k] * Vec3::from(panel.pose.rot.column(k)).dot(&out).abs()).sum::<f64>();
        let top = geometry::corners(sim, self.entity, self.body).iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        Leaf {
            hinge,
            axis,
            out,
            length: radial.dot(&out) + along,
            normal,
            face: radial.dot(&normal) + panel.half[thin],
            top,
        }
    }

    /// Grip-site target `gap` off the outer face once the door has turned by `turn` from where
    /// it is, and the finger yaw lying along the door there.
    fn target(&self, leaf: &Leaf, turn: f64, gap: f64) -> (Vec3, f64) {
        let offset = leaf.out * (PUSH_AT * leaf.length) + leaf.normal * (leaf.face + FINGER_HALF_WIDTH + gap);
        let mut p = stages::swing(&leaf.hinge, &leaf.axis, turn, &offset);
        p.z = leaf.top + HAND_CLEARANCE - HAND_ABOVE_SITE;
        (p, geometry::yaw_of_axis(&(axis_angle(&leaf.axis, turn) * leaf.out)))
    }
}

/// The target leads the door by this angle while pushing (radians).
const LEAD: f64 = 0.25;

impl Skill for Door {
    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a door stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        let leaf = self.leaf(sim);
        let to_go = self.closed_q(sim) - self.q(sim);
        let (start, yaw) = self.target(&leaf, 0.0, STANDOFF);
        let yaw = motion::reachable_yaw(sim, yaw);
        let (leg, then) = match self.stage.now {
            Stage::Rise => {
                self.cruise_z = cruise_height(sim, &start, 0.08, start.z + 0.08, None);
                (stages::rise(sim, self.cruise_z, motion::orientation(yaw), CLOSE), Stage::Over)
            }
            Stage::Over => (stages::cross(sim, &start, self.cruise_z, motion::orientation(yaw), Tol::pose(0.01, 0.05), CLOSE), Stage::Lower),
            Stage::Lower => {
                let leg = stages::reach(sim, Waypoint::down(start, yaw), Pace::ClosingIn, Tol::pose(0.006, 0.05), CLOSE);
                if leg.is_last() {
                    self.to_go.clear();
                }
                (leg, Stage::Push)
            }
            // Follow the hinge, the fingers leading the door round its arc.
            Stage::Push => {
                if to_go.abs() < CLOSED_WITHIN {
                    (Leg::Over, Stage::Back)
                } else {
                    self.to_go.record(to_go);
                    if self.to_go.change(14, 20).is_some_and(|c| c.abs() < 0.005) {
                        return Step::Failed("the door stopped moving");
                    }
                    let (p, yaw) = self.target(&leaf, to_go.signum() * LEAD.min(to_go.abs() + 0.05), -0.004);
                    let wp = Waypoint::down(p, motion::nearest_yaw(yaw, motion::current_yaw(&ee)));
                    (Leg::Go(stages::Move { to: wp, servo: Servo::TRAVEL, grip: CLOSE }), Stage::Back)
                }
            }
            Stage::Back => {
                let away = ee.pos + leaf.normal * 0.04 + Vec3::new(0.0, 0.0, 0.06);
                (stages::retreat(self.stage.steps, 10, Waypoint::down(away, motion::current_yaw(&ee)), CLOSE), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }

    fn describe(&self) -> String {
        format!("door close {}", self.stage)
    }
}
