//! What is built once per task and shared by every episode of it, on every thread: the scene
//! model (the immutable `mjModel`-like half of the simulation), the render scene's meshes and
//! the shipped initial states.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use vifo_scenes::Task;
use vifo_scenes::init_states::{self, EpisodeStart};
use vifo_scenes::sim::SceneModel;
use vifo_scenes::view::SceneView;

use super::EnvError;

/// A task's shared parts.
pub struct SceneAssets {
    pub model: Arc<SceneModel>,
    /// Template of the render scene; episodes clone it (meshes are shared by `Arc`).
    pub view: SceneView,
    pub starts: &'static [EpisodeStart],
}

/// The assets of a built-in task, built on first use and kept for the life of the process
/// (40 tasks at most).
pub fn assets(task: &'static Task) -> Result<&'static SceneAssets, EnvError> {
    static BUILT: Mutex<BTreeMap<String, &'static SceneAssets>> = Mutex::new(BTreeMap::new());
    // Held while building, so two threads never build the same task twice; building takes
    // milliseconds.
    let mut built = BUILT.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(a) = built.get(&task.name) {
        return Ok(a);
    }
    let model = SceneModel::build(task).map_err(|e| EnvError::Scene(e.to_string()))?;
    let starts = init_states::fixed(task).map_err(|e| EnvError::Scene(e.to_string()))?;
    let view = SceneView::new(&model);
    let assets: &'static SceneAssets = Box::leak(Box::new(SceneAssets { model, view, starts }));
    built.insert(task.name.clone(), assets);
    Ok(assets)
}
