//! What the expert knows of the scene's shapes, from its (privileged) collision boxes: the
//! hand's own dimensions, obstacle sets, grasp choice (solid, rim and part grasps) and the
//! heights the hand must pass over.

use vifo_robots::spatial::{Pose, Vec3};
use vifo_scenes::catalog::ColliderShape;
use vifo_scenes::sim::Sim;

use crate::arm;

/// Widest object the Panda's fingers can straddle (open gap 0.079 m) with some margin.
pub const MAX_GRASP_WIDTH: f64 = 0.068;
/// Half the gap between the fully open fingers' inner faces.
pub const OPEN_HALF_GAP: f64 = 0.0385;
/// Clearance between each finger and the object while the fingers come down around it.
const APPROACH_CLEARANCE: f64 = 0.011;
/// Half gap of a rim grasp: enough for a bowl or mug wall and a few millimetres of play.
const RIM_HALF_GAP: f64 = 0.013;
/// Finger size: thickness along the closing axis, half-width across it, length below the hand.
const FINGER_THICKNESS: f64 = 0.026;
pub(crate) const FINGER_HALF_WIDTH: f64 = 0.011;
/// The fingertips reach this far below the grip site, the hand starts this far above it.
const TIP_BELOW_SITE: f64 = 0.009;
pub(crate) const HAND_ABOVE_SITE: f64 = 0.031;
/// The hand's half-extents along the finger axis and across it, and the height of the column
/// it sweeps coming straight down to the grasp (the hand itself is 9 cm tall; the column also
/// keeps the wrist clear of overhangs such as an open drawer).
pub(crate) const HAND_HALF_LENGTH: f64 = 0.102;
pub(crate) const HAND_HALF_WIDTH: f64 = 0.032;
const HAND_HEIGHT: f64 = 0.25;
/// The grip site stays at least this far above the surface an object rests on, so the
/// fingertips do not dig into it.
const TIP_CLEARANCE: f64 = 0.010;

/// An oriented box of the scene (world frame).
#[derive(Clone, Copy, Debug)]
pub struct Obb {
    pub pose: Pose,
    pub half: Vec3,
}

impl Obb {
    /// Separating-axis test: do the two boxes, each grown by `margin`, overlap?
    pub fn overlaps(&self, other: &Obb, margin: f64) -> bool {
        let (a, b) = (&self.pose.rot, &other.pose.rot);
        let (ha, hb) = (self.half.add_scalar(margin), other.half.add_scalar(margin));
        let t = other.pose.pos - self.pose.pos;
        let axes_a: [Vec3; 3] = [a.column(0).into(), a.column(1).into(), a.column(2).into()];
        let axes_b: [Vec3; 3] = [b.column(0).into(), b.column(1).into(), b.column(2).into()];
        let separated = |axis: &Vec3| -> bool {
            let n = axis.norm();
            if n < 1e-9 {
                return false;
            }
            let axis = axis / n;
            let ra: f64 = (0..3).map(|k| ha[k] * axes_a[k].dot(&axis).abs()).sum();
            let rb: f64 = (0..3).map(|k| hb[k] * axes_b[k].dot(&axis).abs()).sum();
            t.dot(&axis).abs() > ra + rb
        };
        for i in 0..3 {
            if separated(&axes_a[i]) || separated(&axes_b[i]) {
                return false;
            }
        }
        for a in &axes_a {
            for b in &axes_b {
                if separated(&a.cross(b)) {
                    return false;
                }
            }
        }
        true
    }

    /// The box carried along by a rigid motion (a moved object's part).
    pub fn moved(&self, by: &Pose) -> Obb {
        Obb { pose: by.mul(&self.pose), half: self.half }
    }

    fn corners(&self) -> impl Iterator<Item = Vec3> + '_ {
        (0..8).map(move |k| {
            let s = |bit: usize, h: f64| if k & bit == 0 { -h } else { h };
            self.pose.transform_point(&Vec3::new(s(1, self.half.x), s(2, self.half.y), s(4, self.half.z)))
        })
    }
}

