//! [`EpisodeCue`]: one cue instance drawn into every camera frame of one episode.

use vifo_cues::{Anchors, CueSpec, FrameInputs, InsertMode, InsertReport, Inserter, RgbaImage};
use vifo_render::{Camera, Renderer};
use vifo_scenes::sim::Sim;
use vifo_scenes::task::Atom;
use vifo_scenes::view::{Cameras, ImageOrder, SceneView};

use super::anchors::{self, CuePoints, ScenePoint};
use super::demo::{self, DEFAULT_STEP_CAP, DemoOutcome};
use super::ghost::Ghost;
use super::projector::CameraProjector;
use super::SceneCueError;

/// Ghost poses shown when the spec gives no opacities (whose count would set it).
pub const DEFAULT_GHOSTS: usize = 4;

/// Which way a cue's own drawing (its text, codes, labels and pictograms) faces.
///
/// Every model profile receives LIBERO's "180° rotation" of robosuite's bottom-up frame, which is
/// the upright frame mirrored left–right (see `serving::profile`). A cue drawn on the upright frame
/// therefore reaches those models mirrored, text reading backwards, as the scene does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CueFacing {
    /// Drawn on the upright frame: readable there, mirrored in the models' images.
    #[default]
    Upright,
    /// Drawn on the frame as the models receive it (the upright frame mirrored left–right, its
    /// anchors, ghost layers and goal pictures mirrored with it), then mirrored back: readable in
    /// the models' images. Marks anchored in the scene stay where they were; a fixed region is
    /// taken in the models' image, so it lies on the other side of the upright frame.
    Model,
}

/// Everything a cue needs that is fixed for the episode — the spec, which scene things its
/// anchors follow, the ghost's future poses, the F4 pictures — plus the inserter's cache.
/// Built once at reset from the episode's start, then [`EpisodeCue::apply`] per camera frame.
pub struct EpisodeCue {
    spec: CueSpec,
    points: CuePoints,
    ghost: Option<Ghost>,
    pictures: Vec<RgbaImage>,
    demo: Option<DemoOutcome>,
    inserter: Inserter,
    facing: CueFacing,
    /// The pictures mirrored left–right, where the cue faces the model.
    mirrored_pictures: Vec<RgbaImage>,
}

/// F4 variants drawn from the task's steps alone; every other F4 variant shows pictures.
fn draws_from_steps(variant: &str) -> bool {
    matches!(variant, "pictogram_strip" | "step_cards")
}

impl EpisodeCue {
    /// Prepares `spec` for the episode `sim` is at (after its settle steps).
    ///
    /// * Scene-anchored cues (F2, F5, F6, F7) find their source and target in the scene.
    /// * F3 runs the scripted expert on `goals` (the goals the cue shows) on a fork of `sim`,
    ///   records the manipulated object and keeps K poses evenly spaced along its motion, the
    ///   final pose included (K = the number of `params.alphas`, else [`DEFAULT_GHOSTS`]).
    /// * F4 picture variants get, rendered from agentview at `size`: the start, the moment the
    ///   object is lifted, the end of every step (a goal atom becoming true) and the final state
    ///   of the same kind of demonstration; the last picture is the goal.
    ///
    /// A demonstration that fails still gives ghosts and pictures of the states it reached;
    /// [`EpisodeCue::demo`] says so. `view` is only read (a copy renders the pictures).
    pub fn prepare(
        sim: &Sim,
        view: &SceneView,
        renderer: &mut Renderer,
        spec: &CueSpec,
        goals: &[Atom],
        size: (u32, u32),
    ) -> Result<EpisodeCue, SceneCueError> {
        spec.check()?;
        let cue = spec.id();
        let points = anchors::resolve(sim, spec)?;
        let wants_ghost = spec.insert_mode == InsertMode::SimulatorState;
        let wants_pictures = spec.family == vifo_cues::Family::F4 && !draws_from_steps(&spec.variant);
        let moved = match points.source {
            ScenePoint::Entity { entity } if sim.model().entities[entity].movable() => Some(entity),
            _ => None,
        };
        let mut cue_state = EpisodeCue {
            spec: spec.clone(),
            points,
            ghost: None,
            pictures: Vec::new(),
            demo: None,
            inserter: Inserter::new(),
            facing: CueFacing::Upright,
            mirrored_pictures: Vec::new(),
        };
        if !(wants_ghost || wants_pictures) {
            return Ok(cue_state);
        }
        if wants_ghost && moved.is_none() {
            let why = format!("a ghost needs a movable source, and '{}' is not one", spec.source);
            return Err(SceneCueError::Unsupported { cue, why });
        }
        if goals.is_empty() {
            return Err(SceneCueError::Unsupported { cue, why: "no goal atoms to demonstrate".into() });
        }
        let cap = sim.model().task.suite.as_deref().and_then(vifo_scenes::suite).map_or(DEFAULT_STEP_CAP, |s| s.max_steps as usize);
        let key = demo::RecordingKey::new(sim, goals, moved, cap, wants_pictures.then(|| demo::PictureKey::new(size, view, renderer)));
        let recording = demo::recorded(key, || {
            let camera = Cameras::new(size.0, size.1).agentview(sim.model().class);
            let mut painter = view.clone();
            let mut pictures = Vec::new();
            let mut picture = |s: &Sim| -> Result<(), SceneCueError> {
                if wants_pictures {
                    painter.update(s);
                    let frame = painter.render(renderer, &camera, ImageOrder::Upright)?;
                    let data = frame.color.data.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
                    pictures.push(RgbaImage { width: frame.width(), height: frame.height(), data });
                }
                Ok(())
            };
            picture(sim)?;
            let demo = demo::run(sim, &cue, goals, moved, cap, &mut picture)?;
            Ok(demo::Recording { demo, pictures })
        })?;
        if let (true, Some(entity)) = (wants_ghost, moved) {
            let k = spec.params.alphas.as_ref().map_or(DEFAULT_GHOSTS, Vec::len);
            let poses = demo::spaced_poses(&recording.demo.track, k);
            cue_state.ghost = Some(Ghost::new(view, sim, entity, &poses));
        }
        cue_state.pictures = recording.pictures.clone();
        cue_state.demo = Some(recording.demo.outcome.clone());
        Ok(cue_state)
    }

