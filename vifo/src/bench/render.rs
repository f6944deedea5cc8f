//! `vifo bench render`: camera frames per second on the full libero_spatial scene (task 0,
//! LIBERO's initial state 0), one thread.
//!
//! A control step of an evaluation updates the scene from the simulation and renders both
//! cameras; that is timed as a whole, and each camera alone. Times are medians over batches
//! after a warm-up, in this thread's CPU time where Linux reports it (the machine is shared).

use anyhow::Result;
use serde::Serialize;
use vifo_render::{Frame, RenderStats, Renderer};
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

use std::sync::Arc;

use vifo_scenes::look::Look;
use vifo_scenes::sim::SceneModel;

use super::timing::{Clock, median_ms};
use crate::look::label;
use crate::start::InitSource;
use crate::render::{RenderRequest, episode};

const TASK: &str = "libero_spatial/0";
const SIZE: u32 = 256;
/// Target length of one timed batch.
const BATCH_MS: f64 = 100.0;

/// What `vifo bench render` prints.
#[derive(Debug, Serialize)]
pub struct RenderBench {
    pub task: &'static str,
    pub size: u32,
    /// `thread CPU time` or `wall-clock time`.
    pub clock: &'static str,
    /// Timed batches of about 100 ms each; every figure is the median batch's mean.
    pub batches: usize,
    /// Triangles in the scene, and in each camera's view frustum.
    pub triangles: usize,
    pub triangles_in_view_agentview: usize,
    pub triangles_in_view_eye_in_hand: usize,
    /// What each camera's frame skipped and drew.
    pub culling_agentview: Culling,
    pub culling_eye_in_hand: Culling,
    pub ms_per_frame_agentview_256: f64,
    pub ms_per_frame_eye_in_hand_256: f64,
    /// Posing the scene from the simulation.
    pub ms_per_update: f64,
    /// Update plus both cameras: the rendering cost of one control step.
    pub ms_per_step_two_cameras_256: f64,
    pub fps_agentview_256: f64,
    pub steps_per_second_two_cameras_256: f64,
    /// `built-in` or `libero-assets:<hash>`.
    pub look: String,
    /// This process's peak resident memory (Linux `VmHWM`) after building the scenes of all 40
    /// tasks with this look; `None` where the system does not report it.
    pub peak_rss_mb_all_40_tasks: Option<f64>,
}

/// What a frame skipped whole and what it drew (the renderer's counts).
#[derive(Debug, Serialize)]
pub struct Culling {
    /// Triangle clusters outside the view or facing away.
    pub clusters_culled: usize,
    /// Clusters and instances hidden behind what was drawn before them.
    pub hidden: usize,
    /// Triangles that covered a pixel centre and reached the depth test.
    pub triangles_rasterized: usize,
    /// Of those, large ones skipped whole because what was drawn before hides them.
    pub triangles_hidden: usize,
    pub vertices_lit: usize,
}

impl From<RenderStats> for Culling {
    fn from(s: RenderStats) -> Culling {
        Culling { clusters_culled: s.clusters_culled, hidden: s.hidden, triangles_rasterized: s.triangles_rasterized, triangles_hidden: s.triangles_hidden, vertices_lit: s.vertices_lit }
    }
}

/// Runs the benchmark on initial state 0 from `source`.
pub fn run(source: InitSource, batches: usize, look: Option<Arc<Look>>) -> Result<RenderBench> {
    let request = RenderRequest { size: SIZE, look, ..RenderRequest::still(TASK, source) };
    let sim = episode(&request)?;
    let mut view = SceneView::with_look(sim.model(), request.look.as_deref());
    view.update(&sim);
    let cameras = Cameras::new(SIZE, SIZE);
    let mut renderer = Renderer::default();
    let mut frame = Frame::default();
    let agent = cameras.agentview(sim.model().class);
    let batches = batches.max(1);

    let ms_per_frame_agentview_256 = median_ms(batches, BATCH_MS, || Ok(view.render_into(&mut renderer, &agent, ImageOrder::Upright, &mut frame)?))?;
    let (triangles_in_view_agentview, culling_agentview) = (renderer.stats().triangles_in_view, renderer.stats().into());
    let wrist = cameras.eye_in_hand(&sim);
    let ms_per_frame_eye_in_hand_256 = median_ms(batches, BATCH_MS, || Ok(view.render_into(&mut renderer, &wrist, ImageOrder::Upright, &mut frame)?))?;
    let (triangles_in_view_eye_in_hand, culling_eye_in_hand) = (renderer.stats().triangles_in_view, renderer.stats().into());
    let ms_per_update = median_ms(batches, BATCH_MS, || {
        view.update(&sim);
        Ok(())
    })?;
    let ms_per_step_two_cameras_256 = median_ms(batches, BATCH_MS, || {
        view.update(&sim);
        for name in CameraName::ALL {
            view.render_into(&mut renderer, &cameras.get(name, &sim), ImageOrder::Upright, &mut frame)?;
        }
        Ok(())
    })?;
    // Every task's scene alive at once, as a process evaluating all 40 tasks holds them.
    let mut all = Vec::new();
    for task in vifo_scenes::all_tasks() {
        let model = SceneModel::build(task)?;
        all.push(SceneView::with_look(&model, request.look.as_deref()));
    }
    let peak_rss_mb_all_40_tasks = super::memory::peak_rss_mb();
    drop(all);
    Ok(RenderBench {
        look: label(request.look.as_deref()),
        peak_rss_mb_all_40_tasks,
        task: TASK,
        size: SIZE,
        clock: if Clock::cpu_ns().is_some() { "thread CPU time" } else { "wall-clock time" },
        batches,
        triangles: view.triangle_count(),
        triangles_in_view_agentview,
        triangles_in_view_eye_in_hand,
        culling_agentview,
        culling_eye_in_hand,
        ms_per_frame_agentview_256,
        ms_per_frame_eye_in_hand_256,
        ms_per_update,
        ms_per_step_two_cameras_256,
        fps_agentview_256: 1e3 / ms_per_frame_agentview_256,
        steps_per_second_two_cameras_256: 1e3 / ms_per_step_two_cameras_256,
    })
}