/// The collision boxes of one body of an entity, in the world.
pub fn body_boxes(sim: &Sim, entity: usize, body: usize) -> Vec<Obb> {
    let e = &sim.model().entities[entity];
    let pose = sim.body_pose(entity, body);
    e.model.bodies[body]
        .colliders
        .iter()
        .map(|c| {
            let half = match c.shape {
                ColliderShape::Box { half_size } => half_size,
                ColliderShape::Capsule { radius, half_length } => [radius, radius, half_length + radius],
            };
            Obb { pose: pose.mul(&Pose::from_wxyz(c.pos, c.quat_wxyz)), half: Vec3::from(half) }
        })
        .collect()
}

/// The eight corners of a box.
pub fn obb_corners(b: &Obb) -> Vec<Vec3> {
    b.corners().collect()
}

/// World-frame corners of every collision shape of one body of an entity.
pub fn corners(sim: &Sim, entity: usize, body: usize) -> Vec<Vec3> {
    body_boxes(sim, entity, body).iter().flat_map(|b| b.corners()).collect()
}

/// Axis-aligned world bounds of a point set: (min, max).
pub fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let mut lo = Vec3::repeat(f64::INFINITY);
    let mut hi = Vec3::repeat(f64::NEG_INFINITY);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

/// Everything the fingers must not run into: every other entity's shapes.
#[derive(Clone)]
pub struct Obstacles {
    boxes: Vec<Obb>,
}

impl Obstacles {
    pub fn around(sim: &Sim, exclude: usize) -> Obstacles {
        let mut boxes = Vec::new();
        for (i, e) in sim.model().entities.iter().enumerate() {
            if i != exclude {
                for b in 0..e.model.bodies.len() {
                    boxes.extend(body_boxes(sim, i, b));
                }
            }
        }
        Obstacles { boxes }
    }

    /// Only the boxes reaching within `radius` of `centre`.
    pub fn near(self, centre: &Vec3, radius: f64) -> Obstacles {
        let boxes = self.boxes.into_iter().filter(|b| (b.pose.pos - centre).norm() < radius + b.half.norm()).collect();
        Obstacles { boxes }
    }

    /// Only the boxes whose centres lie further than `radius` from `centre` (horizontally).
    pub fn beyond(self, centre: &Vec3, radius: f64) -> Obstacles {
        let far = |b: &Obb| ((b.pose.pos.x - centre.x).powi(2) + (b.pose.pos.y - centre.y).powi(2)).sqrt() > radius;
        Obstacles { boxes: self.boxes.into_iter().filter(far).collect() }
    }

    /// The first obstacle box the given volumes overlap.
    pub fn first_hit(&self, volumes: &[Obb], margin: f64) -> Option<Obb> {
        self.boxes.iter().find(|b| volumes.iter().any(|v| v.overlaps(b, margin))).copied()
    }

    /// How many obstacle boxes the given volumes (the gripper's, a carried object's) would overlap.
    pub fn hits(&self, volumes: &[Obb], margin: f64) -> usize {
        self.boxes.iter().filter(|b| volumes.iter().any(|v| v.overlaps(b, margin))).count()
    }
}

/// A top-down grasp: where the grip site goes and how the fingers are turned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grasp {
    /// Grip-site position at the grasp.
    pub pos: Vec3,
    /// Yaw of the finger axis (see [`crate::motion::Waypoint`]).
    pub yaw: f64,
    /// Object width between the fingers.
    pub width: f64,
    /// Half the finger gap to approach with (no wider than needed, to stay clear of walls).
    pub half_gap: f64,
}

pub fn yaw_of_axis(axis: &Vec3) -> f64 {
    libm::atan2(-axis.x, axis.y)
}

/// The volumes of the two open fingers and of the hand for a grasp at `site` with the fingers
/// closing along `axis`, the hand coming straight down.
fn gripper_volumes(site: &Vec3, axis: &Vec3, half_gap: f64) -> [Obb; 3] {
    let down = -Vec3::z();
    let rot = vifo_robots::spatial::Mat3::from_columns(&[*axis, down.cross(axis), down]);
    gripper_volumes_at(&Pose::new(*site, rot), half_gap)
}

