//! The episode's cue, drawn into every rendered camera frame of the current state.
//!
//! Drawing a cue into a simulated scene (anchors projected from the current state, ghost
//! layers, goal pictures) is the scene_cues bridge's job (`protocols::scene_cues`, written in
//! parallel). Until it is merged, [`DRAWING`] is [`CueDrawing::Unavailable`]: observations
//! carry no cue and `vifo run` says so before it starts. The environment already calls
//! [`EpisodeCue::draw`] once per rendered camera frame, so wiring the bridge in changes only
//! this file.

use vifo_cues::{CueSpec, RgbImage};
use vifo_render::{Camera, Renderer};
use vifo_scenes::sim::Sim;
use vifo_scenes::view::{CameraName, SceneView};

use super::EnvError;

/// Whether the episode's observations show its cue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CueDrawing {
    /// The protocol has no cue (original).
    NoCue,
    /// The cue is drawn into every rendered frame.
    Drawn,
    /// The episode has a cue but this build cannot draw it into scene frames yet.
    Unavailable,
}

/// What this build does with an episode's cue.
pub const DRAWING: CueDrawing = CueDrawing::Unavailable;

/// The cue of one episode, prepared at reset.
pub struct EpisodeCue {
    spec: &'static CueSpec,
}

impl EpisodeCue {
    /// Prepares `spec` for an episode starting from `sim`'s state with `size`² frames.
    pub fn prepare(_sim: &Sim, _view: &mut SceneView, spec: &'static CueSpec, _size: u32) -> Result<EpisodeCue, EnvError> {
        spec.check().map_err(|e| EnvError::Cue(format!("{}: {e}", spec.id())))?;
        Ok(EpisodeCue { spec })
    }

    pub fn spec(&self) -> &'static CueSpec {
        self.spec
    }

    /// Draws the cue into one upright camera frame of the current state (see [`DRAWING`]).
    pub fn draw(
        &mut self,
        _sim: &Sim,
        _view: &SceneView,
        _renderer: &mut Renderer,
        _camera: &Camera,
        _name: CameraName,
        _frame: &mut RgbImage,
    ) -> Result<(), EnvError> {
        Ok(())
    }
}
