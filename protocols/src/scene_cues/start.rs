//! Episode starts for pictures of real scenes (gallery, `vifo render --cue`, the cue bench).

use std::sync::Arc;

use vifo_scenes::init_states;
use vifo_scenes::sim::{SceneModel, Sim};

use super::SceneCueError;

/// The episode of `model`'s task at its shipped initial state `init`, after LIBERO's wait steps
/// (the hold action, gripper open) — the state of the first observation.
pub fn settled_start(model: &Arc<SceneModel>, init: usize) -> Result<Sim, SceneCueError> {
    let task = &model.task;
    let start_error = |why: String| SceneCueError::Start { task: task.label(), init, why };
    let starts = init_states::fixed(task).map_err(|e| start_error(e.to_string()))?;
    let start = starts.get(init).ok_or_else(|| start_error(format!("{} shipped states (0..{})", starts.len(), starts.len())))?;
    let mut sim = Sim::new(model.clone());
    init_states::apply(&mut sim, start).map_err(|e| start_error(e.to_string()))?;
    init_states::wait(&mut sim);
    Ok(sim)
}