/// The volumes of the two open fingers and of the hand for the grip site at `grip` (orientation
/// as a [`crate::motion::Waypoint`]'s: first column the finger axis, third the approach).
fn gripper_volumes_at(grip: &Pose, half_gap: f64) -> [Obb; 3] {
    let axis: Vec3 = grip.rot.column(0).into();
    let up: Vec3 = -Vec3::from(grip.rot.column(2));
    let rot = vifo_robots::spatial::Mat3::from_columns(&[axis, up.cross(&axis), up]);
    let site = grip.pos;
    let finger_len = TIP_BELOW_SITE + HAND_ABOVE_SITE;
    let finger = |side: f64| Obb {
        pose: Pose::new(site + axis * (side * (half_gap + 0.5 * FINGER_THICKNESS)) + up * (0.5 * finger_len - TIP_BELOW_SITE), rot),
        half: Vec3::new(0.5 * FINGER_THICKNESS, FINGER_HALF_WIDTH, 0.5 * finger_len),
    };
    let hand = Obb {
        pose: Pose::new(site + up * (HAND_ABOVE_SITE + 0.5 * HAND_HEIGHT), rot),
        half: Vec3::new(HAND_HALF_LENGTH, HAND_HALF_WIDTH, 0.5 * HAND_HEIGHT),
    };
    [finger(-1.0), finger(1.0), hand]
}

/// How many obstacle boxes the gripper, at any orientation, would overlap.
pub fn gripper_hits_at(obstacles: &Obstacles, grip: &Pose, half_gap: f64) -> usize {
    obstacles.hits(&gripper_volumes_at(grip, half_gap), 0.003)
}

/// How many obstacle boxes the gripper would overlap at `site`, fingers closing along `axis`
/// with `half_gap` between them, the hand coming straight down.
pub fn gripper_hits(obstacles: &Obstacles, site: &Vec3, axis: &Vec3, half_gap: f64) -> usize {
    obstacles.hits(&gripper_volumes(site, axis, half_gap), 0.003)
}

/// Extent of `points` along `axis`: (min, max).
pub fn extent(points: &[Vec3], axis: &Vec3) -> (f64, f64) {
    points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), p| {
        let d = p.dot(axis);
        (mn.min(d), mx.max(d))
    })
}

/// A top-down grasp of the object's upper part across a direction narrow enough for the
/// fingers, chosen so that the open fingers stay clear of the rest of the scene. Off the
/// object's middle only where no centred grasp is clear: first slid along the object's
/// length, then, where the hand still meets a neighbour, also shifted along the finger axis
/// (the far finger then pushes the object a few millimetres as it closes, faces square,
/// rather than closing turned on its corners, which can tip a flat bar). `depth` is how far
/// below the object's top the fingers close.
pub fn solid_grasp(points: &[Vec3], depth: f64, obstacles: &Obstacles) -> Option<Grasp> {
    let (lo, hi) = bounds(points);
    let z = (hi.z - depth.min((hi.z - lo.z) * 0.5)).max(lo.z + TIP_CLEARANCE);
    // Only what the fingertips reach: a knife's blade lying flat beside its handle would pull
    // the grasp's middle off the handle, over the blade, and the fingers would close on nothing.
    let band: Vec<Vec3> = points.iter().copied().filter(|p| p.z >= z - TIP_BELOW_SITE).collect();
    let mut best: Option<(usize, Grasp)> = None;
    for offsets in [Offsets::Centred, Offsets::Slid, Offsets::SlidAndShifted] {
        let found = best_solid_grasp(&band, z, obstacles, offsets);
        if found.is_some_and(|(hits, _)| best.is_none_or(|(h, _)| hits < h)) {
            best = found;
        }
        if best.is_some_and(|(hits, _)| hits == 0) {
            break;
        }
    }
    best.map(|(_, g)| g)
}

/// Steps (m) by which a solid grasp may slide off the object's middle along the fingers' width.
const OFF_CENTRE_STEP: f64 = 0.005;
/// Steps (m) by which a solid grasp may shift along the finger axis, and the clearance the
/// near finger keeps from the object while coming down.
const SHIFT_STEP: f64 = 0.0035;
const SHIFT_CLEARANCE: f64 = 0.004;

/// How far a solid grasp may move off the object's middle.
#[derive(Clone, Copy, PartialEq)]
enum Offsets {
    Centred,
    /// Along the object's length (across the finger axis), fingers still wholly on it.
    Slid,
    /// Also along the finger axis, by up to the fingers' approach clearance.
    SlidAndShifted,
}