    /// Draws the cue into `frame`, an upright frame `camera` rendered of the current state of
    /// `sim` (insert before flipping to robosuite's bottom-up order). Anchors are projected
    /// again on every call; ghost layers are rendered with `renderer` when the camera moved.
    /// The cue faces as [`EpisodeCue::set_facing`] set it. On error the frame is unchanged.
    pub fn apply(
        &mut self,
        sim: &Sim,
        renderer: &mut Renderer,
        camera: &Camera,
        frame: &mut vifo_render::RgbImage,
    ) -> Result<InsertReport, SceneCueError> {
        if (camera.width, camera.height) != (frame.width, frame.height) {
            return Err(SceneCueError::FrameSize {
                cue: self.spec.id(),
                camera_w: camera.width,
                camera_h: camera.height,
                frame_w: frame.width,
                frame_h: frame.height,
            });
        }
        // Ghosts use the anchors too: a trail starts at the object where it stands now.
        let anchors = match self.spec.insert_mode {
            InsertMode::SceneAnchored | InsertMode::SimulatorState => self.anchors(sim, camera),
            _ => Anchors::default(),
        };
        let facing_model = self.facing == CueFacing::Model;
        let ghost_layers = match &mut self.ghost {
            Some(g) => g.layers(renderer, camera)?,
            None => &[],
        };
        let inputs = FrameInputs {
            anchors: if facing_model { anchors.mirrored(frame.width) } else { anchors },
            ghost_layers,
            pictures: if facing_model { &self.mirrored_pictures } else { &self.pictures },
        };
        let mut image =
            vifo_cues::RgbImage { width: frame.width, height: frame.height, data: std::mem::take(&mut frame.data) };
        if facing_model {
            image.mirror_left_right();
        }
        let result = self.inserter.insert(&mut image, &self.spec, &inputs);
        if facing_model {
            image.mirror_left_right();
        }
        frame.data = image.data;
        Ok(result?)
    }

    /// Which way the cue's drawing faces from now on (at preparation: [`CueFacing::Upright`]).
    pub fn set_facing(&mut self, facing: CueFacing) {
        let model = facing == CueFacing::Model;
        self.mirrored_pictures = Vec::new();
        if model {
            self.mirrored_pictures = self.pictures.clone();
            self.mirrored_pictures.iter_mut().for_each(RgbaImage::mirror_left_right);
        }
        if let Some(g) = self.ghost.as_mut() {
            g.set_mirrored(model);
        }
        self.facing = facing;
    }

    /// The source and target as `camera` sees them at the current state.
    pub fn anchors(&self, sim: &Sim, camera: &Camera) -> Anchors {
        let target = self.points.target.as_ref().map(|t| t.world(sim));
        Anchors::from_world(&CameraProjector(camera), Some(&self.points.source.world(sim)), target.as_ref())
    }

    pub fn spec(&self) -> &CueSpec {
        &self.spec
    }

    /// The scene things the cue's source and target follow.
    pub fn points(&self) -> &CuePoints {
        &self.points
    }

    /// How the expert's demonstration ended (F3 and F4 picture cues; `None` for the others).
    /// When it failed, the ghost and pictures show the states it reached — log it.
    pub fn demo(&self) -> Option<&DemoOutcome> {
        self.demo.as_ref()
    }

    /// The F4 pictures in time order (start first, goal last); empty for other cues.
    pub fn pictures(&self) -> &[RgbaImage] {
        &self.pictures
    }

    /// Number of ghost layers (0 for non-ghost cues).
    pub fn ghost_count(&self) -> usize {
        self.ghost.as_ref().map_or(0, Ghost::len)
    }

    /// The ghost layers as `camera` sees them, in time order (empty for non-ghost cues).
    pub fn ghost_layers(&mut self, renderer: &mut Renderer, camera: &Camera) -> Result<&[RgbaImage], SceneCueError> {
        match &mut self.ghost {
            Some(g) => Ok(g.layers(renderer, camera)?),
            None => Ok(&[]),
        }
    }
}
