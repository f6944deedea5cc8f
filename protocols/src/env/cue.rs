//! The episode's cue, drawn into every rendered camera frame of the current state through the
//! scene_cues bridge (anchors projected from the current state, ghost layers, goal pictures).

use vifo_cues::CueSpec;
use vifo_render::{Camera, Renderer, RgbImage};
use vifo_scenes::sim::Sim;
use vifo_scenes::task::Atom;
use vifo_scenes::view::SceneView;

use super::EnvError;
use crate::scene_cues::{self, CueFacing};

/// Whether the episode's observations show a cue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CueDrawing {
    /// The protocol has no cue (original).
    NoCue,
    /// The cue is drawn into every rendered frame.
    Drawn,
    /// The cue is an object in the scene (paper §4.2); the cameras see it like any other.
    InScene,
}

/// The cue of one episode, prepared at reset.
pub struct EpisodeCue {
    spec: &'static CueSpec,
    /// The bridge's state; `None` when no camera is rendered (nothing to draw into, and the
    /// ghost's expert rollout and the goal pictures are not worth preparing).
    bridge: Option<scene_cues::EpisodeCue>,
    in_scene: bool,
}

impl EpisodeCue {
    /// Prepares `spec` for an episode starting from `sim`'s state with `size`² frames;
    /// `render` is whether any camera will be drawn.
    pub fn prepare(
        sim: &Sim,
        view: &SceneView,
        renderer: &mut Renderer,
        spec: &'static CueSpec,
        goals: &[Atom],
        size: u32,
        render: bool,
    ) -> Result<EpisodeCue, EnvError> {
        spec.check().map_err(|e| EnvError::Cue(format!("{}: {e}", spec.id())))?;
        let bridge = if render {
            let cue = scene_cues::EpisodeCue::prepare(sim, view, renderer, spec, goals, (size, size))
                .map_err(|e| EnvError::Cue(e.to_string()))?;
            Some(cue)
        } else {
            None
        };
        Ok(EpisodeCue { spec, bridge, in_scene: false })
    }

    /// The same cue drawn facing `facing` (prepared: [`CueFacing::Upright`]).
    pub fn facing(mut self, facing: CueFacing) -> EpisodeCue {
        if let Some(bridge) = self.bridge.as_mut() {
            bridge.set_facing(facing);
        }
        self
    }

    /// A cue standing in the scene as an object: nothing is drawn over the frames.
    pub fn in_scene(spec: &'static CueSpec) -> EpisodeCue {
        EpisodeCue { spec, bridge: None, in_scene: true }
    }

    /// Whether the cue is an object in the scene rather than drawn over the frames.
    pub fn is_in_scene(&self) -> bool {
        self.in_scene
    }

    pub fn spec(&self) -> &'static CueSpec {
        self.spec
    }

    /// Draws the cue into one upright camera frame of the current state.
    pub fn draw(&mut self, sim: &Sim, renderer: &mut Renderer, camera: &Camera, frame: &mut RgbImage) -> Result<(), EnvError> {
        if let Some(bridge) = self.bridge.as_mut() {
            bridge.apply(sim, renderer, camera, frame).map_err(|e| EnvError::Cue(e.to_string()))?;
        }
        Ok(())
    }
}