/// Offsets 0, +step, -step, +2 step, ... up to `limit`: ties keep the smallest offset.
fn offsets_within(step: f64, limit: f64) -> impl Iterator<Item = f64> {
    (0..).map(move |k: i32| step * f64::from((k + 1) / 2) * if k % 2 == 0 { 1.0 } else { -1.0 }).take_while(move |d| d.abs() <= limit + 1e-9)
}

/// The narrowest top-down grasp of `band` at height `z` with the fewest obstacle hits, and those
/// hits, moved off the middle as `offsets` allows: the hand (20 cm along the finger axis) then
/// clears a neighbour standing beside the object's middle, such as a carton next to a cream
/// cheese box.
fn best_solid_grasp(band: &[Vec3], z: f64, obstacles: &Obstacles, offsets: Offsets) -> Option<(usize, Grasp)> {
    let mut best: Option<(usize, f64, Grasp)> = None;
    for i in 0..36 {
        let a = std::f64::consts::PI * i as f64 / 36.0;
        let axis = Vec3::new(libm::cos(a), libm::sin(a), 0.0);
        let (mn, mx) = extent(band, &axis);
        let width = mx - mn;
        if width > MAX_GRASP_WIDTH {
            continue;
        }
        let across = Vec3::new(-axis.y, axis.x, 0.0);
        let (amn, amx) = extent(band, &across);
        let centre = axis * (0.5 * (mn + mx)) + across * (0.5 * (amn + amx));
        let half_gap = (0.5 * width + APPROACH_CLEARANCE).min(OPEN_HALF_GAP);
        let room = if offsets == Offsets::Centred { 0.0 } else { (0.5 * (amx - amn) - FINGER_HALF_WIDTH - 0.003).max(0.0) };
        let reach = if offsets == Offsets::SlidAndShifted { (half_gap - 0.5 * width - SHIFT_CLEARANCE).max(0.0) } else { 0.0 };
        for shift in offsets_within(SHIFT_STEP, reach) {
            for slide in offsets_within(OFF_CENTRE_STEP, room) {
                let at = centre + across * slide + axis * shift;
                let site = Vec3::new(at.x, at.y, z);
                let hits = obstacles.hits(&gripper_volumes(&site, &axis, half_gap), 0.003);
                let grasp = Grasp { pos: site, yaw: yaw_of_axis(&axis), width, half_gap };
                if best.is_none_or(|(h, w, _)| (hits, width) < (h, w - 1e-9)) {
                    best = Some((hits, width, grasp));
                }
            }
        }
    }
    best.map(|(h, _, g)| (h, g))
}

/// A grasp on the rim of a hollow object (bowl, mug): the fingers straddle the wall and close
/// radially. Among directions around the object, prefers those facing `toward` whose fingers
/// stay clear of the rest of the scene.
pub fn rim_grasp(points: &[Vec3], centre: &Vec3, toward: &Vec3, obstacles: &Obstacles) -> Grasp {
    let (_, hi) = bounds(points);
    let rim: Vec<&Vec3> = points.iter().filter(|p| p.z > hi.z - 0.015).collect();
    let preferred = Vec3::new(toward.x - centre.x, toward.y - centre.y, 0.0);
    let preferred = if preferred.norm() > 1e-9 { preferred.normalize() } else { Vec3::new(-1.0, 0.0, 0.0) };
    let wall = 0.004;
    let mut best: Option<(usize, f64, Grasp)> = None;
    for i in 0..24 {
        let a = 2.0 * std::f64::consts::PI * i as f64 / 24.0;
        let dir = Vec3::new(libm::cos(a), libm::sin(a), 0.0);
        let outer = rim.iter().map(|p| (*p - centre).dot(&dir)).fold(0.0, f64::max);
        let at = centre + dir * (outer - wall);
        let site = Vec3::new(at.x, at.y, hi.z - 0.012);
        let hits = obstacles.hits(&gripper_volumes(&site, &dir, RIM_HALF_GAP), 0.003);
        let misalignment = 1.0 - dir.dot(&preferred);
        let grasp = Grasp { pos: site, yaw: yaw_of_axis(&dir), width: 2.0 * wall, half_gap: RIM_HALF_GAP };
        if best.is_none_or(|(h, m, _)| (hits, misalignment) < (h, m - 1e-9)) {
            best = Some((hits, misalignment, grasp));
        }
    }
    best.expect("24 directions were tried").2
}

