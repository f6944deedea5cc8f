//! Opening and closing drawers by their handle.
//!
//! Recipe: rise, cross to a stand-off in front of the handle, lower to it, approach the handle
//! (or the front wall), grasp it when pulling, follow the slide out or in, release, back off,
//! and turn upright again.

use vifo_robots::spatial::{Mat3, Vec3, rotation_vector};
use vifo_scenes::sim::{RegionPlace, Sim};

use super::Skill;
use crate::arm;
use crate::geometry::{self, Obb, cruise_height};
use crate::motion::{self, Servo, Waypoint};
use crate::stages::{self, CLOSE, Leg, OPEN, Pace, Progress, Stages, Step, Tol, gripper_toward};

/// What to do with the drawer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawerGoal {
    /// Pull it out (LIBERO's cabinets open toward negative joint positions).
    Open,
    /// Pull an already open drawer further out, by its front wall from inside (the hand
    /// cannot take the handle of a drawer that sticks out toward the robot without the arm
    /// sweeping what stands in front of the cabinet).
    Widen,
    /// Push it in, pointing down in front of the handle.
    Close,
    /// The last centimetres of a close, pitched into the front with the fingertips on the
    /// handle: a hand pointing down meets the handle of the drawer above before a lower drawer
    /// is fully in, and, pitched, the arm would sweep what stands in front of the cabinet
    /// while the drawer is far out.
    Shut,
}

/// Joint position the drawer is pulled to when opening, and pushed past when closing
/// (LIBERO: open below -0.14 m, closed above 0).
const OPEN_TO: f64 = -0.156;
const CLOSED_PAST: f64 = 0.002;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Rise,
    Over,
    Lower,
    Approach,
    Grip,
    Move,
    Release,
    Back,
    Upright,
    Done,
}

/// The space an opening drawer takes (see [`Drawer::sweep`]); `along`/`across` are coordinates
/// along the horizontal opening direction `dir` and perpendicular to it.
pub struct Sweep {
    pub dir: Vec3,
    pub along: (f64, f64),
    pub across: (f64, f64),
    pub bottom: f64,
}

/// Direction a drawer moves when it opens (world, horizontal).
fn open_dir(sim: &Sim, entity: usize, body: usize) -> Vec3 {
    let b = &sim.model().entities[entity].model.bodies[body];
    let axis = Vec3::from(b.joint.as_ref().map_or([0.0, 1.0, 0.0], |j| j.axis));
    let world = sim.body_pose(entity, body).rot * axis;
    Vec3::new(-world.x, -world.y, 0.0).normalize()
}

/// The drawer (entity, body, joint) a region lives on, if it is a drawer's region.
pub fn drawer_of(sim: &Sim, region: &str) -> Option<(usize, usize, String)> {
    let RegionPlace::Site { entity, site } = &sim.model().region(region)?.place else { return None };
    let model = sim.model().entities[*entity].model;
    let body = model.sites[*site].body;
    let joint = model.bodies[body].joint.as_ref()?;
    Some((*entity, body, joint.name.clone()))
}

/// Where to drop an object of horizontal `radius` into a drawer's `region`: its centre, moved
/// out along the drawer's travel as far as needed for the object to come straight down clear
/// of what overhangs the drawer's back part (the cabinet, the drawers above and their
/// handles), but no further than the drawer's front wall allows.
pub fn drop_point(sim: &Sim, region: &str, radius: f64) -> Option<[f64; 2]> {
    let (entity, body, _) = drawer_of(sim, region)?;
    let bounds = sim.region_box(region)?;
    let dir = open_dir(sim, entity, body);
    let across = Vec3::new(-dir.y, dir.x, 0.0);
    let inside = Obb { pose: bounds.pose, half: bounds.half_size };
    let room: Vec<Vec3> = geometry::obb_corners(&inside);
    let (front, bottom, span) = (geometry::extent(&room, &dir).1, geometry::extent(&room, &Vec3::z()).0, geometry::extent(&room, &across));
    let overhang = (0..sim.model().entities[entity].model.bodies.len())
        .filter(|&b| b != body)
        .flat_map(|b| geometry::body_boxes(sim, entity, b))
        .map(|b| geometry::obb_corners(&b))
        .filter(|c| {
            let v = geometry::extent(c, &across);
            geometry::extent(c, &Vec3::z()).0 > bottom + 0.01 && v.1 > span.0 && v.0 < span.1
        })
        .map(|c| geometry::extent(&c, &dir).1)
        .fold(f64::NEG_INFINITY, f64::max);
    let centre = bounds.pose.pos;
    let (lo, hi) = (overhang + radius + 0.005, front - radius);
    let at = if lo <= hi { centre.dot(&dir).clamp(lo, hi) } else { 0.5 * (lo + hi) };
    let p = centre + dir * (at - centre.dot(&dir));
    Some([p.x, p.y])
}

