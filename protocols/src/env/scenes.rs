//! What is built once per task and shared by every episode of it, on every thread: the scene
//! model (the immutable `mjModel`-like half of the simulation), the render scene's meshes and
//! the shipped initial states.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, OnceLock};

use vifo_scenes::Task;
use vifo_scenes::catalog::ObjectModel;
use vifo_scenes::cue_object::{CueObjectKind, ENTITY_NAME};
use vifo_scenes::init_states::{self, EpisodeStart};
use vifo_scenes::look::Look;
use vifo_scenes::sim::SceneModel;
use vifo_scenes::view::SceneView;

use super::{CueFacing, EnvError};

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
    assets_with(task, None)
}

/// The assets of a built-in task with a cue object of `kind` among its entities (paper §4.2;
/// the picture on its face is painted per episode), or without one. Kept like [`assets`]
/// (40 tasks × 6 at most).
pub fn assets_with(task: &'static Task, cue_object: Option<CueObjectKind>) -> Result<&'static SceneAssets, EnvError> {
    static BUILT: Mutex<BTreeMap<(String, Option<CueObjectKind>), &'static SceneAssets>> = Mutex::new(BTreeMap::new());
    // Held while building, so two threads never build the same task twice; building takes
    // milliseconds.
    let mut built = BUILT.lock().unwrap_or_else(|p| p.into_inner());
    let key = (task.name.clone(), cue_object);
    if let Some(a) = built.get(&key) {
        return Ok(a);
    }
    let props: Vec<(&str, &'static ObjectModel)> = cue_object.map(|k| (ENTITY_NAME, k.model())).into_iter().collect();
    let model = SceneModel::build_with(task, &props).map_err(|e| EnvError::Scene(e.to_string()))?;
    let starts = init_states::fixed(task).map_err(|e| EnvError::Scene(e.to_string()))?;
    let view = SceneView::with_look(&model, look());
    let assets: &'static SceneAssets = Box::leak(Box::new(SceneAssets { model, view, starts }));
    built.insert(key, assets);
    Ok(assets)
}

/// The look of every scene this process builds: set once, before the first episode.
static LOOK: OnceLock<Option<Arc<Look>>> = OnceLock::new();

/// Draws every scene of this process with `look` (`None`: the built-in look). Must come before
/// the first scene is built; asking again for the same look is fine, for another one an error.
pub fn use_look(look: Option<Arc<Look>>) -> Result<(), EnvError> {
    let wanted = look.as_deref().map(Look::label);
    let set = LOOK.get_or_init(|| look);
    let current = set.as_deref().map(Look::label);
    if current == wanted {
        Ok(())
    } else {
        Err(EnvError::Scene(format!("this process already draws with look {}", current.unwrap_or_else(|| "built-in".into()))))
    }
}

fn look() -> Option<&'static Look> {
    LOOK.get_or_init(|| None).as_deref()
}

/// What records store as the look: empty for the built-in look (so its records are byte for
/// byte what they were before looks existed), else `libero-assets:<hash>`.
pub fn look_label() -> String {
    look().map_or_else(String::new, Look::label)
}

/// What records store as the look of an episode whose policy was sent no images (the built-in
/// policies read the simulator): its result is the same whatever the look, so a report puts
/// such rows beside rows of any look.
pub const NO_IMAGES: &str = "none";

/// A stored look's name: the built-in look's ([`vifo_scenes::look::BUILT_IN`]) for the empty
/// label, and what [`NO_IMAGES`] means for it.
pub fn look_name(look: &str) -> &str {
    match look {
        "" => vifo_scenes::look::BUILT_IN,
        NO_IMAGES => "none (the policies were sent no images)",
        _ => look,
    }
}

/// What records store as the look of frames whose drawn cues face `facing`: [`look_label`], and
/// where the cues face the model, that as well, since such rates are not comparable with those of
/// upright cues (a report refuses to mix the two, as it does looks).
pub fn recorded_look(facing: CueFacing) -> String {
    match facing {
        CueFacing::Upright => look_label(),
        CueFacing::Model => {
            format!("{} with cues facing the model", look_name(&look_label()))
        }
    }
}
