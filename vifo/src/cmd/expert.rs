//! `vifo expert`: run the scripted expert and print success rates.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use rayon::prelude::*;
use clap::Args;
use vifo::expert::{self, InitSource};
use vifo_scenes::sim::SceneModel;

#[derive(Args)]
pub struct ExpertArgs {
    /// Suite name or `all`.
    #[arg(long, default_value = "all")]
    pub suite: String,
    /// Only this task index of the suite.
    #[arg(long)]
    pub task: Option<usize>,
    /// Episodes (initial states) per task.
    #[arg(long, default_value_t = 20)]
    pub episodes: usize,
    /// First initial state.
    #[arg(long, default_value_t = 0)]
    pub first: usize,
    /// Read LIBERO's own initial states from this `init_files` directory.
    #[arg(long)]
    pub libero_init: Option<PathBuf>,
    /// Print a trace of every step (for debugging the expert).
    #[arg(long)]
    pub trace: bool,
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &ExpertArgs) -> Result<()> {
    let source = InitSource::Libero(args.libero_init.clone().ok_or_else(|| anyhow!("--libero-init DIR is required for now"))?);
    let suites: Vec<&vifo_scenes::Suite> = vifo_scenes::suites().iter().filter(|s| args.suite == "all" || s.name == args.suite).collect();
    if suites.is_empty() {
        return Err(anyhow!("unknown suite {}", args.suite));
    }
    for suite in suites {
        for (index, task) in suite.tasks.iter().enumerate() {
            if args.task.is_some_and(|t| t != index) {
                continue;
            }
            let model = SceneModel::build(task)?;
            let states = expert::init_states(task, &model, &source)?;
            let range: Vec<usize> = (args.first..(args.first + args.episodes).min(states.len())).collect();
            let results = range
                .par_iter()
                .map(|&k| expert::episode(&model, &states[k], k, k as u64, suite.max_steps as usize, args.trace))
                .collect::<Result<Vec<_>>>()?;
            let ok = results.iter().filter(|r| r.success).count();
            let mean = results.iter().map(|r| r.steps as f64).sum::<f64>() / results.len().max(1) as f64;
            let failures: Vec<String> = results.iter().filter(|r| !r.success).map(|r| format!("{}:{}", r.init, r.failure.as_deref().unwrap_or("budget"))).collect();
            println!("{}/{index} {:<70} {ok}/{} mean steps {mean:.0} budget {} {}", suite.name, task.name, results.len(), suite.max_steps, failures.join(", "));
        }
    }
    Ok(())
}