pub struct Drawer {
    entity: usize,
    body: usize,
    joint: String,
    goal: DrawerGoal,
    stage: Stages<Stage>,
    cruise_z: f64,
    /// The joint's position while the drawer moves.
    travel: Progress,
    /// A close stalled near the end: back off, then shut.
    shut_next: bool,
}

const STAGE_LIMIT: usize = 90;

/// Widening: the grip site this far behind the front wall's inner face (finger half-width and
/// some room for the servo's error) and this far below its top edge.
const WIDEN_GAP: f64 = 0.03;
const WIDEN_DEPTH: f64 = 0.022;
/// Shutting: the grip site this far in front of the handle (the fingertips reach 9 mm past it).
const CLOSE_GAP: f64 = 0.013;
/// A close that stalls past this joint position is finished by shutting. Pushing a bottom drawer
/// in with the hand pointing down, the Panda's forearm (link 5's hull) meets the cabinet's front
/// 5-7 cm before the drawer is in.
const SHUT_FROM: f64 = -0.08;

/// A drawer open at least this far (joint position) has room behind its front wall for the
/// fingers, and is widened from inside rather than taken by the handle.
pub const PARTLY_OPEN: f64 = -0.09;

/// How far the gripper points down from level when it takes a handle (radians).
const PITCH: f64 = 0.4;

impl Drawer {
    pub fn new(entity: usize, body: usize, joint: String, goal: DrawerGoal) -> Self {
        Drawer { entity, body, joint, goal, stage: Stages::new(Stage::Rise, STAGE_LIMIT), cruise_z: 0.0, travel: Progress::default(), shut_next: false }
    }

    fn q(&self, sim: &Sim) -> f64 {
        sim.joint_position(self.entity, &self.joint).unwrap_or(0.0)
    }

    fn open_dir(&self, sim: &Sim) -> Vec3 {
        open_dir(sim, self.entity, self.body)
    }

    /// Where the drawer will be once pulled open: its extent along the opening direction
    /// (`along`, from the back of the closed drawer to the front of the open one), across it, and
    /// the height of its underside. Objects standing in that space block the hand later.
    pub fn sweep(&self, sim: &Sim) -> Sweep {
        let dir = self.open_dir(sim);
        let across = Vec3::new(-dir.y, dir.x, 0.0);
        let travel = (self.q(sim) - OPEN_TO).max(0.0);
        let points = geometry::corners(sim, self.entity, self.body);
        let (lo, hi) = geometry::extent(&points, &dir);
        let bottom = geometry::extent(&points, &Vec3::z()).0;
        Sweep { dir, along: (lo, hi + travel), across: geometry::extent(&points, &across), bottom }
    }

    /// The handle: the drawer's box that sticks out furthest in the opening direction.
    fn handle(&self, sim: &Sim) -> Obb {
        let dir = self.open_dir(sim);
        geometry::body_boxes(sim, self.entity, self.body)
            .into_iter()
            .max_by(|a, b| a.pose.pos.dot(&dir).total_cmp(&b.pose.pos.dot(&dir)))
            .expect("drawers have boxes")
    }

    /// Side grasp: pointing into the drawer front and pitched down by [`PITCH`], fingers
    /// pinching the bar across its height. The hand is 20 cm long along the finger axis; level,
    /// its lower end would hang 10 cm below a low handle (onto the table or a plate in front of
    /// the cabinet), pitched it stays near the handle's height.
    fn side_orientation(&self, sim: &Sim) -> Mat3 {
        let into = -self.open_dir(sim);
        let up = Vec3::z();
        let (s, c) = (libm::sin(PITCH), libm::cos(PITCH));
        let z = into * c - up * s;
        // Opening pinches the bar across its height; shutting pushes with the closed fingers
        // side by side along the bar, so the 20 cm hand lies flat instead of reaching down.
        let across = if self.goal == DrawerGoal::Shut { into.cross(&up) } else { up * c + into * s };
        // Of the two hands pinching the bar (a half turn apart about the approach axis), the
        // one the wrist reaches, with the smaller turn from where it is first.
        let current = arm::of(sim).grip_site().rot;
        let hand = |x: Vec3| Mat3::from_columns(&[x, z.cross(&x), z]);
        let turn = |m: &Mat3| rotation_vector(&(m * current.transpose())).norm();
        let (a, b) = (hand(across), hand(-across));
        let (first, second) = if turn(&a) <= turn(&b) { (a, b) } else { (b, a) };
        let arm = arm::of(sim);
        if arm.wrist_reaches(&first) || !arm.wrist_reaches(&second) { first } else { second }
    }

