//! `vifo render`: a still, a GIF or a folder of frames of a task through one of LIBERO's cameras.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use vifo::expert::InitSource;
use vifo::render::{self, RenderRequest};
use vifo_scenes::view::{CameraName, ImageOrder};

#[derive(Args)]
pub struct RenderArgs {
    /// Task as <suite>/<index>, e.g. libero_spatial/0.
    #[arg(long)]
    pub task: String,
    /// Index of the initial state.
    #[arg(long, default_value_t = 0)]
    pub init: usize,
    /// LIBERO's init_files folder (holding <suite>/<task>.pruned_init).
    #[arg(long, value_name = "DIR")]
    pub libero_init: Option<PathBuf>,
    /// Seed of the fixture placement.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// agentview or robot0_eye_in_hand.
    #[arg(long, default_value = "agentview")]
    pub camera: CameraName,
    /// Image width and height in pixels.
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Rows bottom-up, as robosuite returns images and LIBERO's datasets store them.
    #[arg(long)]
    pub bottom_up: bool,
    /// PNG of the initial frame.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Animated GIF of a rollout under the hold action.
    #[arg(long, value_name = "FILE")]
    pub gif: Option<PathBuf>,
    /// Folder for one PNG per rollout frame.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<PathBuf>,
    /// Control steps of the rollout (GIF or frames).
    #[arg(long, default_value_t = 40)]
    pub steps: usize,
    /// Let the scripted expert drive the rollout (it solves the task) instead of holding still.
    #[arg(long)]
    pub expert: bool,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let request = RenderRequest {
        task: args.task,
        init: args.init,
        source: args.libero_init.map(InitSource::Libero),
        seed: args.seed,
        camera: args.camera,
        size: args.size,
        order: if args.bottom_up { ImageOrder::BottomUp } else { ImageOrder::Upright },
        png: args.output,
        gif: args.gif,
        frames: args.frames,
        steps: args.steps,
        expert: args.expert,
    };
    let frames = render::run(&request)?;
    println!("rendered {frames} frame(s) of {} (init {}) with {}", request.task, request.init, request.camera);
    Ok(())
}
