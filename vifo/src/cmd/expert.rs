//! `vifo expert`: run the scripted expert and print success rates.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::{Result, anyhow, ensure};
use clap::Args;
use rayon::prelude::*;
use serde::Serialize;
use vifo::expert::{self, ExpertEpisode};
use vifo::start::{InitSource, Starts};
use vifo_scenes::sim::{self, Extremes, SceneModel};

#[derive(Args)]
pub struct ExpertArgs {
    /// Suite name or `all` (the 40 LIBERO tasks); a study suite (`vifo_safety`, `vifo_piper`) by name.
    #[arg(long, default_value = "all")]
    pub suite: String,
    /// Only this task index of the suite.
    #[arg(long)]
    pub task: Option<usize>,
    /// Episodes (initial states) per task.
    #[arg(long, default_value_t = 20, value_parser = super::episode_count)]
    pub episodes: usize,
    /// First initial state.
    #[arg(long, default_value_t = 0)]
    pub first: usize,
    /// Start from LIBERO's own initial states in this init_files folder instead of the shipped ones.
    #[arg(long, value_name = "DIR")]
    pub libero_init: Option<PathBuf>,
    /// Print a trace of every fifth step to stderr (for debugging the expert).
    #[arg(long)]
    pub trace: bool,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Write the episode's actions (the settling steps first) to this JSON file, for the
    /// original stack to replay (`xval/record_complete.py --actions`); one task and one episode.
    #[arg(long, value_name = "FILE")]
    pub actions: Option<PathBuf>,
}

/// Where the initial states came from, as the outputs name it.
fn init_source(source: &InitSource) -> String {
    match source {
        InitSource::Shipped => "shipped".to_string(),
        InitSource::Libero(dir) => dir.display().to_string(),
    }
}

/// What `--actions` writes: one episode's actions from its initial state.
#[derive(Serialize)]
struct EpisodeActions<'a> {
    suite: &'a str,
    task_id: usize,
    task_name: &'a str,
    /// The initial state's index (LIBERO's own states with `--libero-init`).
    init: usize,
    init_source: String,
    success: bool,
    actions: &'a [[f64; 7]],
}

/// One task's line of the table (and of the JSON).
#[derive(Serialize)]
struct TaskResult {
    suite: String,
    index: usize,
    name: String,
    episodes: usize,
    success_rate: f64,
    mean_steps: f64,
    /// Each episode's control steps, in initial-state order (what a change meant to keep the
    /// expert's behaviour is checked against).
    steps: Vec<usize>,
    budget: u32,
    /// `init:why` of every failed episode.
    failures: Vec<String>,
    /// `init: step: what` of every episode in which an object went below the table or floor.
    below_support: Vec<String>,
    /// The largest speeds and penetration over the task's episodes.
    extremes: Extremes,
}

#[derive(Serialize)]
struct Summary {
    tasks: Vec<TaskResult>,
    episodes: usize,
    success_rate: f64,
    /// Tasks whose success rate is below 90 %.
    tasks_below_90: usize,
    /// Episodes in which an object went below the table top or floor.
    episodes_below_support: usize,
    /// The largest speeds and penetration over the pass (the physics guard's limits sit far
    /// above them).
    extremes: Extremes,
    init_source: String,
}