    /// Direction the gripper comes in along (its approach axis): pitched into the front when
    /// opening or shutting, straight down when widening, straight in when closing.
    fn approach(&self, sim: &Sim) -> Vec3 {
        match self.goal {
            DrawerGoal::Open | DrawerGoal::Shut => self.side_orientation(sim) * Vec3::z(),
            DrawerGoal::Widen => -Vec3::z(),
            DrawerGoal::Close => -self.open_dir(sim),
        }
    }

    fn push_yaw(&self, sim: &Sim) -> f64 {
        let dir = self.open_dir(sim);
        // Fingers side by side across the front (finger axis perpendicular to the motion).
        let across = Vec3::new(-dir.y, dir.x, 0.0);
        motion::reachable_yaw(sim, geometry::yaw_of_axis(&across))
    }

    /// Where the gripper works: on the handle (open), behind the front wall (widen), just in
    /// front of the handle (close) or with the fingertips there (shut).
    fn work_point(&self, sim: &Sim) -> Vec3 {
        let h = self.handle(sim).pose.pos;
        match self.goal {
            DrawerGoal::Open => h,
            DrawerGoal::Widen => {
                let (dir, wall) = (self.open_dir(sim), self.front_wall(sim));
                let inner = geometry::extent(&wall, &dir).0;
                let top = geometry::extent(&wall, &Vec3::z()).1;
                let p = h + dir * (inner - WIDEN_GAP - h.dot(&dir));
                Vec3::new(p.x, p.y, top - WIDEN_DEPTH)
            }
            DrawerGoal::Close => h + self.open_dir(sim) * 0.035,
            DrawerGoal::Shut => {
                let dir = self.open_dir(sim);
                let handle = self.handle(sim);
                let front = geometry::extent(&geometry::obb_corners(&handle), &dir).1 - h.dot(&dir);
                h + dir * (front + CLOSE_GAP)
            }
        }
    }

    /// Corners of the drawer's front wall: of the boxes spanning most of its width, the one
    /// furthest out that stands up (not the floor).
    fn front_wall(&self, sim: &Sim) -> Vec<Vec3> {
        let dir = self.open_dir(sim);
        let across = Vec3::new(-dir.y, dir.x, 0.0);
        let boxes: Vec<Vec<Vec3>> = geometry::body_boxes(sim, self.entity, self.body).iter().map(geometry::obb_corners).collect();
        let size = |c: &Vec<Vec3>, axis: &Vec3| {
            let (a, b) = geometry::extent(c, axis);
            b - a
        };
        let widest = boxes.iter().map(|c| size(c, &across)).fold(0.0, f64::max);
        boxes
            .into_iter()
            .filter(|c| size(c, &across) > 0.6 * widest && size(c, &Vec3::z()) > size(c, &dir))
            .max_by(|a, b| geometry::extent(a, &dir).1.total_cmp(&geometry::extent(b, &dir).1))
            .expect("drawers have a front wall")
    }

    /// How the gripper is turned: pitched into the front when it takes or shuts the handle,
    /// pointing down when it pushes.
    fn rot(&self, sim: &Sim) -> Mat3 {
        match self.goal {
            DrawerGoal::Open | DrawerGoal::Shut => self.side_orientation(sim),
            DrawerGoal::Widen | DrawerGoal::Close => motion::orientation(self.push_yaw(sim)),
        }
    }

    fn waypoint(&self, sim: &Sim, pos: Vec3) -> Waypoint {
        Waypoint { pos, rot: self.rot(sim) }
    }

    fn done(&self, sim: &Sim) -> bool {
        match self.goal {
            DrawerGoal::Open | DrawerGoal::Widen => self.q(sim) < OPEN_TO,
            DrawerGoal::Close | DrawerGoal::Shut => self.q(sim) > CLOSED_PAST,
        }
    }
}

