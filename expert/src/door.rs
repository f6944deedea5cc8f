//! Closing a hinged door (the microwave's) by pushing its outer face shut.

use vifo_robots::spatial::{Vec3, axis_angle};

use crate::geometry::{self, FINGER_HALF_WIDTH, HAND_ABOVE_SITE, Obb};
use crate::motion::{self, Servo, Waypoint};
use crate::skill::{CLOSE, Step, climb, cruise_height};
use vifo_scenes::sim::Sim;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Over,
    Lower,
    Push,
    Back,
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
    stage: Stage,
    stage_steps: usize,
    cruise_z: f64,
    history: Vec<f64>,
}

const STAGE_LIMIT: usize = 120;
/// Where along the door (fraction of the hinge-to-free-edge distance) the fingers push.
const PUSH_AT: f64 = 0.65;
/// Gap between the fingers and the door face while coming down beside it.
const STANDOFF: f64 = 0.03;
/// The target leads the door by this angle while pushing (radians).
const LEAD: f64 = 0.25;
/// Pushed until this close to the closed end (LIBERO counts the microwave closed within
/// 0.005 rad).
const CLOSED_WITHIN: f64 = 0.002;
/// The hand's underside ([`HAND_ABOVE_SITE`] over the grip site) stays this much above the
/// door's top edge; the fingers' faces are [`FINGER_HALF_WIDTH`] off the grip site.
const HAND_CLEARANCE: f64 = 0.006;

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

impl Door {
    pub fn new(entity: usize, body: usize, joint: String) -> Self {
        Door { entity, body, joint, stage: Stage::Rise, stage_steps: 0, cruise_z: 0.0, history: Vec::new() }
    }

    pub fn describe(&self) -> String {
        format!("door close {:?} step {}", self.stage, self.stage_steps)
    }

    fn next(&mut self, stage: Stage) {
        self.stage = stage;
        self.stage_steps = 0;
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
        let rot = axis_angle(&leaf.axis, turn);
        let offset = leaf.out * (PUSH_AT * leaf.length) + leaf.normal * (leaf.face + FINGER_HALF_WIDTH + gap);
        let mut p = leaf.hinge + rot * offset;
        p.z = leaf.top + HAND_CLEARANCE - HAND_ABOVE_SITE;
        (p, geometry::yaw_of_axis(&(rot * leaf.out)))
    }

    pub fn step(&mut self, sim: &Sim) -> Step {
        self.stage_steps += 1;
        if self.stage_steps > STAGE_LIMIT {
            return Step::Failed("a door stage took too long");
        }
        let ee = sim.model().robot.grip_site_pose(sim.world());
        let leaf = self.leaf(sim);
        let to_go = self.closed_q(sim) - self.q(sim);
        let (start, yaw) = self.target(&leaf, 0.0, STANDOFF);
        let yaw = motion::reachable_yaw(sim, yaw);
        match self.stage {
            Stage::Rise => {
                self.cruise_z = cruise_height(sim, &start, 0.08, start.z + 0.08, None);
                let Some(up) = climb(&ee.pos, self.cruise_z) else {
                    self.next(Stage::Over);
                    return self.step(sim);
                };
                Step::Act(Servo::TRAVEL.act(sim, &Waypoint::down(up, yaw), CLOSE))
            }
            Stage::Over => {
                let wp = Waypoint::down(Vec3::new(start.x, start.y, self.cruise_z), yaw);
                let (d, r) = motion::error(sim, &wp);
                if d < 0.01 && r < 0.05 {
                    self.next(Stage::Lower);
                }
                Step::Act(Servo::TRAVEL.act(sim, &wp, CLOSE))
            }
            Stage::Lower => {
                let wp = Waypoint::down(start, yaw);
                let (d, r) = motion::error(sim, &wp);
                if d < 0.006 && r < 0.05 {
                    self.history.clear();
                    self.next(Stage::Push);
                }
                Step::Act(Servo::closing_in(d).act(sim, &wp, CLOSE))
            }
            Stage::Push => {
                if to_go.abs() < CLOSED_WITHIN {
                    self.next(Stage::Back);
                    return self.step(sim);
                }
                self.history.push(to_go);
                let n = self.history.len();
                if n > 20 && (self.history[n - 15] - to_go).abs() < 0.005 {
                    return Step::Failed("the door stopped moving");
                }
                let (p, yaw) = self.target(&leaf, to_go.signum() * LEAD.min(to_go.abs() + 0.05), -0.004);
                let wp = Waypoint::down(p, motion::nearest_yaw(yaw, motion::current_yaw(&ee)));
                Step::Act(Servo::TRAVEL.act(sim, &wp, CLOSE))
            }
            Stage::Back => {
                if self.stage_steps >= 10 {
                    return Step::Done;
                }
                let away = ee.pos + leaf.normal * 0.04 + Vec3::new(0.0, 0.0, 0.06);
                Step::Act(Servo::TRAVEL.act(sim, &Waypoint::down(away, motion::current_yaw(&ee)), CLOSE))
            }
        }
    }
}