pub fn run(args: &ExpertArgs) -> Result<()> {
    let source = InitSource::from_libero_dir(args.libero_init.clone());
    // "all" is LIBERO's four suites; a study suite (vifo_safety, vifo_piper) is reached by its name.
    let suites: Vec<&vifo_scenes::Suite> = match args.suite.as_str() {
        "all" => vifo_scenes::suites().iter().collect(),
        name => vifo_scenes::suite(name).into_iter().collect(),
    };
    if suites.is_empty() {
        return Err(anyhow!("unknown suite {} (libero_spatial, libero_object, libero_goal, libero_10, all, or a study suite: vifo_safety, vifo_piper)", args.suite));
    }
    if let Some(t) = args.task {
        let most = suites.iter().map(|s| s.tasks.len()).max().unwrap_or(0);
        ensure!(t < most, "--task {t}: {} has tasks 0 to {}", args.suite, most.saturating_sub(1));
    }
    ensure!(args.episodes > 0, "--episodes 0: nothing to run");
    ensure!(
        args.actions.is_none() || (args.task.is_some() && args.episodes == 1 && suites.len() == 1),
        "--actions writes one episode: give one suite, --task and --episodes 1"
    );
    let mut tasks = Vec::new();
    // Printed with the first row, so that an error found on loading the first task stands alone.
    let mut header = !args.json;
    for suite in suites {
        for (index, task) in suite.tasks.iter().enumerate() {
            if args.task.is_some_and(|t| t != index) {
                continue;
            }
            let model = SceneModel::build(task)?;
            let starts = Starts::load(task, &model, &source)?;
            let range: Vec<usize> = (args.first..(args.first + args.episodes).min(starts.len())).collect();
            ensure!(!range.is_empty(), "--first {}: {}/{index} has initial states 0 to {}", args.first, suite.name, starts.len().saturating_sub(1));
            if range.len() < args.episodes {
                eprintln!(
                    "note: {}/{index} has initial states 0 to {}: {} episode{} from state {}, not {}",
                    suite.name,
                    starts.len() - 1,
                    range.len(),
                    if range.len() == 1 { "" } else { "s" },
                    args.first,
                    args.episodes
                );
            }
            let done = AtomicUsize::new(0);
            // The counter rewrites one line, which only a terminal shows as such.
            let live = std::io::stderr().is_terminal();
            let results = range
                .par_iter()
                .map(|&k| {
                    let r = expert::episode(&model, &starts, k, k as u64, suite.max_steps as usize, args.trace);
                    let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if live {
                        eprint!("\r{}/{index}: {n}/{} episodes", suite.name, range.len());
                    }
                    r
                })
                .collect::<Result<Vec<ExpertEpisode>>>()?;
            if live {
                eprint!("\r\x1b[K");
            }
            let ok = results.iter().filter(|r| r.success).count();
            if let (Some(path), [episode]) = (&args.actions, results.as_slice()) {
                let written = EpisodeActions {
                    suite: &suite.name,
                    task_id: index,
                    task_name: &task.name,
                    init: episode.init,
                    init_source: init_source(&source),
                    success: episode.success,
                    actions: &episode.actions,
                };
                std::fs::write(path, serde_json::to_string(&written)?).map_err(|e| anyhow!("cannot write {}: {e}", path.display()))?;
                eprintln!("{} actions written to {}", episode.actions.len(), path.display());
            }
            let result = TaskResult {
                suite: suite.name.to_string(),
                index,
                name: task.name.clone(),
                episodes: results.len(),
                success_rate: ok as f64 / results.len().max(1) as f64,
                mean_steps: results.iter().map(|r| r.steps as f64).sum::<f64>() / results.len().max(1) as f64,
                steps: results.iter().map(|r| r.steps).collect(),
                budget: suite.max_steps,
                failures: results.iter().filter(|r| !r.success).map(|r| format!("{}:{}", r.init, r.failure.as_deref().unwrap_or("budget"))).collect(),
                below_support: results.iter().filter_map(|r| Some(format!("{}: {}", r.init, r.below_support.as_ref()?))).collect(),
                extremes: results.iter().fold(Extremes::default(), |m, r| m.max(r.extremes)),
            };
            if std::mem::take(&mut header) {
                println!("{:<15} {:>2} {:<72} {:>7} {:>6} {:>6} {:>6}  failures (init:why)", "suite", "#", "task", "ok", "rate", "steps", "budget");
            }
            if !args.json {
                println!(
                    "{:<15} {:>2} {:<72} {:>3}/{:<3} {:>5.0}% {:>6.0} {:>6}  {}",
                    result.suite,
                    index,
                    result.name,
                    ok,
                    result.episodes,
                    result.success_rate * 100.0,
                    result.mean_steps,
                    result.budget,
                    result.failures.join(", ")
                );
            }
            tasks.push(result);
        }
    }
    let episodes: usize = tasks.iter().map(|t| t.episodes).sum();
    let successes: f64 = tasks.iter().map(|t| t.success_rate * t.episodes as f64).sum();
    let summary = Summary {
        episodes,
        success_rate: successes / episodes.max(1) as f64,
        tasks_below_90: tasks.iter().filter(|t| t.success_rate < 0.9).count(),
        episodes_below_support: tasks.iter().map(|t| t.below_support.len()).sum(),
        extremes: tasks.iter().fold(Extremes::default(), |m, t| m.max(t.extremes)),
        init_source: init_source(&source),
        tasks,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "{}, success {:.1}%, {} of {} tasks below 90%, {} with an object below the table or floor",
            super::episodes_text(summary.episodes),
            summary.success_rate * 100.0,
            summary.tasks_below_90,
            summary.tasks.len(),
            super::episodes_text(summary.episodes_below_support)
        );
        let e = summary.extremes;
        println!(
            "physics maxima: body speed {:.3} m/s, angular speed {:.2} rad/s, penetration {:.4} m, distance from origin {:.2} m \
             (guard limits {} m/s, {} rad/s, {} m, {} m)",
            e.linear_speed,
            e.angular_speed,
            e.penetration,
            e.distance,
            sim::MAX_LINEAR_SPEED,
            sim::MAX_ANGULAR_SPEED,
            sim::MAX_PENETRATION,
            sim::MAX_DISTANCE
        );
        for t in summary.tasks.iter().filter(|t| !t.below_support.is_empty()) {
            println!("  below support in {}/{}: {}", t.suite, t.index, t.below_support.join("; "));
        }
    }
    Ok(())
}
