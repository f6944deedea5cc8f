//! LIBERO-style random placement of fixtures (their poses are not part of LIBERO's state
//! vectors: `reset()` samples them from their BDDL regions with numpy's global RNG).

use rand::{Rng, RngExt};
use vifo_robots::spatial::{Pose, Vec3, axis_angle};

use super::episode::Sim;
use super::model::SceneModel;
use crate::task::Predicate;

/// A fixture's sampled pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixturePlacement {
    pub entity: usize,
    pub pose: Pose,
}

/// Where a fixture may stand: the region its `(On fixture region)` init atom names, offset
/// by the workspace; a yaw range; and the height at which its bottom rests on the workspace
/// (the problem class's fixture z offset).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixtureRange {
    pub entity: usize,
    /// `[x0, y0, x1, y1]` of the region, before `offset`.
    pub region: [f64; 4],
    pub offset: [f64; 2],
    pub yaw: [f64; 2],
    pub z: f64,
}

impl FixtureRange {
    /// Whether `pose` is one [`sample_fixtures`] could draw (to `tolerance` in metres and
    /// radians): what a stored initial state's fixtures are checked against.
    pub fn admits(&self, pose: &Pose, tolerance: f64) -> bool {
        let within = |v: f64, lo: f64, hi: f64| v >= lo - tolerance && v <= hi + tolerance;
        let [x0, y0, x1, y1] = self.region;
        let upright = (pose.rot * Vec3::z()).z >= 1.0 - tolerance;
        let x_axis = pose.rot * Vec3::x();
        let yaw = x_axis.y.atan2(x_axis.x);
        let tau = std::f64::consts::TAU;
        within(pose.pos.x, x0 + self.offset[0], x1 + self.offset[0])
            && within(pose.pos.y, y0 + self.offset[1], y1 + self.offset[1])
            && (pose.pos.z - self.z).abs() <= tolerance
            && upright
            && [yaw - tau, yaw, yaw + tau].iter().any(|&y| within(y, self.yaw[0], self.yaw[1]))
    }
}

/// The range of every fixture that has a placement region, in entity order.
pub fn fixture_ranges(model: &SceneModel) -> Vec<FixtureRange> {
    let class = model.class;
    let mut out = Vec::new();
    for (entity, e) in model.entities.iter().enumerate().filter(|(_, e)| !e.movable()) {
        let Some(region) = model.task.init.iter().find_map(|a| {
            (a.predicate == Predicate::On && a.args.first() == Some(&e.name)).then(|| model.task.region(&a.args[1])).flatten()
        }) else {
            continue;
        };
        let Some(region_box) = region.ranges.first().copied() else { continue };
        let [a, b] = region.yaw_rotation.unwrap_or([0.0, 0.0]);
        out.push(FixtureRange {
            entity,
            region: region_box,
            offset: [class.workspace_offset[0], class.workspace_offset[1]],
            yaw: [a, if b > a { b } else { a }],
            z: class.workspace_offset[2] + class.fixture_z_offset - e.model.bottom_offset[2],
        });
    }
    out
}

/// Samples every fixture's pose in its [`FixtureRange`]: x, y uniform in the region, yaw
/// uniform in the yaw range.
pub fn sample_fixtures(sim: &Sim, rng: &mut impl Rng) -> Vec<FixturePlacement> {
    let mut out = Vec::new();
    for r in fixture_ranges(sim.model()) {
        let [x0, y0, x1, y1] = r.region;
        let x = rng.random_range(x0..=x1) + r.offset[0];
        let y = rng.random_range(y0..=y1) + r.offset[1];
        let [a, b] = r.yaw;
        let yaw = if b > a { rng.random_range(a..=b) } else { a };
        out.push(FixturePlacement { entity: r.entity, pose: Pose::new(Vec3::new(x, y, r.z), axis_angle(&Vec3::z(), yaw)) });
    }
    out
}

impl Sim {
    /// Places fixtures (see [`sample_fixtures`]).
    pub fn apply_fixtures(&mut self, placements: &[FixturePlacement]) {
        for p in placements {
            self.place_fixture(p.entity, &p.pose);
        }
    }
}
