//! `vifo render`: pictures of a task's episode through LIBERO's cameras.
//!
//! The episode starts from initial state `k` (the shipped states by default; LIBERO's own files
//! with their fixtures placed by the seeded LIBERO-style sampler). A still is the frame right after loading (what
//! LIBERO's `set_init_state` observation shows); a rollout adds one frame per control step under
//! the hold action (no motion, gripper open) or, with `expert`, under the scripted expert.

use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result, anyhow, bail};
use vifo_render::imageio::{GifWriter, save_png_with_text};
use vifo_render::{Frame, Renderer};
use vifo_robots::action::Action;
use vifo_expert::Expert;
use vifo_scenes::look::Look;
use vifo_scenes::sim::{SceneModel, Sim};
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

use crate::start::{InitSource, Starts};

/// Frame rate of rollout GIFs: LIBERO's 20 Hz control rate, so they play in real time.
pub const GIF_FPS: f32 = 20.0;

/// Everything `vifo render` needs.
pub struct RenderRequest {
    /// `suite/index`, e.g. `libero_spatial/0`.
    pub task: String,
    pub init: usize,
    /// Where initial states come from.
    pub source: InitSource,
    /// Seed of the fixture placement (LIBERO's states only).
    pub seed: u64,
    pub camera: CameraName,
    pub size: u32,
    pub order: ImageOrder,
    /// PNG of the first frame.
    pub png: Option<PathBuf>,
    /// Animated GIF of the rollout.
    pub gif: Option<PathBuf>,
    /// Folder for one PNG per rollout frame (`frame_0000.png`, ...).
    pub frames: Option<PathBuf>,
    /// Control steps after the first frame (rollouts only).
    pub steps: usize,
    /// Drive the rollout with the scripted expert instead of the hold action.
    pub expert: bool,
    /// LIBERO's look, or `None` for the built-in one.
    pub look: Option<Arc<Look>>,
}

impl RenderRequest {
    /// Initial state 0 of `task` (`suite/index`) through agentview at 256², upright, writing
    /// nothing: the fields a caller then changes.
    pub fn still(task: &str, source: InitSource) -> RenderRequest {
        RenderRequest {
            task: task.to_string(),
            init: 0,
            source,
            seed: 0,
            camera: CameraName::AgentView,
            size: 256,
            order: ImageOrder::Upright,
            png: None,
            gif: None,
            frames: None,
            steps: 0,
            expert: false,
            look: None,
        }
    }

    /// Whether the request names a task and something to write: checked before the look's
    /// files are loaded (seconds), so that a typo is reported at once.
    pub fn check(&self) -> Result<()> {
        if self.png.is_none() && self.gif.is_none() && self.frames.is_none() {
            bail!("nothing to write: give -o FILE.png, --gif FILE.gif or --frames DIR");
        }
        parse_task(&self.task).map(|_| ())
    }
}

/// Parses `suite/index`.
pub fn parse_task(spec: &str) -> Result<&'static vifo_scenes::Task> {
    let (suite, index) = spec.split_once('/').ok_or_else(|| anyhow!("task '{spec}': expected <suite>/<index>, e.g. libero_spatial/0"))?;
    let index: usize = index.parse().map_err(|_| anyhow!("task '{spec}': '{index}' is not a task index"))?;
    vifo_scenes::task(suite, index).ok_or_else(|| {
        anyhow!("task '{spec}': no such task (suites: {}; indices 0-9)", vifo_scenes::suite_names().join(", "))
    })
}

/// The episode `vifo render` shows: fixtures placed with `seed`, initial state `init` loaded.
pub fn episode(request: &RenderRequest) -> Result<Sim> {
    let model = SceneModel::build(parse_task(&request.task)?)?;
    Starts::load(&model.task, &model, &request.source)?.begin(&model, request.init, request.seed)
}

/// What [`run`] drew.
#[derive(Debug, PartialEq, Eq)]
pub struct Rendered {
    pub frames: usize,
    /// The first control step of a rollout after which the task's goal held.
    pub done_at: Option<usize>,
}

/// Renders what the request asks for.
pub fn run(request: &RenderRequest) -> Result<Rendered> {
    request.check()?;
    let mut sim = episode(request)?;
    let mut view = SceneView::with_look(sim.model(), request.look.as_deref());
    let mut renderer = Renderer::default();
    let cameras = Cameras::new(request.size, request.size);
    let mut frame = Frame::default();
    let mut render = |sim: &Sim, view: &mut SceneView, frame: &mut Frame| -> Result<()> {
        view.update(sim);
        view.render_into(&mut renderer, &cameras.get(request.camera, sim), request.order, frame)?;
        Ok(())
    };
    render(&sim, &mut view, &mut frame)?;
    // Each file says what drew it: a frame of LIBERO's look and one of the built-in look must
    // not be taken for each other once they leave the console.
    let look = crate::look::label(request.look.as_deref());
    let scene = format!("{} init {}, {}", request.task, request.init, request.camera);
    let text = [("look", look.as_str()), ("scene", scene.as_str())];
    if let Some(path) = &request.png {
        save_png_with_text(&frame.color, path, &text)?;
    }
    let rollout = request.gif.is_some() || request.frames.is_some();
    if !rollout {
        return Ok(Rendered { frames: 1, done_at: None });
    }
    let mut gif = match &request.gif {
        Some(path) => {
            let file = File::create(path).with_context(|| format!("creating {}", path.display()))?;
            let mut gif = GifWriter::new(BufWriter::new(file), request.size, request.size, GIF_FPS)?;
            gif.comment(&format!("look: {look}; scene: {scene}"))?;
            Some(gif)
        }
        None => None,
    };
    if let Some(dir) = &request.frames {
        vifo_protocols::runner::create_folder(dir)?;
    }
    let mut expert = if request.expert { Some(Expert::new(&sim)?) } else { None };
    let mut done_at = None;
    for t in 0..=request.steps {
        if t > 0 {
            let action = expert.as_mut().map_or(Action::hold(-1.0), |e| e.act(&sim));
            sim.step(&action);
            render(&sim, &mut view, &mut frame)?;
            if done_at.is_none() && sim.success()? {
                done_at = Some(t);
            }
        }
        if let Some(gif) = &mut gif {
            gif.add_frame(&frame.color)?;
        }
        if let Some(dir) = &request.frames {
            save_png_with_text(&frame.color, dir.join(format!("frame_{t:04}.png")), &text)?;
        }
    }
    if let Some(gif) = gif {
        gif.finish()?;
    }
    Ok(Rendered { frames: request.steps + 1, done_at })
}
