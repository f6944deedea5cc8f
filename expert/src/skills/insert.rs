//! Putting an object into a covered cavity through its side opening (a mug into a microwave).
//!
//! A top-down placement cannot reach such a region: the hand (9 cm tall) stays above the
//! object, and the cavity's ceiling leaves no room for it. Here the gripper turns to point into
//! the opening (pitched down a little, so the wrist clears what stands behind the object),
//! takes the object from behind by a part narrow enough to pinch (a mug's handle when it faces
//! away from the opening), lifts it just over the cavity's floor and slides it in, the hand
//! staying outside the opening; passing an open door, it goes round the door's free edge. A
//! closing door pushes in what still sticks out.
//!
//! Recipe: turn to point into the opening while crossing over the grasp, descend, grasp, lift
//! just over the cavity's floor, carry in (round an open door), set down, release, back out,
//! rise, turn upright.

use vifo_robots::spatial::{Mat3, Pose, Vec3};
use vifo_scenes::sim::{RegionPlace, Sim};

use super::Skill;
use crate::arm;
use crate::geometry::{self, FINGER_HALF_WIDTH, HAND_ABOVE_SITE, HAND_HALF_LENGTH, HAND_HALF_WIDTH, MAX_GRASP_WIDTH, Obb, cruise_height, horizontal, surface_height};
use crate::motion::{self, Servo, Waypoint};
use crate::stages::{self, CLOSE, Leg, OPEN, Pace, Progress, Stages, Step, Tol, gripper_toward};

/// Room the hand needs over an object put in from above: fingers over the rim and the hand
/// itself. A cavity with less headroom over the object is entered from the side.
const TOP_DOWN_HEADROOM: f64 = 0.15;
/// How far the grip site sits in front of the object's rear face (the fingertips reach
/// [`TIP_PAST_SITE`] further).
const GRIP_DEPTH: f64 = 0.004;
const TIP_PAST_SITE: f64 = 0.009;
/// Depth of the rear face whose middle height the fingers take.
const REAR_FACE: f64 = 0.01;
/// The finger pads reach this far behind the grip site along the approach.
const PAD_BEHIND_SITE: f64 = 0.02;
/// Clearance between each finger and the pinched part while approaching.
const APPROACH_CLEARANCE: f64 = 0.011;
/// Half the hand's depth along the approach (the Panda hand's collision box; its other
/// half-extents are [`HAND_HALF_LENGTH`] along the closing axis and [`HAND_HALF_WIDTH`]).
const HAND_HALF_DEPTH: f64 = 0.046;
/// How far the approach may point below horizontal (rad), least first: the hand and wrist,
/// behind and below the grip site, rise with it over what stands behind the grasp, but the
/// hand's upper front edge comes forward, toward the opening.
const PITCHES: [f64; 3] = [0.4, 0.6, 0.8];
/// The wrist behind the hand: length along the approach and half-width around it.
const WRIST_LENGTH: f64 = 0.1;
const WRIST_HALF_WIDTH: f64 = 0.045;
/// Half-height of the band around the grip site the hand occupies across the approach, with
/// a margin.
const HAND_BAND: f64 = 0.05;
/// How far behind its front the hand and wrist sweep obstacles (along the approach).
const HAND_SWEEP: f64 = 0.15;
/// Margins: object to the cavity's back and side walls, the hand's front to the opening, the
/// hand to obstacles beside it.
const BACK_GAP: f64 = 0.01;
const SIDE_GAP: f64 = 0.006;
const HAND_GAP: f64 = 0.003;
const HAND_SIDE_GAP: f64 = 0.008;
/// The object's bottom over the cavity floor while carried, and when let go.
const CARRY_CLEARANCE: f64 = 0.012;
const RELEASE_CLEARANCE: f64 = 0.004;
/// The gripper turns on its way over the grasp, this high over the path, then comes straight
/// down onto it: the open fingers pass either side of a handle's loop, and the hand stays no
/// further back than at the grasp (where other objects may stand).
const CRUISE_CLEARANCE: f64 = 0.08;
/// How far the hand's front passes a door's free edge before turning in behind it.
const PASS: f64 = 0.02;
/// How far the gripper backs out after letting go.
const BACK_OUT: f64 = 0.12;
/// Then up this far over everything within this radius, before turning to point down.
const CLEAR_HEIGHT: f64 = 0.06;
const CLEAR_RADIUS: f64 = 0.12;
const STAGE_LIMIT: usize = 100;

