//! Where a cue object stands: deterministic from a seed, visible from agentview, clear of the
//! task's things, of the goal and of the arm's work on it.
//!
//! The rule, in order, for up to [`TRIES`] draws from a `Pcg64` seeded with the given seed:
//! 1. x, y uniform over the table top 3 cm in from its edges (floor scenes: ± 0.40 m in x,
//!    ± 0.50 m in y around the workspace offset), within ± 0.45 m in y of the workspace offset
//!    (what the camera sees) and at least 0.40 m in front of the robot's base (the arm's
//!    shoulder and its start pose stay clear); the face turned to the agentview camera.
//! 2. The footprint (the rectangle [`super::CueObjectKind::footprint`], turned with the
//!    object) keeps `objects` from every object's and fixture's collision boxes (their
//!    horizontal bounds), and `goal` from everything the goal names: a region's box, an
//!    object's or fixture's horizontal bounds as a whole (a door's or drawer's travel lies
//!    within them). The hand comes down to the table only there (to grasp, place, push or
//!    turn), and the Panda's hand spans 21 cm along its fingers with the wrist reaching out
//!    further above it, so the first stage keeps the arm's reach ([`REACH`]) from them.
//! 3. The paths: the footprint keeps `path` from the straight way between the things of every
//!    two-place goal atom (what is carried, and where to), over which the hand carries it.
//! 4. Visible at the start: the face's four corners project into the agentview image, and the
//!    rays from the camera to the face's centre and to points 10 % in from its corners pass no
//!    object's or fixture's collision box.
//!
//! The first draw meeting all four is taken. After [`TRIES`] draws without one, the rule runs
//! again with the next, smaller clearances of [`CLEARANCES`] (scenes whose visible table has
//! no room for the arm's reach, as LIBERO's crowded living room); none at the last is an error
//! naming the task.

use rand::{RngExt, SeedableRng};
use vifo_robots::spatial::{Pose, Vec3, axis_angle};

use super::CueObjectKind;
use crate::catalog::ColliderShape;
use crate::sim::Sim;
use crate::view::Cameras;

/// Clearances of one stage of the rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// Between the cue's footprint and any object or fixture (m).
    pub objects: f64,
    /// Between the cue's footprint and what the goal names (m).
    pub goal: f64,
    /// Between the cue's footprint and the straight ways of the goal's atoms (m; 0: not kept).
    pub path: f64,
}

/// How far the arm reaches out around where its hand comes down (m): half the hand's 21 cm
/// span along the fingers, and the wrist's links that stand out further above the hand when it
/// turns to a handle.
pub const REACH: f64 = 0.15;
/// The rule's stages: the arm's reach around the goal, then less and less of it down to a
/// 6 cm margin, as the visible table allows; then smaller margins, for scenes whose visible
/// table has no room under the others (LIBERO's crowded living room). Over the 297 F1/F6/F8
/// instances of the paper set and their 50 initial states, 76 % of the places keep the whole
/// reach and none is left without one.
pub const CLEARANCES: [Clearance; 7] = [
    Clearance { objects: 0.02, goal: REACH, path: PATH },
    Clearance { objects: 0.02, goal: 0.13, path: PATH },
    Clearance { objects: 0.02, goal: 0.11, path: PATH },
    Clearance { objects: 0.02, goal: 0.09, path: PATH },
    Clearance { objects: 0.02, goal: 0.06, path: PATH },
    Clearance { objects: 0.01, goal: 0.03, path: 0.0 },
    Clearance { objects: 0.01, goal: 0.01, path: 0.0 },
];
/// Half width of the way a carried thing takes (m): the hand holding a grocery box.
const PATH: f64 = 0.06;
/// Draws per stage before giving up.
const TRIES: usize = 2000;
/// Half extents of the sampled area around the workspace offset in floor scenes (m).
const FLOOR_AREA: [f64; 2] = [0.40, 0.50];
/// Half width (y) of the sampled strip around the workspace offset: the camera sees no wider.
const WIDE: f64 = 0.45;
/// Spacing of the points that stand for a path (m).
const PATH_STEP: f64 = 0.02;
/// How far in from the table's edges the cue's origin stays (m).
const EDGE: f64 = 0.03;
/// Nearest the cue may stand to the robot's base along x (m).
const FROM_BASE: f64 = 0.40;

/// No draw met the placement rule.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("task {task}: no place for the {kind:?} cue object in {tries} draws from seed {seed} (visible from agentview, clear of objects and the goal)")]
pub struct CuePlaceError {
    pub task: String,
    pub kind: CueObjectKind,
    pub seed: u64,
    pub tries: usize,
}

