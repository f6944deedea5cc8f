//! `vifo bench cues`: what drawing a cue instance into a 256² camera frame costs, per family,
//! on real frames (shipped initial state 0 after the settle steps), one thread.
//!
//! Timed per call: restoring the clean frame (a 196 kB copy, a few µs) and
//! [`EpisodeCue::apply`] — projecting the anchors from the simulation, ghost layers, the cue
//! library's drawing and compositing — but not rendering the scene itself. Preparing an
//! episode's cue (the expert's demonstration for ghosts and goal pictures) is timed once per
//! instance and reported apart.
//!
//! Agentview is fixed and the scene here still, so after the first frame its ghost layers are
//! reused, and so is a scene-anchored cue's drawn layer (the inserter keeps the last two): its
//! figure is the cost while the anchored objects rest. The wrist camera moves with the arm, so
//! it is timed with three cameras in turn (1 mm apart), which defeats both caches and renders
//! the K ghost layers and draws the cue on every call, as a moving arm does.

use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use vifo_cues::{Family, variants};
use vifo_protocols::scene_cues::start::settled_start;
use vifo_protocols::scene_cues::{EpisodeCue, instance, task_of};
use vifo_render::glam::Vec3;
use vifo_render::{Camera, RgbImage, Renderer};
use vifo_scenes::sim::{SceneModel, Sim};
use vifo_scenes::view::{Cameras, ImageOrder, SceneView};

use super::timing::{Clock, median_ms};

/// Tasks the instances are taken from: one per suite, a drawer task among them.
pub const TASKS: [&str; 4] = ["libero_spatial/0", "libero_object/0", "libero_goal/1", "libero_10/3"];
const SIZE: u32 = 256;
/// Target length of one timed batch (many instances are timed, so batches are short).
const BATCH_MS: f64 = 40.0;

/// One family's (or the ghost's) figures.
#[derive(Debug, Serialize)]
pub struct FamilyCost {
    pub family: Family,
    /// Instances timed (every variant of the family on each task that can carry it).
    pub instances: usize,
    pub ms_agentview_mean: f64,
    pub ms_agentview_max: f64,
    pub ms_wrist_mean: f64,
    pub ms_wrist_max: f64,
    /// The variant with the highest cost on either camera.
    pub slowest: String,
    /// Mean time to prepare the episode's cue (ghosts and goal pictures run the expert).
    pub ms_prepare_mean: f64,
    /// The most one insertion may cost ([`budget_ms`]), and whether the slowest instance, on
    /// either camera, kept to it.
    pub ms_budget: f64,
    pub within_budget: bool,
}

/// The most inserting one cue into a 256² frame may cost: ghosts (F3) render the scene K times
/// and get 3 ms, every other family 0.5 ms.
pub fn budget_ms(family: Family) -> f64 {
    if family == Family::F3 { 3.0 } else { 0.5 }
}

/// What `vifo bench cues` prints.
#[derive(Debug, Serialize)]
pub struct CueBench {
    pub size: u32,
    pub clock: &'static str,
    pub batches: usize,
    pub tasks: Vec<String>,
    pub families: Vec<FamilyCost>,
    /// Instances whose demonstration failed (timed all the same).
    pub failed_demos: Vec<String>,
}

/// One task's episode start and its clean frames.
struct Scene {
    sim: Sim,
    view: SceneView,
    agent: (Camera, RgbImage),
    /// Three wrist cameras 1 mm apart, with the frame of the first.
    wrist: ([Camera; 3], RgbImage),
}

fn scene(task: &str, renderer: &mut Renderer) -> Result<Scene> {
    let (suite, index) = task.split_once('/').ok_or_else(|| anyhow::anyhow!("task '{task}': expected <suite>/<index>"))?;
    let t = vifo_scenes::task(suite, index.parse()?).ok_or_else(|| anyhow::anyhow!("no built-in task {task}"))?;
    let model = SceneModel::build(t)?;
    let sim = settled_start(&model, 0)?;
    let mut view = SceneView::new(&model);
    view.update(&sim);
    let cameras = Cameras::new(SIZE, SIZE);
    let agent = cameras.agentview(model.class);
    let wrist = cameras.eye_in_hand(&sim);
    let nudged = |dx: f32| Camera { position: wrist.position + Vec3::new(dx, 0.0, 0.0), ..wrist };
    let agent_frame = view.render(renderer, &agent, ImageOrder::Upright)?.color;
    let wrist_frame = view.render(renderer, &wrist, ImageOrder::Upright)?.color;
    Ok(Scene { sim, view, agent: (agent, agent_frame), wrist: ([wrist, nudged(0.001), nudged(0.002)], wrist_frame) })
}