impl Skill for Drawer {
    fn describe(&self) -> String {
        format!("drawer {:?} {}", self.goal, self.stage)
    }

    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("a drawer stage took too long");
        }
        let ee = arm::of(sim).grip_site();
        let dir = self.open_dir(sim);
        let work = self.work_point(sim);
        // Stand-off back along the approach axis: room to come around the handle when taking
        // it, little when pushing (the hand and arm trail behind, toward what stands in front).
        let back = if self.goal == DrawerGoal::Shut { 0.04 } else { 0.12 };
        let standoff = work - self.approach(sim) * back;
        let grip = match self.goal {
            DrawerGoal::Open => gripper_toward(sim, 0.022),
            DrawerGoal::Widen | DrawerGoal::Close | DrawerGoal::Shut => CLOSE,
        };
        let steps = self.stage.steps;
        let (leg, then) = match self.stage.now {
            Stage::Rise => {
                // Cross at the stand-off's own height (already back from the handle) unless
                // something on the way stands taller.
                self.cruise_z = cruise_height(sim, &standoff, 0.08, standoff.z, None);
                (stages::rise(sim, self.cruise_z, self.rot(sim), grip), Stage::Over)
            }
            Stage::Over => (stages::cross(sim, &standoff, self.cruise_z, self.rot(sim), Tol::pose(0.015, 0.08), grip), Stage::Lower),
            Stage::Lower => (stages::reach(sim, self.waypoint(sim, standoff), Pace::Travel, Tol::pose(0.006, 0.04), grip), Stage::Approach),
            Stage::Approach => {
                let leg = stages::reach(sim, self.waypoint(sim, work), Pace::ClosingIn, Tol::pos(0.004), grip);
                if leg.is_last() {
                    self.travel.clear();
                }
                (leg, if self.goal == DrawerGoal::Open { Stage::Grip } else { Stage::Move })
            }
            Stage::Grip => (stages::grasp(steps, 12, self.waypoint(sim, work)), Stage::Move),
            // Follow the slide, leading the drawer a few centimetres along its travel.
            Stage::Move => {
                if self.done(sim) {
                    (Leg::Over, Stage::Release)
                } else {
                    let lead = match self.goal {
                        DrawerGoal::Open | DrawerGoal::Widen => 0.04,
                        DrawerGoal::Close | DrawerGoal::Shut => -0.04,
                    };
                    self.travel.record(self.q(sim));
                    if self.travel.change(9, 15).is_some_and(|c| c.abs() < 0.001) {
                        if self.goal == DrawerGoal::Close && self.q(sim) > SHUT_FROM {
                            self.shut_next = true;
                            (Leg::Over, Stage::Back)
                        } else {
                            return Step::Failed("the drawer stopped moving");
                        }
                    } else {
                        // A pulled handle follows the hand at full speed; a push keeps to the fine servo.
                        let servo = if self.goal == DrawerGoal::Open { Servo::TRAVEL } else { Servo::FINE };
                        (Leg::Go(stages::Move { to: self.waypoint(sim, work + dir * lead), servo, grip: CLOSE }), Stage::Release)
                    }
                }
            }
            Stage::Release => {
                let n = if matches!(self.goal, DrawerGoal::Widen | DrawerGoal::Close) { 0 } else { 8 };
                (stages::release(steps, n, self.waypoint(sim, ee.pos)), Stage::Back)
            }
            Stage::Back => {
                let away = match self.goal {
                    DrawerGoal::Open | DrawerGoal::Shut => ee.pos + dir * 0.06,
                    DrawerGoal::Widen => ee.pos + Vec3::new(0.0, 0.0, 0.08),
                    DrawerGoal::Close => ee.pos + dir * 0.05 + Vec3::new(0.0, 0.0, 0.05),
                };
                let leg = stages::retreat(steps, 8, self.waypoint(sim, away), OPEN);
                let then = if !matches!(leg, Leg::Over) {
                    Stage::Back
                } else if self.shut_next {
                    // A close stalled near the end: shut it, pitched, from the top.
                    self.shut_next = false;
                    self.goal = DrawerGoal::Shut;
                    Stage::Rise
                } else if matches!(self.goal, DrawerGoal::Widen | DrawerGoal::Close) {
                    Stage::Done
                } else {
                    Stage::Upright
                };
                (leg, then)
            }
            Stage::Upright => {
                // Turn back to pointing down by tipping about the handle's axis, which leaves
                // the finger axis along the drawer's travel (the wrist's natural way round).
                let into = -dir;
                let finger = ee.rot * Vec3::x();
                let axis = if finger.dot(&Vec3::z()) >= 0.0 { into } else { -into };
                let wp = Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.03), geometry::yaw_of_axis(&axis));
                let (_, r) = motion::error(sim, &wp);
                (Leg::unless(r < 0.2 || steps >= 25, stages::Move { to: wp, servo: Servo::TRAVEL, grip: OPEN }), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }
}
