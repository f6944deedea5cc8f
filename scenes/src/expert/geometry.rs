//! Grasp geometry from the (privileged) collision shapes of an object.

use vifo_robots::spatial::{Pose, Vec3};

use crate::catalog::ColliderShape;
use crate::sim::Sim;

/// Widest object the Panda's fingers can straddle (open gap 0.079 m) with some margin.
pub const MAX_GRASP_WIDTH: f64 = 0.068;

/// World-frame corners of every collision shape of one body of an entity.
pub fn corners(sim: &Sim, entity: usize, body: usize) -> Vec<Vec3> {
    let e = &sim.model().entities[entity];
    let pose = sim.body_pose(entity, body);
    let mut out = Vec::new();
    for c in &e.model.bodies[body].colliders {
        let half = match c.shape {
            ColliderShape::Box { half_size } => half_size,
            ColliderShape::Capsule { radius, half_length } => [radius, radius, half_length + radius],
        };
        let local = Pose::from_wxyz(c.pos, c.quat_wxyz);
        for k in 0..8 {
            let s = |bit: usize, h: f64| if k & bit == 0 { -h } else { h };
            let p = Vec3::new(s(1, half[0]), s(2, half[1]), s(4, half[2]));
            out.push(pose.transform_point(&local.transform_point(&p)));
        }
    }
    out
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

/// A top-down grasp: where the grip site goes and how the fingers are turned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grasp {
    /// Grip-site position at the grasp.
    pub pos: Vec3,
    /// Yaw of the finger axis (see [`super::motion::Waypoint`]).
    pub yaw: f64,
    /// Object width between the fingers.
    pub width: f64,
}

fn yaw_of_axis(axis: &Vec3) -> f64 {
    libm::atan2(-axis.x, axis.y)
}

/// The narrowest horizontal direction of the object's top part: grip it there if it fits
/// between the fingers. `depth` is how far below the top the fingers close.
pub fn solid_grasp(points: &[Vec3], depth: f64) -> Option<Grasp> {
    let (_, hi) = bounds(points);
    let (lo, _) = bounds(points);
    let height = hi.z - lo.z;
    let z = hi.z - depth.min(height * 0.5);
    // Points of the shapes reaching the grasp height band.
    let band: Vec<Vec3> = points.iter().copied().filter(|p| p.z >= z - 0.02).collect();
    let mut best: Option<(f64, Vec3, f64)> = None;
    for i in 0..36 {
        let a = std::f64::consts::PI * i as f64 / 36.0;
        let axis = Vec3::new(libm::cos(a), libm::sin(a), 0.0);
        let (mn, mx) = band.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), p| {
            let d = p.dot(&axis);
            (mn.min(d), mx.max(d))
        });
        let width = mx - mn;
        if best.is_none_or(|b| width < b.0 - 1e-9) {
            best = Some((width, axis, 0.5 * (mn + mx)));
        }
    }
    let (width, axis, mid) = best?;
    if width > MAX_GRASP_WIDTH {
        return None;
    }
    // Centre along the other horizontal axis, too.
    let other = Vec3::new(-axis.y, axis.x, 0.0);
    let (mn, mx) = band.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(mn, mx), p| {
        let d = p.dot(&other);
        (mn.min(d), mx.max(d))
    });
    let centre = axis * mid + other * (0.5 * (mn + mx));
    Some(Grasp { pos: Vec3::new(centre.x, centre.y, z), yaw: yaw_of_axis(&axis), width })
}

/// A grasp on the rim of a hollow object (bowl, mug): the fingers straddle the wall where it
/// faces `toward`, closing radially.
pub fn rim_grasp(points: &[Vec3], centre: &Vec3, toward: &Vec3) -> Grasp {
    let (_, hi) = bounds(points);
    let mut dir = Vec3::new(toward.x - centre.x, toward.y - centre.y, 0.0);
    if dir.norm() < 1e-9 {
        dir = Vec3::new(-1.0, 0.0, 0.0);
    }
    let dir = dir.normalize();
    // Outer radius of the top rim along that direction.
    let rim: Vec<&Vec3> = points.iter().filter(|p| p.z > hi.z - 0.015).collect();
    let outer = rim.iter().map(|p| (*p - centre).dot(&dir)).fold(0.0, f64::max);
    let wall = 0.004;
    let at = centre + dir * (outer - wall);
    Grasp { pos: Vec3::new(at.x, at.y, hi.z - 0.012), yaw: yaw_of_axis(&dir), width: 2.0 * wall }
}