/// A world box: pose and half extents.
struct WorldBox {
    pose: Pose,
    half: Vec3,
}

impl WorldBox {
    /// Horizontal bounds (x0, y0, x1, y1) of the box.
    fn footprint(&self) -> [f64; 4] {
        let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for k in 0..8 {
            let s = |bit: usize, h: f64| if k & bit == 0 { -h } else { h };
            let p = self.pose.transform_point(&Vec3::new(s(1, self.half.x), s(2, self.half.y), s(4, self.half.z)));
            b = [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)];
        }
        b
    }

    /// Whether the segment from `a` to `b` passes through the box (slab test in its frame).
    fn hit_by(&self, a: &Vec3, b: &Vec3) -> bool {
        let inv = self.pose.inverse();
        let (p, q) = (inv.transform_point(a), inv.transform_point(b));
        let d = q - p;
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for i in 0..3 {
            if d[i].abs() < 1e-12 {
                if p[i].abs() > self.half[i] {
                    return false;
                }
                continue;
            }
            let (mut ta, mut tb) = ((-self.half[i] - p[i]) / d[i], (self.half[i] - p[i]) / d[i]);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
            if t0 > t1 {
                return false;
            }
        }
        true
    }
}

/// Every collision box of an entity in the world (capsules as their bounding boxes).
fn boxes(sim: &Sim, entity: usize) -> Vec<WorldBox> {
    let e = &sim.model().entities[entity];
    let mut out = Vec::new();
    for (b, body) in e.model.bodies.iter().enumerate() {
        let at = sim.body_pose(entity, b);
        for c in &body.colliders {
            let half = match c.shape {
                ColliderShape::Box { half_size } => half_size,
                ColliderShape::Capsule { radius, half_length } => [radius, radius, half_length + radius],
            };
            out.push(WorldBox { pose: at.mul(&Pose::from_wxyz(c.pos, c.quat_wxyz)), half: Vec3::from(half) });
        }
    }
    out
}

/// Whether a turned rectangle (centre, unit axis `u` of its first half extent, half extents)
/// comes within `margin` of an axis-aligned rectangle `r` (x0, y0, x1, y1): separating axes.
fn near(centre: [f64; 2], u: [f64; 2], half: [f64; 2], r: [f64; 4], margin: f64) -> bool {
    let v = [-u[1], u[0]];
    let (rc, rh) = ([(r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0], [(r[2] - r[0]) / 2.0 + margin, (r[3] - r[1]) / 2.0 + margin]);
    let d = [rc[0] - centre[0], rc[1] - centre[1]];
    let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
    // World axes: the turned rectangle's extent along x and y.
    let ext = |axis: [f64; 2]| half[0] * dot(u, axis).abs() + half[1] * dot(v, axis).abs();
    let apart_world = d[0].abs() > rh[0] + ext([1.0, 0.0]) || d[1].abs() > rh[1] + ext([0.0, 1.0]);
    // Its own axes: the aligned rectangle's extent along them.
    let other = |axis: [f64; 2]| rh[0] * axis[0].abs() + rh[1] * axis[1].abs();
    let apart_own = dot(d, u).abs() > half[0] + other(u) || dot(d, v).abs() > half[1] + other(v);
    !(apart_world || apart_own)
}

/// Where a cue object stands, and which stage of [`CLEARANCES`] found the place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub pose: Pose,
    pub stage: usize,
}

/// The horizontal bounds of a named goal thing: a region's box, or an entity's boxes as a
/// whole; `None` for the cue itself or an unknown name.
fn goal_rect(sim: &Sim, name: &str, entity: usize) -> Option<[f64; 4]> {
    if let Some(r) = sim.region_box(name) {
        return Some(WorldBox { pose: r.pose, half: r.half_size }.footprint());
    }
    let (i, _) = sim.model().entity(name).filter(|(i, _)| *i != entity)?;
    boxes(sim, i).iter().map(WorldBox::footprint).reduce(|a, b| [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])])
}