/// The inside of a covered fixture region, seen from its opening.
#[derive(Clone, Copy, Debug)]
struct Cavity {
    /// Horizontal unit direction into the cavity through the opening, and the horizontal axis
    /// across it.
    inward: Vec3,
    across: Vec3,
    floor: f64,
    ceiling: f64,
    /// Along `inward`: the back wall's face and the ceiling's front edge (the opening).
    back: f64,
    mouth: f64,
    /// Along `across`: the side walls' faces.
    sides: (f64, f64),
}

/// Distance along a ray to where it enters a box (0 when it starts inside).
fn ray_hit(b: &Obb, from: &Vec3, dir: &Vec3) -> Option<f64> {
    let inv = b.pose.inverse();
    let o = inv.transform_point(from);
    let d = inv.rot * dir;
    let (mut t0, mut t1) = (0.0_f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-12 {
            if o[k].abs() > b.half[k] {
                return None;
            }
            continue;
        }
        let (a, c) = ((-b.half[k] - o[k]) / d[k], (b.half[k] - o[k]) / d[k]);
        t0 = t0.max(a.min(c));
        t1 = t1.min(a.max(c));
    }
    (t0 <= t1).then_some(t0)
}

/// The nearest box a ray meets and the distance to it.
fn first_hit<'a>(boxes: &'a [Obb], from: &Vec3, dir: &Vec3) -> Option<(f64, &'a Obb)> {
    boxes.iter().filter_map(|b| ray_hit(b, from, dir).map(|t| (t, b))).min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The cavity holding region `region` of its fixture, if the region is on the fixture's fixed
/// body and enclosed by its shapes on top, below, at the back and both sides and open on one
/// horizontal side (the one facing the robot where several are open).
fn cavity(sim: &Sim, region: &str) -> Option<Cavity> {
    // Only a region of the fixed shell: a drawer's region moves with the drawer.
    let RegionPlace::Site { entity, site } = sim.model().region(region)?.place else { return None };
    if sim.model().entities[entity].model.sites[site].body != 0 {
        return None;
    }
    let r = sim.region_box(region)?;
    let walls = geometry::body_boxes(sim, r.owner?, 0);
    let centre = r.pose.pos;
    let up = Vec3::z();
    let (below, _) = first_hit(&walls, &centre, &-up)?;
    let (above, roof) = first_hit(&walls, &centre, &up)?;
    if below == 0.0 || above == 0.0 {
        return None;
    }
    let base = arm::of(sim).base();
    let to_robot = Vec3::new(base.x - centre.x, base.y - centre.y, 0.0);
    let inward = (0..4)
        .filter_map(|k| {
            let axis: Vec3 = r.pose.rot.column(k % 2).into();
            let out = Vec3::new(axis.x, axis.y, 0.0).normalize() * if k < 2 { 1.0 } else { -1.0 };
            first_hit(&walls, &centre, &out).is_none().then_some(-out)
        })
        .min_by(|a, b| a.dot(&to_robot).total_cmp(&b.dot(&to_robot)))?;
    let across = Vec3::new(-inward.y, inward.x, 0.0);
    let (back, _) = first_hit(&walls, &centre, &inward)?;
    let (left, _) = first_hit(&walls, &centre, &-across)?;
    let (right, _) = first_hit(&walls, &centre, &across)?;
    let mouth = geometry::extent(&geometry::obb_corners(roof), &inward).0;
    Some(Cavity {
        inward,
        across,
        floor: centre.z - below,
        ceiling: centre.z + above,
        back: centre.dot(&inward) + back,
        mouth,
        sides: (centre.dot(&across) - left, centre.dot(&across) + right),
    })
}

/// Everything the insertion needs, worked out from the state when it starts.
#[derive(Clone, Copy, Debug)]
struct Layout {
    cavity: Cavity,
    /// Gripper orientation: pointing along `inward`, fingers closing across it.
    rot: Mat3,
    grasp: Vec3,
    half_gap: f64,
    /// Where the object's origin goes (horizontal).
    target: [f64; 2],
    /// The fixture owning the cavity.
    owner: usize,
}

/// Where and how to take the object from behind: the grip site at its rear part, if that part
/// is narrow enough across the opening to pinch, and the part's width.
fn rear_grasp(parts: &[Obb], inward: &Vec3, across: &Vec3) -> Option<(Vec3, f64)> {
    let points: Vec<Vec3> = parts.iter().flat_map(geometry::obb_corners).collect();
    let (lo, hi) = geometry::bounds(&points);
    let rear = geometry::extent(&points, inward).0;
    // Halfway up the rear face (a handle's outer bar).
    let face = geometry::bounds(&points.iter().copied().filter(|p| p.dot(inward) < rear + REAR_FACE).collect::<Vec<_>>());
    let z = (0.5 * (face.0.z + face.1.z)).clamp(lo.z + FINGER_HALF_WIDTH, hi.z - FINGER_HALF_WIDTH);
    let u = rear + GRIP_DEPTH;
    // The parts between the pads: within the pads' reach along the approach and their width
    // up and down.
    let pinched: Vec<Vec3> = parts
        .iter()
        .map(geometry::obb_corners)
        .filter(|c| {
            let (u0, u1) = geometry::extent(c, inward);
            let (z0, z1) = geometry::extent(c, &Vec3::z());
            u0 < u + TIP_PAST_SITE && u1 > u - PAD_BEHIND_SITE && z0 < z + FINGER_HALF_WIDTH && z1 > z - FINGER_HALF_WIDTH
        })
        .flatten()
        .collect();
    let (v0, v1) = geometry::extent(&pinched, across);
    let width = v1 - v0;
    // `inward` and `across` are horizontal: the site's height is set on its own.
    (width <= MAX_GRASP_WIDTH).then(|| (inward * u + across * (0.5 * (v0 + v1)) + Vec3::new(0.0, 0.0, z), width))
}

/// The overlap of two intervals, if any.
fn overlap(a: (f64, f64), b: (f64, f64)) -> Option<(f64, f64)> {
    let (lo, hi) = (a.0.max(b.0), a.1.min(b.1));
    (lo <= hi).then_some((lo, hi))
}

/// How far the hand's foremost edge (the upper one, the approach pitching down) lies ahead of
/// the grip site along `inward`.
fn front_offset(rot: &Mat3, inward: &Vec3) -> f64 {
    let (approach, up): (Vec3, Vec3) = (rot.column(2).into(), rot.column(1).into());
    [1.0, -1.0].map(|k| (up * (k * HAND_HALF_WIDTH) - approach * HAND_ABOVE_SITE).dot(inward)).into_iter().fold(f64::NEG_INFINITY, f64::max)
}

/// The gripper orientation for the grasp: the least pitch (of [`PITCHES`]) whose hand and
/// wrist stay clear of the other objects, or the one touching fewest; of the two equivalent
/// closing axes, the one the wrist turns to with the least twist.
fn turn(sim: &Sim, object: usize, grasp: &Vec3, inward: &Vec3, across: &Vec3) -> Mat3 {
    let obstacles = geometry::Obstacles::around(sim, object);
    let candidates = PITCHES.map(|p| {
        let approach = inward * libm::cos(p) - Vec3::z() * libm::sin(p);
        let rot_for = |c: Vec3| Mat3::from_columns(&[c, approach.cross(&c), approach]);
        let rot = [rot_for(*across), rot_for(-across)]
            .into_iter()
            .min_by(|a, b| arm::of(sim).wrist_after(a).abs().total_cmp(&arm::of(sim).wrist_after(b).abs()))
            .expect("two candidates");
        let along = |d: f64| Pose::new(grasp - approach * d, rot);
        let hand = Obb { pose: along(HAND_ABOVE_SITE + HAND_HALF_DEPTH), half: Vec3::new(HAND_HALF_LENGTH, HAND_HALF_WIDTH, HAND_HALF_DEPTH) };
        let wrist = Obb {
            pose: along(HAND_ABOVE_SITE + 2.0 * HAND_HALF_DEPTH + 0.5 * WRIST_LENGTH),
            half: Vec3::new(WRIST_HALF_WIDTH, WRIST_HALF_WIDTH, 0.5 * WRIST_LENGTH),
        };
        (obstacles.hits(&[hand, wrist], 0.005), rot)
    });
    candidates.into_iter().min_by_key(|c| c.0).expect("three pitches").1
}

fn layout(sim: &Sim, object: usize, region: &str) -> Option<Layout> {
    let cavity = cavity(sim, region)?;
    let parts = geometry::body_boxes(sim, object, 0);
    let points: Vec<Vec3> = parts.iter().flat_map(geometry::obb_corners).collect();
    let (lo, hi) = geometry::bounds(&points);
    if cavity.ceiling - cavity.floor > hi.z - lo.z + TOP_DOWN_HEADROOM || cavity.ceiling - cavity.floor < hi.z - lo.z + CARRY_CLEARANCE {
        return None;
    }
    let (inward, across) = (cavity.inward, cavity.across);
    let (grasp, width) = rear_grasp(&parts, &inward, &across)?;
    let rot = turn(sim, object, &grasp, &inward, &across);
    // Along the opening: as deep as the back wall allows, the hand staying outside the
    // opening (a closing door pushes in what still sticks out).
    let (_, far) = geometry::extent(&points, &inward);
    let hand_front = grasp.dot(&inward) + front_offset(&rot, &inward);
    let s = (cavity.back - BACK_GAP - far).min(cavity.mouth - HAND_GAP - hand_front);
    // Across it: within the side walls, the hand clear of the fixture's fixed shapes beside its
    // path (a door is left out: the hand only swings it further open), near the middle.
    let (v0, v1) = geometry::extent(&points, &across);
    let fits = (cavity.sides.0 + SIDE_GAP - v0, cavity.sides.1 - SIDE_GAP - v1);
    let middle = 0.5 * (fits.0 + fits.1);
    let centre = 0.5 * (cavity.sides.0 + cavity.sides.1);
    let owner = sim.region_box(region)?.owner?;
    let front = hand_front + s;
    let (mut left, mut right) = (f64::NEG_INFINITY, f64::INFINITY);
    for b in geometry::body_boxes(sim, owner, 0) {
        for p in grid(&b) {
            let u = p.dot(&inward);
            if u > front + HAND_GAP || u < front - HAND_SWEEP || (p.z - grasp.z - (cavity.floor + CARRY_CLEARANCE - lo.z)).abs() > HAND_BAND {
                continue;
            }
            let v = p.dot(&across);
            if v < centre { left = left.max(v) } else { right = right.min(v) }
        }
    }
    let g = grasp.dot(&across);
    let hand = (left + HAND_HALF_LENGTH + HAND_SIDE_GAP - g, right - HAND_HALF_LENGTH - HAND_SIDE_GAP - g);
    let t = overlap(fits, hand).map_or(middle, |(a, b)| middle.clamp(a, b));
    let origin = sim.entity_pose(object).pos + inward * s + across * t;
    Some(Layout {
        cavity,
        rot,
        grasp,
        half_gap: 0.5 * width + APPROACH_CLEARANCE,
        target: [origin.x, origin.y],
        owner,
    })
}

/// A grip-site waypoint that takes the hand past the free edge of a moving part of the fixture
/// (an open door) standing in the hand's way in: beside the edge, the hand's front just past
/// it. Met end-on, a door edge would be pushed shut against the hand; met on its face, it only
/// swings further open.
fn around_door(sim: &Sim, l: &Layout, site: &Vec3, target: &Vec3) -> Option<Vec3> {
    let (inward, across) = (l.cavity.inward, l.cavity.across);
    let ahead = front_offset(&l.rot, &inward);
    let (from, to) = (site.dot(&inward) + ahead, target.dot(&inward) + ahead);
    let reach = HAND_HALF_LENGTH + HAND_SIDE_GAP;
    let v = target.dot(&across);
    let bodies = sim.model().entities[l.owner].model.bodies.len();
    let blockers: Vec<Vec3> = (1..bodies)
        .flat_map(|b| geometry::body_boxes(sim, l.owner, b))
        .flat_map(|b| grid(&b).collect::<Vec<_>>())
        .filter(|p| {
            let u = p.dot(&inward);
            u > from && u < to && (p.z - target.z).abs() < HAND_BAND && (p.dot(&across) - v).abs() < reach
        })
        .collect();
    if blockers.is_empty() {
        return None;
    }
    // Pass on the side away from the blockers, beside the one reaching furthest across.
    let side = if blockers.iter().map(|p| p.dot(&across) - v).sum::<f64>() < 0.0 { 1.0 } else { -1.0 };
    let edge = blockers.iter().max_by(|a, b| (side * a.dot(&across)).total_cmp(&(side * b.dot(&across))))?;
    let lateral = edge.dot(&across) + side * reach;
    let along = edge.dot(&inward) + PASS - ahead;
    let level = Vec3::new(0.0, 0.0, target.z);
    Some(inward * along + across * lateral + level)
}

/// Points on a box's surface and inside it (a 5 × 5 × 5 grid), to find what a sweep passes.
fn grid(b: &Obb) -> impl Iterator<Item = Vec3> + '_ {
    (0..125).map(move |k| {
        let f = |i: usize, h: f64| (i as f64 / 2.0 - 1.0) * h;
        b.pose.transform_point(&Vec3::new(f(k % 5, b.half.x), f(k / 5 % 5, b.half.y), f(k / 25, b.half.z)))
    })
}