/// Mean ms of one `apply` on a copy of `clean`, cycling through `cameras`.
fn time_apply(cue: &mut EpisodeCue, sim: &Sim, renderer: &mut Renderer, cameras: &[Camera], clean: &RgbImage, batches: usize) -> Result<f64> {
    let mut frame = clean.clone();
    let mut turn = 0;
    median_ms(batches, BATCH_MS, || {
        frame.data.copy_from_slice(&clean.data);
        cue.apply(sim, renderer, &cameras[turn % cameras.len()], &mut frame)?;
        turn += 1;
        Ok(())
    })
}

/// Runs the benchmark over `tasks` (keys `suite/index`).
pub fn run(tasks: &[String], batches: usize) -> Result<CueBench> {
    let batches = batches.max(1);
    let mut renderer = Renderer::default();
    let scenes: Vec<(String, Scene)> = tasks.iter().map(|t| Ok((t.clone(), scene(t, &mut renderer)?))).collect::<Result<_>>()?;
    let mut families = Vec::new();
    let mut failed_demos = Vec::new();
    for family in Family::ALL {
        let (mut agent, mut wrist, mut prepare) = (Vec::new(), Vec::new(), Vec::new());
        let mut slowest = (0.0, String::new());
        for v in variants::of_family(family) {
            for (task, s) in &scenes {
                let Ok(spec) = instance(&format!("{task}/{family}/{}", v.name)) else { continue };
                let goals = &task_of(spec)?.goal;
                let started = Instant::now();
                let mut cue = EpisodeCue::prepare(&s.sim, &s.view, &mut renderer, spec, goals, (SIZE, SIZE))?;
                prepare.push(started.elapsed().as_secs_f64() * 1e3);
                if cue.demo().is_some_and(|d| !d.success) {
                    failed_demos.push(spec.id());
                }
                let a = time_apply(&mut cue, &s.sim, &mut renderer, std::slice::from_ref(&s.agent.0), &s.agent.1, batches)?;
                let w = time_apply(&mut cue, &s.sim, &mut renderer, &s.wrist.0, &s.wrist.1, batches)?;
                if a.max(w) > slowest.0 {
                    slowest = (a.max(w), v.name.to_string());
                }
                agent.push(a);
                wrist.push(w);
            }
        }
        let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len().max(1) as f64;
        let max = |x: &[f64]| x.iter().copied().fold(0.0, f64::max);
        families.push(FamilyCost {
            family,
            instances: agent.len(),
            ms_agentview_mean: mean(&agent),
            ms_agentview_max: max(&agent),
            ms_wrist_mean: mean(&wrist),
            ms_wrist_max: max(&wrist),
            slowest: slowest.1,
            ms_prepare_mean: mean(&prepare),
            ms_budget: budget_ms(family),
            within_budget: max(&agent).max(max(&wrist)) <= budget_ms(family),
        });
    }
    // A family with nothing timed would read as within its budget.
    let untimed: Vec<String> = families.iter().filter(|f| f.instances == 0).map(|f| f.family.to_string()).collect();
    anyhow::ensure!(
        untimed.is_empty(),
        "tasks {} have no cue instance of {} in the library (the PiPER scene's cue is a note on its table): choose tasks of LIBERO's suites",
        tasks.join(", "),
        untimed.join(", ")
    );
    Ok(CueBench {
        size: SIZE,
        clock: if Clock::cpu_ns().is_some() { "thread CPU time" } else { "wall-clock time" },
        batches,
        tasks: tasks.to_vec(),
        families,
        failed_demos,
    })
}
