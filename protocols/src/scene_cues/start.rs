//! Episode starts for pictures of real scenes (gallery, `vifo render --cue`, the cue bench).

use std::sync::Arc;

use vifo_robots::action::Action;
use vifo_scenes::sim::{SceneModel, Sim};

use super::SceneCueError;

/// LIBERO's no-op steps after loading a state, before the first observation.
pub const SETTLE_STEPS: usize = 10;

/// The episode of `model`'s task at initial state `init`, after the settle steps (gripper open).
pub fn settled_start(model: &Arc<SceneModel>, init: usize) -> Result<Sim, SceneCueError> {
    // TEMPORARY until the shipped initial states are merged: LIBERO's own files.
    use rand::SeedableRng;
    let task = &model.task;
    let start_error = |why: String| SceneCueError::Start { task: task.label(), init, why };
    let path = std::path::Path::new("/work/shared/libero/libero/libero/init_files")
        .join(task.suite.as_deref().unwrap_or(""))
        .join(format!("{}.pruned_init", task.name));
    let rows = vifo_scenes::init_file::load(&path).map_err(|e| start_error(e.to_string()))?;
    let row = rows.row(init).ok_or_else(|| start_error(format!("{} states", rows.rows())))?;
    let state = model.layout.decode(row).map_err(|e| start_error(e.to_string()))?;
    let mut sim = Sim::new(model.clone());
    let fixtures = vifo_scenes::sim::sample_fixtures(&sim, &mut rand_pcg::Pcg64::seed_from_u64(0));
    sim.apply_fixtures(&fixtures);
    sim.load_state(&state).map_err(|e| start_error(e.to_string()))?;
    for _ in 0..SETTLE_STEPS {
        sim.step(&Action::hold(-1.0));
    }
    Ok(sim)
}
