//! `vifo expert`: the scripted expert's success rate per task.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, anyhow};
use rand::SeedableRng;
use serde::Serialize;
use vifo_robots::action::Action;
use vifo_scenes::expert::Expert;
use vifo_scenes::init_file::{self, InitState};
use vifo_scenes::sim::{SceneModel, Sim, sample_fixtures};
use vifo_scenes::task::Task;

/// LIBERO's no-op settle steps before a policy takes over.
pub const SETTLE_STEPS: usize = 10;

/// One expert episode.
#[derive(Clone, Debug, Serialize)]
pub struct ExpertEpisode {
    pub init: usize,
    pub success: bool,
    pub steps: usize,
    pub failure: Option<String>,
}

/// Where initial states come from.
pub enum InitSource {
    /// LIBERO's own `.pruned_init` files under this `init_files` directory.
    Libero(PathBuf),
}

/// The initial states of a task.
pub fn init_states(task: &Task, model: &SceneModel, source: &InitSource) -> Result<Vec<InitState>> {
    match source {
        InitSource::Libero(dir) => {
            let suite = task.suite.as_deref().ok_or_else(|| anyhow!("task {} has no suite", task.name))?;
            let path = dir.join(suite).join(format!("{}.pruned_init", task.name));
            let states = init_file::load(&path)?;
            states.iter().map(|row| model.layout.decode(row).context(path.display().to_string())).collect()
        }
    }
}

/// Runs the expert from one initial state with fixtures sampled from `seed`.
pub fn episode(model: &Arc<SceneModel>, state: &InitState, init: usize, seed: u64, budget: usize, trace: bool) -> Result<ExpertEpisode> {
    let mut sim = Sim::new(model.clone());
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let fixtures = sample_fixtures(&sim, &mut rng);
    sim.apply_fixtures(&fixtures);
    sim.load_state(state)?;
    for _ in 0..SETTLE_STEPS {
        sim.step(&Action::hold(-1.0));
    }
    if trace {
        for (i, e) in sim.model().entities.iter().enumerate() {
            let p = sim.entity_pose(i);
            eprintln!("{} at ({:.3} {:.3} {:.3}) quat {:?}", e.name, p.pos.x, p.pos.y, p.pos.z, p.quat_wxyz().map(|v| (v * 1000.0).round() / 1000.0));
        }
    }
    let mut expert = match Expert::new(&sim) {
        Ok(e) => e,
        Err(err) => return Ok(ExpertEpisode { init, success: false, steps: 0, failure: Some(err.to_string()) }),
    };
    let mut steps = 0;
    while steps < budget {
        if sim.success()? {
            return Ok(ExpertEpisode { init, success: true, steps, failure: None });
        }
        let action = expert.act(&sim);
        if trace && steps % 5 == 0 {
            let ee = sim.model().robot.grip_site_pose(sim.world()).pos;
            let q = sim.model().robot.joints(sim.world()).q;
            eprintln!(
                "step {steps:3} ee ({:.3} {:.3} {:.3}) fingers {:.4} {:.4} action {:?} {} contacts {:?}",
                ee.x, ee.y, ee.z, q[7], q[8], action.0.map(|v| (v * 100.0).round() / 100.0), expert.describe(), sim.robot_contacts()
            );
        }
        sim.step(&action);
        steps += 1;
        if expert.finished() && expert.failure().is_some() {
            break;
        }
    }
    let success = sim.success()?;
    Ok(ExpertEpisode { init, success, steps, failure: expert.failure().map(str::to_string) })
}

/// Default location of LIBERO's init files next to the workspace (`../shared`).
pub fn default_libero_init_dir(workspace: &Path) -> PathBuf {
    workspace.join("../shared/libero/libero/libero/init_files")
}
