//! Opening and closing drawers by their handle.

use vifo_robots::spatial::{Mat3, Vec3, rotation_vector};

use super::geometry::{self, Obb};
use super::motion::{self, Servo, Waypoint};
use super::skill::{CLOSE, OPEN, Step, gripper_toward, path_height};
use crate::sim::Sim;

/// What to do with the drawer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawerGoal {
    /// Pull it out (LIBERO's cabinets open toward negative joint positions).
    Open,
    Close,
}

/// Joint position the drawer is pulled to when opening, and pushed past when closing
/// (LIBERO: open below -0.14 m, closed above 0).
const OPEN_TO: f64 = -0.152;
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
}

/// The space an opening drawer takes (see [`Drawer::sweep`]); `along`/`across` are coordinates
/// along the horizontal opening direction `dir` and perpendicular to it.
pub struct Sweep {
    pub dir: Vec3,
    pub along: (f64, f64),
    pub across: (f64, f64),
    pub bottom: f64,
}

pub struct Drawer {
    entity: usize,
    body: usize,
    joint: String,
    goal: DrawerGoal,
    stage: Stage,
    stage_steps: usize,
    cruise_z: f64,
    last_q: Vec<f64>,
}

const STAGE_LIMIT: usize = 90;

/// How far the gripper points down from level when it takes a handle (radians).
const PITCH: f64 = 0.4;

impl Drawer {
    pub fn new(entity: usize, body: usize, joint: String, goal: DrawerGoal) -> Self {
        Drawer { entity, body, joint, goal, stage: Stage::Rise, stage_steps: 0, cruise_z: 0.0, last_q: Vec::new() }
    }

    pub fn describe(&self) -> String {
        format!("drawer {:?} {:?} step {}", self.goal, self.stage, self.stage_steps)
    }

    fn next(&mut self, stage: Stage) {
        self.stage = stage;
        self.stage_steps = 0;
    }

    fn q(&self, sim: &Sim) -> f64 {
        sim.joint_position(self.entity, &self.joint).unwrap_or(0.0)
    }

    /// Direction the drawer moves when it opens (world, horizontal).
    fn open_dir(&self, sim: &Sim) -> Vec3 {
        let body = &sim.model().entities[self.entity].model.bodies[self.body];
        let axis = Vec3::from(body.joint.as_ref().map_or([0.0, 1.0, 0.0], |j| j.axis));
        let world = sim.body_pose(self.entity, self.body).rot * axis;
        let flat = Vec3::new(-world.x, -world.y, 0.0);
        flat.normalize()
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
        let across = up * c + into * s;
        // Of the two hands pinching the bar (a half turn apart about the approach axis), the
        // one the wrist reaches, with the smaller turn from where it is first.
        let current = sim.model().robot.grip_site_pose(sim.world()).rot;
        let hand = |x: Vec3| Mat3::from_columns(&[x, z.cross(&x), z]);
        let turn = |m: &Mat3| rotation_vector(&(m * current.transpose())).norm();
        let (a, b) = (hand(across), hand(-across));
        let (first, second) = if turn(&a) <= turn(&b) { (a, b) } else { (b, a) };
        if motion::wrist_reaches(sim, &first) || !motion::wrist_reaches(sim, &second) { first } else { second }
    }

    /// Direction the gripper comes in along when opening (its approach axis), or straight in
    /// when closing.
    fn approach(&self, sim: &Sim) -> Vec3 {
        match self.goal {
            DrawerGoal::Open => self.side_orientation(sim) * Vec3::z(),
            DrawerGoal::Close => -self.open_dir(sim),
        }
    }

    fn push_yaw(&self, sim: &Sim) -> f64 {
        let dir = self.open_dir(sim);
        // Fingers side by side across the front (finger axis perpendicular to the motion).
        let across = Vec3::new(-dir.y, dir.x, 0.0);
        motion::reachable_yaw(sim, geometry::yaw_of_axis(&across))
    }

    /// Where the gripper works: on the handle (open) or just in front of it (close).
    fn work_point(&self, sim: &Sim) -> Vec3 {
        let h = self.handle(sim).pose.pos;
        match self.goal {
            DrawerGoal::Open => h,
            DrawerGoal::Close => h + self.open_dir(sim) * 0.035,
        }
    }

    fn waypoint(&self, sim: &Sim, pos: Vec3) -> Waypoint {
        match self.goal {
            DrawerGoal::Open => Waypoint { pos, rot: self.side_orientation(sim) },
            DrawerGoal::Close => Waypoint::down(pos, self.push_yaw(sim)),
        }
    }

    fn done(&self, sim: &Sim) -> bool {
        match self.goal {
            DrawerGoal::Open => self.q(sim) < OPEN_TO,
            DrawerGoal::Close => self.q(sim) > CLOSED_PAST,
        }
    }

