//! `vifo render`: a still, a GIF or a folder of frames of a task through one of LIBERO's cameras.

use std::path::PathBuf;

use anyhow::{Result, anyhow, bail};
use clap::Args;
use vifo::look::{LookArgs, label};
use vifo::start::InitSource;
use vifo::render::{self, RenderRequest};
use vifo_protocols::env::{self, Env, EnvConfig};
use vifo_protocols::scene_cues::{self, EpisodeCue, start::settled_start};
use vifo_protocols::{CueForm, EpisodeSpec, Protocol, benchmark};
use vifo_render::{Renderer, RgbImage};
use vifo_render::imageio::save_png_with_text;
use vifo_scenes::sim::SceneModel;
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

#[derive(Args)]
pub struct RenderArgs {
    /// Task as <suite>/<index>, e.g. libero_spatial/0 (implied by --cue).
    #[arg(long, required_unless_present = "cue")]
    pub task: Option<String>,
    /// Draw this cue instance (e.g. libero_goal/1/F2/straight_arrow_red; `vifo cues list --ids`
    /// prints them) on the frame of the shipped initial state --init after LIBERO's settle steps.
    #[arg(long, value_name = "INSTANCE", conflicts_with_all = ["libero_init", "gif", "frames"])]
    pub cue: Option<String>,
    /// With --cue (F1 text, F6 signs, F8 codes): the cue as an object standing in the scene
    /// (paper §4.2) instead of drawn over the frame.
    #[arg(long, requires = "cue")]
    pub as_object: bool,
    /// Index of the initial state.
    #[arg(long, default_value_t = 0)]
    pub init: usize,
    /// Start from LIBERO's own initial states in this init_files folder (holding
    /// <suite>/<task>.pruned_init) instead of the shipped ones.
    #[arg(long, value_name = "DIR")]
    pub libero_init: Option<PathBuf>,
    /// Seed of the fixture placement (with --libero-init; the shipped states fix the fixtures).
    #[arg(long, default_value_t = 0, requires = "libero_init")]
    pub seed: u64,
    /// agentview or robot0_eye_in_hand.
    #[arg(long, default_value = "agentview")]
    pub camera: CameraName,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::image_side)]
    pub size: u32,
    /// Rows bottom-up, as robosuite returns images and LIBERO's datasets store them.
    #[arg(long)]
    pub bottom_up: bool,
    /// With --cue: which way the cue faces (as `vifo run --cue-facing`): upright, or model
    /// (readable in the mirrored image the models receive).
    #[arg(long, value_enum, default_value_t = super::Facing::Upright, requires = "cue")]
    pub cue_facing: super::Facing,
    /// With --cue: write the frame as this profile's model receives it (its orientation and
    /// size: pi05, openvla-oft, ...; see `vifo run --model-profile`), to see what it sees.
    #[arg(long, value_name = "PROFILE", requires = "cue")]
    pub model_profile: Option<String>,
    /// PNG of the initial frame.
    #[arg(short = 'o', long = "out", visible_alias = "output", value_name = "FILE", value_parser = super::png_file)]
    pub output: Option<PathBuf>,
    /// Animated GIF of a rollout under the hold action.
    #[arg(long, value_name = "FILE", value_parser = super::gif_file)]
    pub gif: Option<PathBuf>,
    /// Folder for one PNG per rollout frame.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// Control steps of the rollout (GIF or frames).
    #[arg(long, default_value_t = 40, value_parser = super::step_count)]
    pub steps: usize,
    /// Let the scripted expert drive the rollout (it solves the task) instead of holding still.
    #[arg(long)]
    pub expert: bool,
    #[command(flatten)]
    pub look: LookArgs,
}

pub fn run(args: RenderArgs) -> Result<()> {
    if let Some(id) = &args.cue {
        return if args.as_object { render_cue_object(id, &args) } else { render_cue(id, &args) };
    }
    let mut request = RenderRequest {
        task: args.task.unwrap_or_default(),
        init: args.init,
        source: InitSource::from_libero_dir(args.libero_init),
        seed: args.seed,
        camera: args.camera,
        size: args.size,
        order: if args.bottom_up { ImageOrder::BottomUp } else { ImageOrder::Upright },
        png: args.output,
        gif: args.gif,
        frames: args.frames,
        steps: args.steps,
        expert: args.expert,
        look: None,
    };
    request.check()?;
    request.look = args.look.look()?;
    let rendered = render::run(&request)?;
    let look = label(request.look.as_deref());
    let written: Vec<String> = [&request.png, &request.gif, &request.frames].into_iter().flatten().map(|p| p.display().to_string()).collect();
    println!(
        "rendered {} frame(s) of {} (init {}) with {}, look {look} -> {}",
        rendered.frames,
        request.task,
        request.init,
        request.camera,
        written.join(", ")
    );
    if request.gif.is_some() || request.frames.is_some() {
        match rendered.done_at {
            Some(t) => println!("the task's goal held from step {t}"),
            None if request.expert => println!(
                "the task's goal did not hold within {} steps: the expert may need more (--steps; the suites allow 220 to 520)",
                request.steps
            ),
            None => println!("the task's goal did not hold within {} steps", request.steps),
        }
    }
    Ok(())
}

