//! Why a cue could not be prepared or drawn on a scene.

use vifo_cues::CueError;
use vifo_cues::instances::InstanceError;
use vifo_render::RenderError;
use vifo_expert::PlanError;
use vifo_scenes::sim::PredicateError;

#[derive(Debug, thiserror::Error)]
pub enum SceneCueError {
    #[error("{task}: no initial state {init}: {why}")]
    Start { task: String, init: usize, why: String },
    #[error("unknown cue instance '{id}': {hint}")]
    UnknownInstance { id: String, hint: String },
    #[error("cue {cue}: {role} '{name}' is not in the scene of {task} (objects, fixtures and regions: {known})")]
    UnknownEntity { cue: String, role: &'static str, name: String, task: String, known: String },
    #[error("cue {cue}: no scene name matches the {role} '{phrase}' (candidates: {known})")]
    Ungrounded { cue: String, role: &'static str, phrase: String, known: String },
    #[error("cue {cue}: {why}")]
    Unsupported { cue: String, why: String },
    #[error("cue {cue}: the expert cannot demonstrate the goals: {source}")]
    Plan { cue: String, source: PlanError },
    #[error("cue {cue}: {source}")]
    Predicate { cue: String, source: PredicateError },
    #[error("cue {cue}: the camera is {camera_w}x{camera_h}, the frame {frame_w}x{frame_h}")]
    FrameSize { cue: String, camera_w: u32, camera_h: u32, frame_w: u32, frame_h: u32 },
    #[error(transparent)]
    Cue(#[from] CueError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Instances(#[from] InstanceError),
}