/// Points every [`PATH_STEP`] along the straight ways between the things of every two-place
/// goal atom (centres of their bounds), ends included.
fn path_points(sim: &Sim, entity: usize) -> Vec<[f64; 2]> {
    let centre = |name: &str| goal_rect(sim, name, entity).map(|r| [(r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0]);
    let mut out = Vec::new();
    for atom in &sim.model().task.goal {
        let (Some(a), Some(b)) = (atom.args.first().and_then(|n| centre(n)), atom.args.get(1).and_then(|n| centre(n))) else { continue };
        let n = (libm::hypot(b[0] - a[0], b[1] - a[1]) / PATH_STEP).ceil().max(1.0) as usize;
        out.extend((0..=n).map(|k| {
            let t = k as f64 / n as f64;
            [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
        }));
    }
    out
}

/// The pose of the cue object `entity` (a `kind`) for the scene's current state, by the rule
/// of this module's documentation.
pub fn place(sim: &Sim, entity: usize, kind: CueObjectKind, seed: u64) -> Result<Pose, CuePlaceError> {
    placement(sim, entity, kind, seed).map(|p| p.pose)
}

/// [`place`], with the stage of the rule that found the place.
pub fn placement(sim: &Sim, entity: usize, kind: CueObjectKind, seed: u64) -> Result<Placement, CuePlaceError> {
    let model = sim.model();
    let class = model.class;
    let others: Vec<usize> = (0..model.entities.len()).filter(|&i| i != entity).collect();
    let obstacles: Vec<WorldBox> = others.iter().flat_map(|&i| boxes(sim, i)).collect();
    let goal_rects: Vec<[f64; 4]> =
        model.task.goal.iter().flat_map(|a| &a.args).filter_map(|name| goal_rect(sim, name, entity)).collect();
    let path = path_points(sim, entity);
    let object_rects: Vec<[f64; 4]> = obstacles.iter().map(WorldBox::footprint).collect();
    let on_support = |x: f64, y: f64| match &class.table {
        Some(t) => t.top.iter().any(|s| (x - s.center[0]).abs() <= s.half_size[0] - EDGE && (y - s.center[1]).abs() <= s.half_size[1] - EDGE),
        None => true,
    };
    let camera = Cameras::new(256, 256).agentview(class);
    let cam = Vec3::new(camera.position.x as f64, camera.position.y as f64, camera.position.z as f64);
    let (foot_x, foot_half) = kind.footprint();
    let (face, half) = kind.face();
    let z = class.support_z() + 0.001;
    let [ox, oy, _] = class.workspace_offset;
    let table = match &class.table {
        Some(t) => t.top.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |a, s| {
            [a[0].min(s.center[0] - s.half_size[0]), a[1].min(s.center[1] - s.half_size[1]), a[2].max(s.center[0] + s.half_size[0]), a[3].max(s.center[1] + s.half_size[1])]
        }),
        None => [ox - FLOOR_AREA[0], oy - FLOOR_AREA[1], ox + FLOOR_AREA[0], oy + FLOOR_AREA[1]],
    };
    let area = [table[0].max(class.robot_base.pos[0] + FROM_BASE), table[1].max(oy - WIDE), table[2], table[3].min(oy + WIDE)];
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    for (stage, clearance) in CLEARANCES.iter().enumerate().flat_map(|c| std::iter::repeat_n(c, TRIES)) {
        let x = rng.random_range(area[0] + EDGE..=area[2] - EDGE);
        let y = rng.random_range(area[1] + EDGE..=area[3] - EDGE);
        if !on_support(x, y) {
            continue;
        }
        let yaw = libm::atan2(cam.y - y, cam.x - x);
        let u = [libm::cos(yaw), libm::sin(yaw)];
        let centre = [x + u[0] * foot_x, y + u[1] * foot_x];
        if object_rects.iter().any(|r| near(centre, u, foot_half, *r, clearance.objects)) {
            continue;
        }
        if goal_rects.iter().any(|r| near(centre, u, foot_half, *r, clearance.goal)) {
            continue;
        }
        if clearance.path > 0.0 && path.iter().any(|p| near(centre, u, foot_half, [p[0], p[1], p[0], p[1]], clearance.path)) {
            continue;
        }
        let pose = Pose::new(Vec3::new(x, y, z), axis_angle(&Vec3::z(), yaw));
        let face_world = pose.mul(&face);
        let corner = |u: f64, v: f64| face_world.transform_point(&Vec3::new(u * half[0], v * half[1], 0.0));
        let corners = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
        let in_image = corners.iter().all(|p| {
            camera
                .project(vifo_render::glam::Vec3::new(p.x as f32, p.y as f32, p.z as f32))
                .is_some_and(|q| (0.0..=255.0).contains(&q.u) && (0.0..=255.0).contains(&q.v))
        });
        if !in_image {
            continue;
        }
        let seen = [corner(0.0, 0.0), corner(-0.9, -0.9), corner(0.9, -0.9), corner(0.9, 0.9), corner(-0.9, 0.9)];
        if seen.iter().any(|p| obstacles.iter().any(|b| b.hit_by(&cam, p))) {
            continue;
        }
        return Ok(Placement { pose, stage });
    }
    Err(CuePlaceError { task: model.task.label(), kind, seed, tries: TRIES * CLEARANCES.len() })
}