/// Whether an object is closed on top over its origin (a pot, a box) rather than an open
/// vessel (a bowl, a mug): some part over the origin reaches above the object's mid-height.
/// An open vessel is taken by its rim; a closed one has no rim to take.
pub fn closed_top(parts: &[Obb], origin: &Vec3) -> bool {
    let points: Vec<Vec3> = parts.iter().flat_map(|b| b.corners()).collect();
    let (lo, hi) = bounds(&points);
    let middle = 0.5 * (lo.z + hi.z);
    parts.iter().any(|b| {
        let local = b.pose.inverse().transform_point(&Vec3::new(origin.x, origin.y, b.pose.pos.z));
        let over = (0..3).all(|k| local[k].abs() <= b.half[k]);
        over && b.corners().any(|p| p.z > middle)
    })
}

/// How far below the top of the pinched part the grip site may go.
const PART_DEPTHS: [f64; 3] = [0.015, 0.025, 0.035];

/// A top-down grasp of one part of an object too wide to straddle whole (a moka pot's handle
/// or spout): the fingers pinch one collision box across one of its horizontal axes, clear of
/// every other part of the object and, preferably, of the scene. Among those, the part nearest
/// the origin (the least torque on the fingers).
pub fn part_grasp(parts: &[Obb], obstacles: &Obstacles, origin: &Vec3) -> Option<Grasp> {
    let own = Obstacles { boxes: parts.to_vec() };
    let lowest = parts.iter().flat_map(|b| b.corners()).map(|p| p.z).fold(f64::INFINITY, f64::min);
    let mut best: Option<(usize, f64, Grasp)> = None;
    for part in parts {
        let corners: Vec<Vec3> = part.corners().collect();
        let top = corners.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        for k in 0..3 {
            let a: Vec3 = part.pose.rot.column(k).into();
            let flat = Vec3::new(a.x, a.y, 0.0);
            if flat.norm() < 0.7 {
                continue;
            }
            let axis = flat.normalize();
            let (mn, mx) = extent(&corners, &axis);
            let width = mx - mn;
            if width > MAX_GRASP_WIDTH {
                continue;
            }
            let half_gap = (0.5 * width + APPROACH_CLEARANCE).min(OPEN_HALF_GAP);
            for depth in PART_DEPTHS {
                let site = Vec3::new(part.pose.pos.x, part.pose.pos.y, (top - depth).max(lowest + TIP_CLEARANCE));
                let volumes = gripper_volumes(&site, &axis, half_gap);
                if own.hits(&volumes, 0.002) > 0 {
                    continue;
                }
                let hits = obstacles.hits(&volumes, 0.003);
                let off = ((site.x - origin.x).powi(2) + (site.y - origin.y).powi(2)).sqrt();
                let grasp = Grasp { pos: site, yaw: yaw_of_axis(&axis), width, half_gap };
                if best.is_none_or(|(h, o, _)| (hits, off) < (h, o - 1e-9)) {
                    best = Some((hits, off, grasp));
                }
            }
        }
    }
    best.map(|(_, _, g)| g)
}

/// Horizontal distance from `a` to `b`.
pub fn horizontal(a: &Vec3, b: &Vec3) -> f64 {
    ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt()
}

/// Highest point of the scene (objects, fixtures, arena) over a horizontal disc, excluding one
/// entity (the one being carried): what the hand or a carried object must pass over.
pub fn surface_height(sim: &Sim, centre: [f64; 2], radius: f64, exclude: Option<usize>) -> f64 {
    let mut z = sim.model().class.support_z();
    for (i, e) in sim.model().entities.iter().enumerate() {
        if Some(i) == exclude {
            continue;
        }
        for b in 0..e.model.bodies.len() {
            for p in corners(sim, i, b) {
                let d = ((p.x - centre[0]).powi(2) + (p.y - centre[1]).powi(2)).sqrt();
                if d < radius {
                    z = z.max(p.z);
                }
            }
        }
    }
    z
}

