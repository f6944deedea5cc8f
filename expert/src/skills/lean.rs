//! Laying a carried object on a tilted region, such as the wine rack's slanted shelf: LIBERO's
//! `On` test measures the object's origin along the region's own z axis, so on a tilted region
//! the object lies with its up axis along that z, its origin just past the region's plane.

use vifo_robots::spatial::{Mat3, Pose, Vec3, axis_angle};

use vifo_scenes::sim::{RegionBox, Sim};

use crate::arm;
use crate::geometry::{self, Obb, Obstacles};
use crate::motion::Waypoint;

/// Regions whose z axis leans further than this from the vertical are leaned on, not stood on.
const TILTED: f64 = 0.35;
/// How far past the region's plane (along its z) the object's origin is put: LIBERO counts it on
/// the region up to 10 cm past; the first 3.5 cm are left free, as the object pivots a little in
/// the fingers when it touches down and must not land on the region's lip.
const PAST_PLANE: [f64; 2] = [0.035, 0.07];
/// Margin on each side between the object and the fixture it is laid on (so 3 mm apart); it
/// drops the rest.
const GAP: f64 = 0.0015;
/// How far beyond the region's y extent the object may be held: it is let go over the surface
/// it is laid on and drops onto it.
const ACROSS_SLACK: f64 = 0.01;
/// Only the scene within this distance of the region is in the object's or the gripper's way.
const NEAR: f64 = 0.4;
/// Steps of the searches along the region's x, and along its y and z.
const STEP_X: f64 = 0.01;
const STEP: f64 = 0.002;

/// The axes LIBERO's `On` test reads a region by: it rotates the offset by R, not Rᵀ, so the
/// rows of R (see `Sim::holds`).
fn test_axes(region: &RegionBox) -> [Vec3; 3] {
    let r = &region.pose.rot;
    [r.row(0).transpose(), r.row(1).transpose(), r.row(2).transpose()]
}

/// The region's z axis if it leans enough to be leaned on.
pub fn tilted_up(sim: &Sim, region: &str) -> Option<Vec3> {
    let up = test_axes(&sim.region_box(region)?)[2];
    (up.z < libm::cos(TILTED)).then_some(up)
}

/// The horizontal axis the object turns about to lie along `up`: the fingers close along it, so
/// the turn is about their pinch and the hand stays clear of the surface below.
pub fn tilt_axis(up: &Vec3) -> Vec3 {
    Vec3::z().cross(up).normalize()
}

/// Where the carried object is laid, and the normal of the surface it is laid on (it comes
/// down along it, so it does not slide toward the lip).
#[derive(Clone, Copy, Debug)]
pub struct LeanPlan {
    pub object: Pose,
    pub normal: Vec3,
    /// The grip site in the object's frame when planned.
    held: Pose,
}

impl LeanPlan {
    /// Where the gripper goes for the object to be `above` over the point `along` the normal
    /// from where it is laid, as the object sat in the fingers when planned (it pivots a little
    /// in them; chasing that pivot only makes it swing more).
    pub fn hand(&self, along: f64, above: f64) -> Waypoint {
        let hand = Pose::new(self.object.pos + self.normal * along, self.object.rot).mul(&self.held);
        Waypoint { pos: hand.pos + Vec3::z() * above, rot: hand.rot }
    }
}

