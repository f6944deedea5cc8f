//! Baselines without a task: all-zero actions and seeded uniform noise.

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

use crate::policy::{EpisodeState, Observation, Policy, PolicyError};

/// Sends `[0; 7]` every step (no motion, gripper command 0).
pub struct Zero;

impl Policy for Zero {
    fn name(&self) -> String {
        "zero".to_string()
    }

    fn act(&mut self, _obs: &Observation) -> Result<[f64; 7], PolicyError> {
        Ok([0.0; 7])
    }

    fn uses_images(&self) -> bool {
        false
    }

    fn holding_still(&self) -> bool {
        true
    }
}

/// Uniform actions in [-1, 1]⁷ from a generator seeded with the episode seed, so an episode is
/// the same on every run and thread.
#[derive(Default)]
pub struct Random {
    rng: Option<Pcg64>,
}

impl Policy for Random {
    fn name(&self) -> String {
        "random".to_string()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.rng = None;
        Ok(())
    }

    fn act(&mut self, _obs: &Observation) -> Result<[f64; 7], PolicyError> {
        Err(PolicyError::Other("random needs the episode seed (run it through the environment)".into()))
    }

    fn act_with_state(&mut self, _obs: &Observation, state: &EpisodeState<'_>) -> Result<[f64; 7], PolicyError> {
        let rng = self.rng.get_or_insert_with(|| Pcg64::seed_from_u64(state.seed));
        Ok(std::array::from_fn(|_| rng.random_range(-1.0..=1.0)))
    }

    fn uses_images(&self) -> bool {
        false
    }
}
