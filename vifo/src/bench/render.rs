//! `vifo bench render`: camera frames per second on the full libero_spatial scene (task 0,
//! LIBERO's initial state 0), one thread.
//!
//! A control step of an evaluation updates the scene from the simulation and renders both
//! cameras. The bench first runs the scripted expert through one whole episode (reach, grasp,
//! carry, place) and keeps the posed scene and wrist camera of every step; then it renders those
//! steps in order, as an evaluation does, so that each camera's static layer is kept, rebuilt
//! and drawn over exactly as it would be (a still robot would leave the whole scene static and
//! time nothing but copies). Each camera alone and both per step are timed; the two cameras
//! also with the static layer off. Times are medians over whole passes, in this thread's CPU
//! time where Linux reports it (the machine is shared).

use anyhow::Result;
use serde::Serialize;
use vifo_expert::Expert;
use vifo_render::{Camera, Frame, RenderOptions, RenderStats, Renderer};
use vifo_scenes::view::{Cameras, ImageOrder, SceneView};

use std::sync::Arc;

use vifo_scenes::look::Look;
use vifo_scenes::sim::SceneModel;

use super::timing::{Clock, median_ms, median_pass_ms};
use crate::look::label;
use crate::render::{RenderRequest, episode};
use crate::start::InitSource;

const TASK: &str = "libero_spatial/0";
const SIZE: u32 = 256;
/// Target length of one timed batch of the scene update.
const BATCH_MS: f64 = 100.0;
/// The expert's episode is cut here if it has not succeeded yet.
const MAX_STEPS: usize = 400;

/// What `vifo bench render` prints.
#[derive(Debug, Serialize)]
pub struct RenderBench {
    pub task: &'static str,
    pub size: u32,
    /// `thread CPU time` or `wall-clock time`.
    pub clock: &'static str,
    /// The CPU (`None` where the system does not say), and what the code was built for.
    pub cpu: Option<String>,
    pub code_for: String,
    /// Control steps of the expert's episode that are rendered, and whether it succeeded.
    pub episode_steps: usize,
    pub episode_success: bool,
    /// Timed passes over the episode; every figure is the median pass's mean per step.
    pub passes: usize,
    /// Triangles in the scene, and in each camera's view frustum (first step).
    pub triangles: usize,
    pub triangles_in_view_agentview: usize,
    pub triangles_in_view_eye_in_hand: usize,
    /// What each camera's frames skipped and drew, per frame over the episode.
    pub culling_agentview: Culling,
    pub culling_eye_in_hand: Culling,
    pub ms_per_frame_agentview_256: f64,
    pub ms_per_frame_eye_in_hand_256: f64,
    /// Posing the scene from the simulation.
    pub ms_per_update: f64,
    /// Update plus both cameras: the rendering cost of one control step.
    pub ms_per_step_two_cameras_256: f64,
    /// The same with the static layer off: every frame drawn whole.
    pub ms_per_step_two_cameras_256_whole: f64,
    pub fps_agentview_256: f64,
    pub steps_per_second_two_cameras_256: f64,
    /// `built-in` or `libero-assets:<hash>`.
    pub look: String,
    /// This process's peak resident memory (Linux `VmHWM`) after building the scenes of all 40
    /// tasks with this look; `None` where the system does not report it.
    pub peak_rss_mb_all_40_tasks: Option<f64>,
    /// The targets this figure is held to, met or missed; empty for the built-in look, which
    /// they do not concern.
    pub gates: Vec<Gate>,
}

/// A control step's two 256² cameras in LIBERO's look, on one core (the time is this thread's).
pub const GATE_MS_PER_STEP: f64 = 4.0;
/// A process with all 40 tasks' scenes built in LIBERO's look.
pub const GATE_PEAK_MB: f64 = 1.5 * 1024.0;

/// One target of the render benchmark and how the run measured against it.
#[derive(Debug, PartialEq, Serialize)]
pub struct Gate {
    pub what: &'static str,
    /// `ms` or `MB`.
    pub unit: &'static str,
    /// At most this much.
    pub limit: f64,
    /// `None` where the system does not report the figure.
    pub measured: Option<f64>,
    pub met: bool,
}

/// The gates for a run's figures; none for the built-in look (`assets` false): they are about
/// LIBERO's look.
fn gates(assets: bool, ms_per_step: f64, peak_mb: Option<f64>) -> Vec<Gate> {
    if !assets {
        return Vec::new();
    }
    let gate = |what, unit, limit, measured: Option<f64>| Gate { what, unit, limit, measured, met: measured.is_some_and(|m| m <= limit) };
    vec![
        gate("control step, two 256² cameras, one core", "ms", GATE_MS_PER_STEP, Some(ms_per_step)),
        gate("peak memory, all 40 tasks' scenes built", "MB", GATE_PEAK_MB, peak_mb),
    ]
}

/// What a camera's frames skipped whole and drew, per frame over the episode (the renderer's
/// counts).
#[derive(Debug, Default, Serialize)]
pub struct Culling {
    /// Triangle clusters outside the view or facing away.
    pub clusters_culled: f64,
    /// Clusters and instances hidden behind what was drawn before them.
    pub hidden: f64,
    /// Triangles that covered a pixel centre and reached the depth test.
    pub triangles_rasterized: f64,
    /// Of those, large ones skipped whole because what was drawn before hides them.
    pub triangles_hidden: f64,
    pub vertices_lit: f64,
    /// Instances in view taken from the camera's static layer instead of drawn.
    pub instances_reused: f64,
    pub instances_drawn: f64,
}

