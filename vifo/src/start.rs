//! Where an episode starts: the project's shipped initial states (the default, needing no files)
//! or LIBERO's own `.pruned_init` files, for comparing against LIBERO's published setup.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result, anyhow};
use rand::SeedableRng;
use vifo_scenes::init_file::{self, InitState};
use vifo_scenes::init_states::{self, EpisodeStart};
use vifo_scenes::sim::{SceneModel, Sim, sample_fixtures};
use vifo_scenes::task::Task;

/// Where initial states come from.
#[derive(Clone, Debug, Default)]
pub enum InitSource {
    /// The 50 states per task built into the program (fixtures included).
    #[default]
    Shipped,
    /// LIBERO's own `.pruned_init` files under this `init_files` directory; fixtures are placed
    /// by the seeded LIBERO-style sampler, as LIBERO's states do not record them.
    Libero(PathBuf),
}

impl InitSource {
    /// LIBERO's files when a directory is given, else the shipped states.
    pub fn from_libero_dir(dir: Option<PathBuf>) -> InitSource {
        dir.map_or(InitSource::Shipped, InitSource::Libero)
    }
}

/// The initial states of one task, from either source.
pub enum Starts {
    Shipped(&'static [EpisodeStart]),
    Libero(Vec<InitState>),
}

impl Starts {
    /// Loads the states of `task` (LIBERO's are decoded onto `model`'s state layout).
    pub fn load(task: &Task, model: &SceneModel, source: &InitSource) -> Result<Starts> {
        match source {
            InitSource::Shipped => Ok(Starts::Shipped(init_states::fixed(task)?)),
            InitSource::Libero(dir) => {
                let suite = task.suite.as_deref().ok_or_else(|| anyhow!("task {} has no suite", task.name))?;
                let path = dir.join(suite).join(format!("{}.pruned_init", task.name));
                let rows = init_file::load(&path)?;
                let states = rows.iter().map(|row| model.layout.decode(row).context(path.display().to_string())).collect::<Result<_>>()?;
                Ok(Starts::Libero(states))
            }
        }
    }

    pub fn len(&self) -> usize {
        match self {
            Starts::Shipped(s) => s.len(),
            Starts::Libero(s) => s.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A simulation at state `k` (`seed` places the fixtures of LIBERO's states).
    pub fn begin(&self, model: &Arc<SceneModel>, k: usize, seed: u64) -> Result<Sim> {
        if k >= self.len() {
            return Err(anyhow!("{} has {} initial states; state {k} is out of range", model.task.name, self.len()));
        }
        let mut sim = Sim::new(model.clone());
        match self {
            Starts::Shipped(starts) => init_states::apply(&mut sim, &starts[k]),
            Starts::Libero(states) => {
                let fixtures = sample_fixtures(&sim, &mut rand_pcg::Pcg64::seed_from_u64(seed));
                sim.apply_fixtures(&fixtures);
                sim.load_state(&states[k])
            }
        }
        .with_context(|| format!("loading initial state {k} of {}", model.task.name))?;
        Ok(sim)
    }
}