/// Whether `region` is a covered cavity that `object` has to be slid into from the side, and
/// can be (it has a part to hold from behind).
pub fn needed(sim: &Sim, object: usize, region: &str) -> bool {
    layout(sim, object, region).is_some()
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stage {
    Turn,
    Down,
    Close,
    Lift,
    Carry,
    Lower,
    Release,
    Out,
    Up,
    Upright,
    Done,
}

/// Slide an object into a covered cavity through its side opening.
pub struct Insert {
    object: usize,
    region: String,
    layout: Option<Layout>,
    stage: Stages<Stage>,
    cruise_z: f64,
    /// Grip site minus object origin, and origin minus the object's bottom, while carried.
    carry_offset: Vec3,
    carry_height: f64,
    lift_start_z: f64,
    /// Recent grip-site heights while lowering, to notice a stall.
    lowering: Progress,
    /// A grip-site waypoint on the way in, around the free edge of a door in the way.
    via: Option<Vec3>,
}

impl Insert {
    pub fn new(object: usize, region: String) -> Self {
        Insert {
            object,
            region,
            layout: None,
            stage: Stages::new(Stage::Turn, STAGE_LIMIT),
            cruise_z: 0.0,
            carry_offset: Vec3::zeros(),
            carry_height: 0.0,
            lift_start_z: 0.0,
            lowering: Progress::default(),
            via: None,
        }
    }

    /// Grip-site position that puts the carried object's origin at the target, its bottom
    /// `clearance` over the cavity floor.
    fn placed(&self, l: &Layout, clearance: f64) -> Vec3 {
        Vec3::new(l.target[0], l.target[1], l.cavity.floor + clearance + self.carry_height) + self.carry_offset
    }
}

impl Skill for Insert {
    fn describe(&self) -> String {
        let l = self.layout.map(|l| format!("grasp ({:.3} {:.3} {:.3}) target ({:.3} {:.3})", l.grasp.x, l.grasp.y, l.grasp.z, l.target[0], l.target[1])).unwrap_or_default();
        format!("insert {} {l}", self.stage)
    }

    fn step(&mut self, sim: &Sim) -> Step {
        if !self.stage.tick() {
            return Step::Failed("an insertion stage took too long");
        }
        if self.layout.is_none() {
            self.layout = layout(sim, self.object, &self.region);
        }
        let Some(l) = self.layout else { return Step::Failed("no way to slide the object in") };
        let ee = arm::of(sim).grip_site();
        let object = sim.entity_pose(self.object).pos;
        let steps = self.stage.steps;
        let (leg, then) = match self.stage.now {
            // Approach at cruise height, turning on the way over the grasp.
            Stage::Turn => {
                if steps == 1 {
                    self.cruise_z = cruise_height(sim, &l.grasp, CRUISE_CLEARANCE, (l.grasp.z + CRUISE_CLEARANCE).max(ee.pos.z), None);
                }
                let wp = Waypoint { pos: Vec3::new(l.grasp.x, l.grasp.y, self.cruise_z), rot: l.rot };
                let (_, r) = motion::error(sim, &wp);
                let m = stages::Move { to: wp, servo: Servo::TRAVEL, grip: gripper_toward(sim, l.half_gap) };
                (Leg::until(m, horizontal(&ee.pos, &l.grasp) < 0.005 && r < 0.03), Stage::Down)
            }
            Stage::Down => (stages::descend(sim, &l.grasp, l.rot, 0.004, gripper_toward(sim, l.half_gap)), Stage::Close),
            Stage::Close => {
                let leg = stages::grasp(steps, 12, Waypoint { pos: l.grasp, rot: l.rot });
                if leg.is_last() {
                    self.lift_start_z = object.z;
                }
                (leg, Stage::Lift)
            }
            Stage::Lift => {
                if let Some(why) = stages::lift_failure(sim, steps, 10, self.lift_start_z, object.z, 0.005) {
                    return Step::Failed(why);
                }
                let bottom = geometry::bounds(&geometry::corners(sim, self.object, 0)).0.z;
                let rise = l.cavity.floor + CARRY_CLEARANCE - (self.lift_start_z - (object.z - bottom));
                let wp = Waypoint { pos: l.grasp + Vec3::new(0.0, 0.0, rise.max(0.0) + 0.005), rot: l.rot };
                let (d, _) = motion::error(sim, &wp);
                let lifted = d < 0.006 && bottom > l.cavity.floor + 0.5 * CARRY_CLEARANCE;
                if lifted {
                    self.carry_offset = ee.pos - object;
                    self.carry_height = object.z - bottom;
                }
                (Leg::until(stages::Move { to: wp, servo: Servo::closing_in(d), grip: CLOSE }, lifted), Stage::Carry)
            }
            Stage::Carry => {
                if ((ee.pos - object) - self.carry_offset).norm() > 0.03 {
                    return Step::Failed("the object slipped out");
                }
                let target = self.placed(&l, CARRY_CLEARANCE);
                if steps == 1 {
                    self.via = around_door(sim, &l, &ee.pos, &target);
                }
                let wp = Waypoint { pos: self.via.unwrap_or(target), rot: l.rot };
                let (d, _) = motion::error(sim, &wp);
                // Past the door's edge, on to the target itself.
                let there = match self.via {
                    Some(_) => {
                        if d < 0.01 {
                            self.via = None;
                        }
                        false
                    }
                    None => d < 0.005,
                };
                (Leg::until(stages::Move { to: wp, servo: Servo::closing_in(d), grip: CLOSE }, there), Stage::Lower)
            }
            Stage::Lower => {
                let wp = Waypoint { pos: self.placed(&l, RELEASE_CLEARANCE), rot: l.rot };
                (stages::set_down(sim, &mut self.lowering, wp, Pace::Fine, 0.004, 0.001), Stage::Release)
            }
            Stage::Release => (stages::release(steps, 10, Waypoint { pos: ee.pos, rot: l.rot }), Stage::Out),
            Stage::Out => {
                let wp = Waypoint { pos: self.placed(&l, RELEASE_CLEARANCE) - l.cavity.inward * BACK_OUT, rot: l.rot };
                let leg = stages::reach(sim, wp, Pace::Travel, Tol::pos(0.02), OPEN);
                if leg.is_last() {
                    self.cruise_z = surface_height(sim, [ee.pos.x, ee.pos.y], CLEAR_RADIUS, None) + CLEAR_HEIGHT;
                }
                (leg, Stage::Up)
            }
            // Up clear of the fixture before turning back to pointing down: turning in front of
            // the opening swings the hand into it.
            Stage::Up => {
                let wp = Waypoint { pos: Vec3::new(ee.pos.x, ee.pos.y, self.cruise_z), rot: l.rot };
                (Leg::until(stages::Move { to: wp, servo: Servo::TRAVEL, grip: OPEN }, ee.pos.z > self.cruise_z - 0.02), Stage::Upright)
            }
            Stage::Upright => {
                let finger: Vec3 = l.rot.column(0).into();
                let wp = Waypoint::down(Vec3::new(ee.pos.x, ee.pos.y, self.cruise_z), geometry::yaw_of_axis(&finger));
                let (_, r) = motion::error(sim, &wp);
                (Leg::unless(r < 0.1, stages::Move { to: wp, servo: Servo::TRAVEL, grip: OPEN }), Stage::Done)
            }
            Stage::Done => return Step::Done,
        };
        Step::after(self.stage.play(sim, leg, then), || self.step(sim))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Expert;
    use vifo_scenes::init_states;
    use vifo_scenes::sim::SceneModel;
    use vifo_scenes::task::Predicate;

    /// Shipped initial state `state` of a task, after LIBERO's wait steps.
    fn start(suite: &str, index: usize, state: usize) -> Sim {
        let task = vifo_scenes::task(suite, index).expect("built-in task");
        let mut sim = Sim::new(SceneModel::build(task).expect("scene builds"));
        init_states::apply(&mut sim, &init_states::fixed(task).expect("shipped states")[state]).expect("state applies");
        init_states::wait(&mut sim);
        sim
    }

    #[test]
    fn the_microwave_cavity_opens_toward_the_robot_under_its_ceiling() {
        let sim = start("libero_10", 9, 0);
        let (m, _) = sim.model().entity("microwave_1").expect("microwave");
        let at = sim.entity_pose(m).pos;
        let c = cavity(&sim, "microwave_1_heating_region").expect("a covered cavity");
        // The microwave is not turned: its opening faces -y, its shell boxes bound the inside.
        assert!((c.inward - Vec3::y()).norm() < 1e-9, "inward {:?}", c.inward);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6;
        assert!(close(c.mouth, at.y - 0.088), "mouth {}", c.mouth);
        assert!(close(c.back, at.y + 0.0805), "back {}", c.back);
        assert!(close(c.floor, at.z + 0.024) && close(c.ceiling, at.z + 0.168), "floor {} ceiling {}", c.floor, c.ceiling);
        // `across` is -x here: the side walls' inner faces at x = -0.1435 and 0.0635.
        assert!(close(c.sides.0, -(at.x + 0.0635)) && close(c.sides.1, -(at.x - 0.1435)), "sides {:?}", c.sides);
    }

    #[test]
    fn only_the_microwave_goal_is_slid_in_from_the_side() {
        for suite in vifo_scenes::suites() {
            for (index, task) in suite.tasks.iter().enumerate() {
                let sim = start(&suite.name, index, 0);
                for atom in task.goal.iter().filter(|a| a.predicate == Predicate::In) {
                    let Some((object, _)) = sim.model().entity(&atom.args[0]) else { continue };
                    let expected = suite.name == "libero_10" && index == 9;
                    assert_eq!(needed(&sim, object, &atom.args[1]), expected, "{} {index}: {atom}", suite.name);
                }
            }
        }
    }

    #[test]
    fn the_expert_puts_the_mug_in_the_microwave_and_closes_it() {
        let mut sim = start("libero_10", 9, 0);
        let mut expert = Expert::new(&sim).expect("a plan");
        for _ in 0..520 {
            if sim.success().expect("goal atoms resolve") {
                return;
            }
            let action = expert.act(&sim);
            sim.step(&action);
        }
        panic!("not done in 520 steps: {}", expert.failure().unwrap_or("budget"));
    }
}