/// `--cue`: the instance's scene at a shipped initial state, the cue drawn on the chosen camera.
fn render_cue(id: &str, args: &RenderArgs) -> Result<()> {
    let spec = scene_cues::instance(id)?;
    if let Some(task) = args.task.as_deref().filter(|t| *t != spec.task) {
        bail!("--task {task} differs from the task of cue {id} ({}); leave --task out", spec.task);
    }
    let output = args.output.as_ref().ok_or_else(|| anyhow!("give -o FILE.png for the frame with the cue"))?;
    if args.bottom_up {
        bail!("--bottom-up is not available with --cue (cues are drawn on upright frames; --model-profile gives a model's view)");
    }
    let profile = args.model_profile.as_deref().map(super::profile).transpose()?;
    let task = scene_cues::task_of(spec)?;
    let model = SceneModel::build(task)?;
    let sim = settled_start(&model, args.init)?;
    let look = args.look.look()?;
    let mut view = SceneView::with_look(&model, look.as_deref());
    view.update(&sim);
    let mut renderer = Renderer::default();
    let camera = Cameras::new(args.size, args.size).get(args.camera, &sim);
    let mut cue = EpisodeCue::prepare(&sim, &view, &mut renderer, spec, &task.goal, (args.size, args.size))?;
    cue.set_facing(args.cue_facing.into());
    let mut frame = view.render(&mut renderer, &camera, ImageOrder::Upright)?.color;
    let report = cue.apply(&sim, &mut renderer, &camera, &mut frame)?;
    let seen = match profile {
        Some(p) => {
            let seen = p.image(&vifo_cues::RgbImage::from_raw(frame.width, frame.height, frame.data)?);
            RgbImage { width: seen.width, height: seen.height, data: seen.data }
        }
        None => frame,
    };
    let look = label(look.as_deref());
    let facing = match args.cue_facing {
        super::Facing::Upright => "",
        super::Facing::Model => ", cue facing the model",
    };
    let as_seen = profile.map_or_else(String::new, |p| format!(", as {} receives it ({}x{})", p.name, seen.width, seen.height));
    let scene = format!("{id} on {} (init {}) with {}{facing}{as_seen}", spec.task, args.init, args.camera);
    save_png_with_text(&seen, output, &[("look", &look), ("scene", &scene)])?;
    println!("{scene}, look {look} -> {} ({})", output.display(), serde_json::to_string(&report)?);
    if let Some(demo) = cue.demo().filter(|d| !d.success) {
        println!("note: the expert's demonstration failed ({}); the cue shows the states it reached", demo.failure.as_deref().unwrap_or("unknown"));
    }
    Ok(())
}

/// `--cue ID --as-object`: the episode's first observation with the cue standing in the scene,
/// as `vifo run` shows it to policies (authorized protocol, initial state --init).
fn render_cue_object(id: &str, args: &RenderArgs) -> Result<()> {
    let cue = benchmark::instances::find(id)?;
    let task = benchmark::instances::task_of(cue)?;
    if let Some(given) = args.task.as_deref().filter(|t| *t != cue.task) {
        bail!("--task {given} differs from the task of cue {id} ({}); leave --task out", cue.task);
    }
    let output = args.output.as_ref().ok_or_else(|| anyhow!("give -o FILE.png for the frame with the cue object"))?;
    // An episode spec wraps its init around the shipped states (episode k of a run starts at
    // state k mod 50); a picture must show the state it is labelled with.
    let shipped = benchmark::specs::INIT_STATES;
    anyhow::ensure!(args.init < shipped, "--init {}: the tasks have {shipped} shipped initial states (0..{shipped})", args.init);
    let look = args.look.look()?;
    env::scenes::use_look(look.clone())?;
    let order = if args.bottom_up { ImageOrder::BottomUp } else { ImageOrder::Upright };
    let mut env = Env::new(EnvConfig { size: args.size, order, cameras: vec![args.camera], ..EnvConfig::default() });
    let spec = EpisodeSpec { cue_form: CueForm::Object, ..benchmark::specs::spec(&task, Protocol::Authorized, Some(id), args.init, 0)? };
    let obs = env.reset(&spec)?;
    let image = obs.image(args.camera);
    let (look, scene) = (label(look.as_deref()), format!("{id} as a scene object on {} (init {}) with {}", cue.task, args.init, args.camera));
    let image = vifo_render::RgbImage { width: image.width, height: image.height, data: image.data.clone() };
    save_png_with_text(&image, output, &[("look", &look), ("scene", &scene)])?;
    println!("{scene}, look {look} -> {}", output.display());
    Ok(())
}