    pub fn step(&mut self, sim: &Sim) -> Step {
        self.stage_steps += 1;
        if self.stage_steps > STAGE_LIMIT {
            return Step::Failed("a drawer stage took too long");
        }
        let ee = sim.model().robot.grip_site_pose(sim.world());
        let dir = self.open_dir(sim);
        let work = self.work_point(sim);
        // Stand-off back along the approach axis.
        let standoff = work - self.approach(sim) * 0.12;
        let grip = match self.goal {
            DrawerGoal::Open => gripper_toward(sim, 0.022),
            DrawerGoal::Close => CLOSE,
        };
        match self.stage {
            Stage::Rise => {
                let path_top = path_height(sim, [ee.pos.x, ee.pos.y], [standoff.x, standoff.y], 0.1, None);
                self.cruise_z = (path_top + 0.08).max(work.z + 0.10);
                if ee.pos.z >= self.cruise_z - 0.02 {
                    self.next(Stage::Over);
                    return self.step(sim);
                }
                Step::Act(Servo::TRAVEL.act(sim, &self.waypoint(sim, Vec3::new(ee.pos.x, ee.pos.y, self.cruise_z)), grip))
            }
            Stage::Over => {
                let wp = self.waypoint(sim, Vec3::new(standoff.x, standoff.y, self.cruise_z));
                let (d, r) = motion::error(sim, &wp);
                if d < 0.015 && r < 0.08 {
                    self.next(Stage::Lower);
                }
                Step::Act(Servo::TRAVEL.act(sim, &wp, grip))
            }
            Stage::Lower => {
                let wp = self.waypoint(sim, standoff);
                let (d, r) = motion::error(sim, &wp);
                if d < 0.006 && r < 0.04 {
                    self.next(Stage::Approach);
                }
                Step::Act(Servo::TRAVEL.act(sim, &wp, grip))
            }
            Stage::Approach => {
                let wp = self.waypoint(sim, work);
                let (d, _) = motion::error(sim, &wp);
                if d < 0.004 {
                    self.last_q.clear();
                    self.next(if self.goal == DrawerGoal::Open { Stage::Grip } else { Stage::Move });
                }
                Step::Act(Servo::closing_in(d).act(sim, &wp, grip))
            }
            Stage::Grip => {
                if self.stage_steps >= 12 {
                    self.next(Stage::Move);
                }
                Step::Act(Servo::FINE.act(sim, &self.waypoint(sim, work), CLOSE))
            }
            Stage::Move => {
                if self.done(sim) {
                    self.next(Stage::Release);
                    return self.step(sim);
                }
                // Lead the drawer a few centimetres along its travel.
                let lead = match self.goal {
                    DrawerGoal::Open => dir * 0.04,
                    DrawerGoal::Close => -dir * 0.04,
                };
                self.last_q.push(self.q(sim));
                let n = self.last_q.len();
                if n > 15 && (self.last_q[n - 10] - self.last_q[n - 1]).abs() < 0.001 {
                    return Step::Failed("the drawer stopped moving");
                }
                Step::Act(Servo::FINE.act(sim, &self.waypoint(sim, work + lead), CLOSE))
            }
            Stage::Release => {
                if self.stage_steps >= 8 || self.goal == DrawerGoal::Close {
                    self.next(Stage::Back);
                }
                Step::Act(Servo::FINE.act(sim, &self.waypoint(sim, ee.pos), OPEN))
            }
            Stage::Back => {
                let away = match self.goal {
                    DrawerGoal::Open => ee.pos + dir * 0.06,
                    DrawerGoal::Close => ee.pos + Vec3::new(0.0, 0.0, 0.08),
                };
                if self.stage_steps >= 8 {
                    if self.goal == DrawerGoal::Close {
                        return Step::Done;
                    }
                    self.next(Stage::Upright);
                    return self.step(sim);
                }
                Step::Act(Servo::TRAVEL.act(sim, &self.waypoint(sim, away), OPEN))
            }
            Stage::Upright => {
                // Turn back to pointing down by tipping about the handle's axis, which leaves
                // the finger axis along the drawer's travel (the wrist's natural way round).
                let into = -dir;
                let finger = ee.rot * Vec3::x();
                let axis = if finger.dot(&Vec3::z()) >= 0.0 { into } else { -into };
                let wp = Waypoint::down(ee.pos + Vec3::new(0.0, 0.0, 0.03), geometry::yaw_of_axis(&axis));
                let (_, r) = motion::error(sim, &wp);
                if r < 0.2 || self.stage_steps >= 25 {
                    return Step::Done;
                }
                Step::Act(Servo::TRAVEL.act(sim, &wp, OPEN))
            }
        }
    }
}
