//! LIBERO-style random placement of fixtures (their poses are not part of LIBERO's state
//! vectors: `reset()` samples them from their BDDL regions with numpy's global RNG).

use rand::{Rng, RngExt};
use vifo_robots::spatial::{Pose, Vec3, axis_angle};

use super::episode::Sim;
use crate::task::Predicate;

/// A fixture's sampled pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixturePlacement {
    pub entity: usize,
    pub pose: Pose,
}

/// Samples every fixture's pose from the region its `(On fixture region)` init atom names:
/// x, y uniform in the region, yaw uniform in the region's yaw range, z so that the fixture's
/// bottom rests on the workspace (the problem class's fixture z offset).
pub fn sample_fixtures(sim: &Sim, rng: &mut impl Rng) -> Vec<FixturePlacement> {
    let model = sim.model();
    let class = model.class;
    let mut out = Vec::new();
    for (entity, e) in model.entities.iter().enumerate().filter(|(_, e)| !e.movable()) {
        let Some(region) = model.task.init.iter().find_map(|a| {
            (a.predicate == Predicate::On && a.args.first() == Some(&e.name)).then(|| model.task.region(&a.args[1])).flatten()
        }) else {
            continue;
        };
        let Some([x0, y0, x1, y1]) = region.ranges.first().copied() else { continue };
        let x = rng.random_range(x0..=x1) + class.workspace_offset[0];
        let y = rng.random_range(y0..=y1) + class.workspace_offset[1];
        let [a, b] = region.yaw_rotation.unwrap_or([0.0, 0.0]);
        let yaw = if b > a { rng.random_range(a..=b) } else { a };
        let z = class.workspace_offset[2] + class.fixture_z_offset - e.model.bottom_offset[2];
        out.push(FixturePlacement { entity, pose: Pose::new(Vec3::new(x, y, z), axis_angle(&Vec3::z(), yaw)) });
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