/// Highest point of the scene along a straight horizontal path (within `radius` of it).
pub fn path_height(sim: &Sim, from: [f64; 2], to: [f64; 2], radius: f64, exclude: Option<usize>) -> f64 {
    (0..=10)
        .map(|k| {
            let t = k as f64 / 10.0;
            surface_height(sim, [from[0] + t * (to[0] - from[0]), from[1] + t * (to[1] - from[1])], radius, exclude)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Height at which the hand crosses from where it is to `to`: `clearance` over everything
/// within the hand's half length of the straight way there (but `exclude`), and no lower than
/// `floor`.
pub fn cruise_height(sim: &Sim, to: &Vec3, clearance: f64, floor: f64, exclude: Option<usize>) -> f64 {
    let ee = arm::of(sim).grip_site().pos;
    (path_height(sim, [ee.x, ee.y], [to.x, to.y], 0.1, exclude) + clearance).max(floor)
}

/// What `object` stands on: the highest point of the scene right under its centre.
pub fn support_under(sim: &Sim, object: usize) -> f64 {
    let c = sim.entity_pose(object).pos;
    surface_height(sim, [c.x, c.y], 0.02, Some(object))
}

#[cfg(test)]
mod tests {
    use super::*;
    use vifo_robots::spatial::Mat3;

    fn upright(pos: Vec3, half: Vec3) -> Obb {
        Obb { pose: Pose::new(pos, Mat3::identity()), half }
    }

    /// A flat bar (7.6 x 4 x 2 cm, long along x) on a table at z = 0, and its corners.
    fn bar() -> Vec<Vec3> {
        upright(Vec3::new(0.0, 0.0, 0.01), Vec3::new(0.038, 0.02, 0.01)).corners().collect()
    }

    #[test]
    fn a_clear_bar_is_taken_square_across_its_middle() {
        let g = solid_grasp(&bar(), 0.025, &Obstacles { boxes: Vec::new() }).expect("the bar fits the fingers");
        assert!(g.pos.x.abs() < 1e-9 && g.pos.y.abs() < 1e-9, "grasp at {:?}", g.pos);
        assert!((g.width - 0.04).abs() < 1e-9, "width {}", g.width);
    }

    /// The safety scenes' knife: a 10 cm handle 2.5 cm tall and a 1.5 mm blade lying flat
    /// beyond it. The fingers close on the handle: the blade lies below the fingertips, and
    /// counting it pulled the grasp's middle 1 cm past the handle's end.
    #[test]
    fn a_knife_is_taken_by_its_handle_not_over_its_flat_blade() {
        let handle = upright(Vec3::new(-0.05, 0.0, 0.0125), Vec3::new(0.05, 0.012, 0.0125));
        let blade = upright(Vec3::new(0.06, -0.002, 0.00075), Vec3::new(0.06, 0.0135, 0.00075));
        let points: Vec<Vec3> = handle.corners().chain(blade.corners()).collect();
        let g = solid_grasp(&points, 0.025, &Obstacles { boxes: Vec::new() }).expect("the handle fits the fingers");
        // The fingers are 2.2 cm wide: wholly on the handle means the middle 1.1 cm inside it.
        assert!((-0.1 + FINGER_HALF_WIDTH..=-FINGER_HALF_WIDTH).contains(&g.pos.x), "grasp at {:?}", g.pos);
    }

    /// A carton stands where the 20 cm hand would end, beside the bar's middle, and too wide
    /// for a slide along the bar to clear it: the grasp shifts along the finger axis, away from
    /// the carton, and stays square to the bar's faces (a turned grasp closes on the corners).
    #[test]
    fn a_neighbour_at_the_hands_end_shifts_the_grasp_along_the_fingers() {
        let carton = upright(Vec3::new(0.0, -0.1285, 0.055), Vec3::new(0.02625, 0.02625, 0.055));
        let obstacles = Obstacles { boxes: vec![carton] };
        let centred = Vec3::new(0.0, 0.0, 0.01);
        assert!(gripper_hits(&obstacles, &centred, &Vec3::y(), 0.031) > 0, "the centred grasp must meet the carton");
        let g = solid_grasp(&bar(), 0.025, &obstacles).expect("the bar fits the fingers");
        let axis = Vec3::new(-libm::sin(g.yaw), libm::cos(g.yaw), 0.0);
        assert!(axis.x.abs() < 1e-9, "fingers close along {axis:?}, not square to the bar");
        assert!(g.pos.y > 0.0 && g.pos.y <= g.half_gap - 0.02 - SHIFT_CLEARANCE + 1e-9, "grasp at {:?}", g.pos);
        assert_eq!(gripper_hits(&obstacles, &g.pos, &axis, g.half_gap), 0);
    }
}