/// Plans laying `object` (held with the grip site at `grip`) on the tilted `region`: the object
/// turned so its up axis follows the region's z, its origin as near the region's plane and
/// middle as neither the object nor the gripper overlaps the scene; then turned again to lie
/// parallel to the face of the fixture it would rest on (the region need not be parallel to
/// it), and fitted once more.
pub fn plan(sim: &Sim, object: usize, region: &str, grip: &Pose) -> Option<LeanPlan> {
    let r = sim.region_box(region)?;
    let [_, ey, ez] = test_axes(&r);
    let now = sim.entity_pose(object);
    let obstacles = Obstacles::around(sim, object).near(&r.pose.pos, NEAR);
    let parts = geometry::body_boxes(sim, object, 0);
    let held = now.inverse().mul(grip);
    let fitting = Fitting { region: &r, parts: &parts, now: &now, held: &held, holding: 0.5 * arm::of(sim).finger_gap(), obstacles: &obstacles };
    let along = |up: &Vec3| rotation_between(&(now.rot * Vec3::z()), up) * now.rot;
    let (first, y) = fitting.fit(&along(&ez))?;
    // The face below: the box the object meets first moving toward the region's plane, its
    // axis nearest the region's y, pointing to the object's side.
    let side = if y < 0.0 { -ey } else { ey };
    let support = (1..=(y.abs() / STEP) as i32).find_map(|k| {
        let toward = Pose::new(first.pos - side * (f64::from(k) * STEP), first.rot);
        obstacles.first_hit(&fitting.placed(&toward), GAP)
    });
    let normal = support.map_or(side, |b| {
        let faces = [0, 1, 2].map(|k| {
            let a = Vec3::from(b.pose.rot.column(k));
            if a.dot(&side) < 0.0 { -a } else { a }
        });
        faces.into_iter().max_by(|a, c| a.dot(&side).total_cmp(&c.dot(&side))).unwrap_or(side)
    });
    let up = (ez - normal * ez.dot(&normal)).normalize();
    let (laid, _) = fitting.fit(&along(&up))?;
    Some(LeanPlan { object: laid, normal, held })
}

/// What a fit is searched with: the region, the object as it is now (its boxes, pose and the
/// grip site in its frame, the fingers' opening on it) and what it must clear.
struct Fitting<'a> {
    region: &'a RegionBox,
    parts: &'a [Obb],
    now: &'a Pose,
    held: &'a Pose,
    holding: f64,
    obstacles: &'a Obstacles,
}

impl Fitting<'_> {
    /// The object's collision boxes moved to `pose`.
    fn placed(&self, pose: &Pose) -> Vec<Obb> {
        let moved = pose.mul(&self.now.inverse());
        self.parts.iter().map(|b| b.moved(&moved)).collect()
    }

    /// The first pose (searching along the region's x, then its z, then its y, each from the
    /// middle out) where the object, turned to `rot`, and the gripper holding it clear the
    /// scene; with its offset along the region's y.
    fn fit(&self, rot: &Mat3) -> Option<(Pose, f64)> {
        let r = self.region;
        let [ex, ey, ez] = test_axes(r);
        // 0, +d, -d, +2d, ...: nearest the middle first.
        let offsets = |half: f64, step: f64| {
            let n = libm::floor(half / step + 1e-6) as i32;
            (0..=2 * n).map(move |k| step * f64::from((k + 1) / 2) * if k % 2 == 1 { 1.0 } else { -1.0 })
        };
        let past = (0..((PAST_PLANE[1] - PAST_PLANE[0]) / STEP) as i32).map(|k| r.half_size.z + PAST_PLANE[0] + f64::from(k) * STEP);
        let candidates = offsets(r.half_size.x - 0.01, STEP_X)
            .flat_map(|x| past.clone().flat_map(move |z| offsets(r.half_size.y + ACROSS_SLACK, STEP).map(move |y| (x, y, z))));
        for (x, y, z) in candidates {
            let target = Pose::new(r.pose.pos + ex * x + ey * y + ez * z, *rot);
            if self.obstacles.hits(&self.placed(&target), GAP) > 0 {
                continue;
            }
            // Clear both as it holds the object and once opened to let go.
            let hand = target.mul(self.held);
            if [self.holding, geometry::OPEN_HALF_GAP].iter().all(|&gap| geometry::gripper_hits_at(self.obstacles, &hand, gap) == 0) {
                return Some((target, y));
            }
        }
        None
    }
}

/// The smallest rotation taking unit vector `a` to unit vector `b`.
fn rotation_between(a: &Vec3, b: &Vec3) -> Mat3 {
    let axis = a.cross(b);
    let s = axis.norm();
    if s < 1e-12 {
        return Mat3::identity();
    }
    axis_angle(&(axis / s), libm::atan2(s, a.dot(b)))
}
