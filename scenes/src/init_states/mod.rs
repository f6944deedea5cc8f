//! The project's own fixed initial states: 50 per task, sampled with LIBERO's placement rules,
//! settled in our physics and shipped in our own format.
//!
//! LIBERO evaluates every episode from one of 50 fixed states per task. Its files are its data,
//! so we generate our own with the same rules and ship them (`scenes/init_states/<suite>.json`).
//! Unlike LIBERO's, our states carry the fixture poses too, so an episode start is fully
//! determined by its state.
//!
//! - [`sample`]: one settled, validated [`EpisodeStart`] from a seed (see `sample.rs` for the
//!   pipeline and `place.rs` for LIBERO's per-atom placement rules).
//! - [`seed`]: the seed of state `k` of a suite's task `i`.
//! - [`fixed`]: the shipped states of a built-in task (embedded, parsed on first use);
//!   [`apply`] puts one into a [`Sim`].
//! - [`check`]: what the shipped states are judged by (init atoms after LIBERO's 10 wait steps,
//!   support, drift under a zero action).
//! - [`parse`] / [`write`](fn@write): the JSON format.

mod articulation;
mod check;
mod drop;
mod format;
mod orientation;
mod place;
mod plan;
mod sample;
mod shipped;

pub use check::{Check, DRIFT_STEPS, MAX_DRIFT, WAIT_STEPS, below_support, check, wait, wait_action};
pub use format::{FORMAT, FormatError, SuiteStates, TaskStates, parse, write};
pub use orientation::spawn_quat;
pub use sample::{ARM_NOISE_STD, SETTLE_STEPS, SampleError, sample, seed};
pub use shipped::{ShippedError, fixed, shipped_suite, starts_for};

use crate::init_file::InitState;
use crate::sim::{Sim, StateError};
use vifo_robots::spatial::Pose;

/// Everything that fixes an episode's first frame: LIBERO's state (arm, gripper, object poses,
/// articulation joints; velocities zero) plus the pose of every fixture.
#[derive(Clone, Debug, PartialEq)]
pub struct EpisodeStart {
    pub state: InitState,
    /// Every non-arena fixture of the scene, in scene order.
    pub fixtures: Vec<FixturePose>,
}

/// Where a fixture stands (its root body; articulated parts follow their joints).
#[derive(Clone, Debug, PartialEq)]
pub struct FixturePose {
    pub name: String,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
}

/// Puts `start` into `sim`: fixtures first (their parts move with them), then LIBERO's state.
/// A start that does not fit the scene is an error and changes nothing.
pub fn apply(sim: &mut Sim, start: &EpisodeStart) -> Result<(), StateError> {
    let fixtures = start
        .fixtures
        .iter()
        .map(|f| {
            let fixture = sim.model().entity(&f.name).filter(|(_, e)| !e.movable()).map(|(i, _)| i);
            let entity = fixture.ok_or_else(|| StateError::UnknownObject(f.name.clone()))?;
            crate::sim::check_pose(&f.pos, &f.quat_wxyz, || format!("of fixture {}", f.name))?;
            Ok((entity, Pose::from_wxyz(f.pos, f.quat_wxyz)))
        })
        .collect::<Result<Vec<_>, _>>()?;
    sim.check_state(&start.state)?;
    for (entity, at) in &fixtures {
        sim.place_fixture(*entity, at);
    }
    sim.load_state(&start.state)
}