impl Culling {
    fn add(&mut self, s: RenderStats, n: usize) {
        let n = n as f64;
        self.clusters_culled += s.clusters_culled as f64 / n;
        self.hidden += s.hidden as f64 / n;
        self.triangles_rasterized += s.triangles_rasterized as f64 / n;
        self.triangles_hidden += s.triangles_hidden as f64 / n;
        self.vertices_lit += s.vertices_lit as f64 / n;
        self.instances_reused += s.instances_reused as f64 / n;
        self.instances_drawn += s.instances_drawn as f64 / n;
    }
}

/// One control step of the episode, ready to render.
struct Posed {
    view: SceneView,
    wrist: Camera,
}

/// Runs the benchmark on initial state 0 from `source`.
pub fn run(source: InitSource, passes: usize, look: Option<Arc<Look>>) -> Result<RenderBench> {
    let request = RenderRequest { size: SIZE, look, ..RenderRequest::still(TASK, source) };
    let mut sim = episode(&request)?;
    let mut view = SceneView::with_look(sim.model(), request.look.as_deref());
    let cameras = Cameras::new(SIZE, SIZE);
    let agent = cameras.agentview(sim.model().class);
    let passes = passes.max(1);

    view.update(&sim);
    let ms_per_update = median_ms(passes, BATCH_MS, || {
        view.update(&sim);
        Ok(())
    })?;
    let mut expert = Expert::new(&sim)?;
    let mut steps = Vec::new();
    let episode_success = loop {
        view.update(&sim);
        steps.push(Posed { view: view.clone(), wrist: cameras.eye_in_hand(&sim) });
        if sim.success()? {
            break true;
        }
        if steps.len() >= MAX_STEPS {
            break false;
        }
        sim.step(&expert.act(&sim));
    };
    let n = steps.len();

    let mut frame = Frame::default();
    let (mut renderer, mut whole) = (Renderer::default(), Renderer::new(RenderOptions { static_layer: false, ..RenderOptions::default() }));
    let mut draw = |renderer: &mut Renderer, s: &Posed, camera: &Camera| s.view.render_into(renderer, camera, ImageOrder::Upright, &mut frame);
    let first = &steps[0];
    draw(&mut renderer, first, &agent)?;
    let triangles_in_view_agentview = renderer.stats().triangles_in_view;
    draw(&mut renderer, first, &first.wrist)?;
    let triangles_in_view_eye_in_hand = renderer.stats().triangles_in_view;
    let (mut culling_agentview, mut culling_eye_in_hand) = (Culling::default(), Culling::default());
    let mut counter = Renderer::default();
    for s in &steps {
        draw(&mut counter, s, &agent)?;
        culling_agentview.add(counter.stats(), n);
        draw(&mut counter, s, &s.wrist)?;
        culling_eye_in_hand.add(counter.stats(), n);
    }

    let ms_per_frame_agentview_256 = median_pass_ms(passes, n, |k| Ok(draw(&mut renderer, &steps[k], &agent)?))?;
    let ms_per_frame_eye_in_hand_256 = median_pass_ms(passes, n, |k| Ok(draw(&mut renderer, &steps[k], &steps[k].wrist)?))?;
    let mut both = |renderer: &mut Renderer, k: usize| -> Result<()> {
        draw(renderer, &steps[k], &agent)?;
        Ok(draw(renderer, &steps[k], &steps[k].wrist)?)
    };
    let ms_per_step_two_cameras_256 = ms_per_update + median_pass_ms(passes, n, |k| both(&mut renderer, k))?;
    let ms_per_step_two_cameras_256_whole = ms_per_update + median_pass_ms(passes, n, |k| both(&mut whole, k))?;

    // Every task's scene alive at once, as a process evaluating all 40 tasks holds them.
    let mut all = Vec::new();
    for task in vifo_scenes::all_tasks() {
        let model = SceneModel::build(task)?;
        all.push(SceneView::with_look(&model, request.look.as_deref()));
    }
    let peak_rss_mb_all_40_tasks = super::memory::peak_rss_mb();
    drop(all);
    Ok(RenderBench {
        gates: gates(request.look.is_some(), ms_per_step_two_cameras_256, peak_rss_mb_all_40_tasks),
        look: label(request.look.as_deref()),
        peak_rss_mb_all_40_tasks,
        task: TASK,
        size: SIZE,
        clock: if Clock::cpu_ns().is_some() { "thread CPU time" } else { "wall-clock time" },
        cpu: super::machine::cpu_name(),
        code_for: super::machine::code_for(),
        episode_steps: n,
        episode_success,
        passes,
        triangles: view.triangle_count(),
        triangles_in_view_agentview,
        triangles_in_view_eye_in_hand,
        culling_agentview,
        culling_eye_in_hand,
        ms_per_frame_agentview_256,
        ms_per_frame_eye_in_hand_256,
        ms_per_update,
        ms_per_step_two_cameras_256,
        ms_per_step_two_cameras_256_whole,
        fps_agentview_256: 1e3 / ms_per_frame_agentview_256,
        steps_per_second_two_cameras_256: 1e3 / ms_per_step_two_cameras_256,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gates_are_met_at_their_limits_missed_above_them_and_absent_for_the_built_in_look() {
        assert!(gates(false, 99.0, Some(1e6)).is_empty());
        let at = gates(true, GATE_MS_PER_STEP, Some(GATE_PEAK_MB));
        assert_eq!(at.iter().map(|g| g.met).collect::<Vec<_>>(), [true, true]);
        let over = gates(true, 4.01, Some(GATE_PEAK_MB + 1.0));
        assert_eq!(over.iter().map(|g| (g.met, g.measured)).collect::<Vec<_>>(), [(false, Some(4.01)), (false, Some(GATE_PEAK_MB + 1.0))]);
        // A figure the system does not report is not a pass.
        assert!(!gates(true, 3.0, None)[1].met);
    }
}
