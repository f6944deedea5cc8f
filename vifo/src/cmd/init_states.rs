//! `vifo init-states generate|check`: regenerate the shipped initial states, or judge them.
//!
//! `generate` draws every (task, state) with its own seed ([`init_states::seed`]) on a pool of
//! threads; results are put back in order, so the files are the same for any thread count.
//! `check` loads every shipped state, runs LIBERO's 10 wait steps and reports problems and how far
//! objects moved; `--drift` adds the stability gate (200 zero-action steps, ≤ 1 mm).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args as ClapArgs, Subcommand};
use vifo_scenes::init_states::{self, Check, DRIFT_STEPS, MAX_DRIFT, SuiteStates, TaskStates};
use vifo_scenes::sim::SceneModel;
use vifo_scenes::{Suite, Task};

#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Draw, settle and validate the states and write `<out>/<suite>.json`.
    Generate {
        /// One suite (default: all four).
        #[arg(long)]
        suite: Option<String>,
        /// Output folder (default: the repository's `scenes/init_states`, for the shipped 50
        /// states only).
        #[arg(short = 'o', long, visible_alias = "output")]
        out: Option<PathBuf>,
        /// States per task.
        #[arg(long, default_value_t = 50, value_parser = super::state_count)]
        states: usize,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Load every shipped state, settle it and report problems and motion per task.
    Check {
        /// One suite (default: all four).
        #[arg(long)]
        suite: Option<String>,
        /// Also run 200 zero-action steps and report the largest drift per task.
        #[arg(long)]
        drift: bool,
        /// Read `<DIR>/<suite>.json` instead of the states built into this program (e.g. files
        /// `generate` just wrote).
        #[arg(long)]
        from: Option<PathBuf>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
    },
}

pub fn run(args: Args) -> Result<()> {
    match args.command {
        Command::Generate { suite, out, states, threads } => {
            let out = match out {
                Some(out) => out,
                None => shipped_folder(states)?,
            };
            // Fail before the minutes of work, not after.
            vifo_protocols::runner::create_folder(&out)?;
            for suite in selected(suite.as_deref())? {
                let started = Instant::now();
                let stored = generate(suite, states, workers(threads))?;
                let path = out.join(format!("{}.json", suite.name));
                std::fs::write(&path, init_states::write(&stored)).with_context(|| path.display().to_string())?;
                println!("{}: {} tasks × {states} states in {:.0} s -> {}", suite.name, stored.tasks.len(), started.elapsed().as_secs_f64(), path.display());
            }
            Ok(())
        }
        Command::Check { suite, drift, from, threads } => {
            let mut failed = 0;
            for suite in selected(suite.as_deref())? {
                let (stored, source) = match &from {
                    Some(dir) => {
                        let path = dir.join(format!("{}.json", suite.name));
                        let text = std::fs::read_to_string(&path).with_context(|| path.display().to_string())?;
                        (init_states::parse(&text, &path.display().to_string())?, path.display().to_string())
                    }
                    None => (init_states::shipped_suite(&suite.name)?.clone(), "the states built into vifo".to_string()),
                };
                failed += check_suite(suite, &stored, drift, workers(threads)).with_context(|| source)?;
            }
            if failed > 0 {
                bail!("{failed} states have problems");
            }
            Ok(())
        }
    }
}

/// The repository's `scenes/init_states`, the default of `generate`: only in the source checkout
/// this program was built from, and only for the shipped count of states, so that a trial run
/// (`--states 5`) cannot overwrite the shipped files.
fn shipped_folder(states: usize) -> Result<PathBuf> {
    let folder = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../scenes/init_states");
    anyhow::ensure!(folder.is_dir(), "{}: no source checkout here to regenerate; give --out FOLDER", folder.display());
    let shipped = vifo_protocols::benchmark::specs::INIT_STATES;
    anyhow::ensure!(
        states == shipped,
        "--states {states}: the shipped files hold {shipped} states per task; write other counts elsewhere with --out FOLDER"
    );
    Ok(folder)
}

fn selected(name: Option<&str>) -> Result<Vec<&'static Suite>> {
    match name {
        None => Ok(vifo_scenes::suites().iter().collect()),
        Some(n) => Ok(vec![vifo_scenes::suite(n).ok_or_else(|| anyhow!("unknown suite {n} (known: {})", vifo_scenes::suite_names().join(", ")))?]),
    }
}

fn workers(threads: Option<usize>) -> usize {
    threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())).max(1)
}

/// Runs `job(i)` for `0..count` on `threads` threads; results in index order.
fn parallel<T: Send>(count: usize, threads: usize, job: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<T>>> = Mutex::new((0..count).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads.min(count) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= count {
                        break;
                    }
                    let r = job(i);
                    results.lock().expect("no worker panics while holding the lock")[i] = Some(r);
                }
            });
        }
    });
    results.into_inner().expect("workers finished").into_iter().map(|r| r.expect("every index ran")).collect()
}

fn models(suite: &Suite) -> Result<Vec<Arc<SceneModel>>> {
    suite.tasks.iter().map(|t| SceneModel::build(t).map_err(Into::into)).collect()
}

fn generate(suite: &Suite, states: usize, threads: usize) -> Result<SuiteStates> {
    let models = models(suite)?;
    let times: Mutex<Vec<f64>> = Mutex::new(vec![0.0; suite.tasks.len()]);
    let starts = parallel(suite.tasks.len() * states, threads, |job| {
        let (task, k) = (job / states, job % states);
        let t0 = Instant::now();
        let r = init_states::sample(&models[task], init_states::seed(&suite.name, task, k));
        times.lock().expect("no panics")[task] += t0.elapsed().as_secs_f64();
        r
    });
    let times = times.into_inner().expect("no panics");
    let mut starts = starts.into_iter();
    let mut tasks = Vec::new();
    for (index, task) in suite.tasks.iter().enumerate() {
        let mine: Vec<_> = starts.by_ref().take(states).collect::<Result<_, _>>()?;
        println!("  {}/{index} {:<60} {:.1} s", suite.name, short(task), times[index]);
        tasks.push(TaskStates { index, name: task.name.clone(), starts: mine });
    }
    Ok(SuiteStates { suite: suite.name.clone(), tasks })
}

fn short(task: &Task) -> String {
    task.name.chars().take(60).collect()
}

/// Prints one line per task; returns how many states have problems.
fn check_suite(suite: &Suite, stored: &SuiteStates, drift: bool, threads: usize) -> Result<usize> {
    let models = models(suite)?;
    let starts: Vec<&[init_states::EpisodeStart]> = suite.tasks.iter().map(|t| init_states::starts_for(stored, t)).collect::<Result<_, _>>()?;
    let jobs: Vec<(usize, usize)> = starts.iter().enumerate().flat_map(|(t, s)| (0..s.len()).map(move |k| (t, k))).collect();
    let checks = parallel(jobs.len(), threads, |j| {
        let (t, k) = jobs[j];
        init_states::check(&models[t], &starts[t][k], drift)
    });
    let mut per_task: Vec<Vec<Check>> = vec![Vec::new(); suite.tasks.len()];
    for (&(t, k), check) in jobs.iter().zip(checks) {
        per_task[t].push(check.with_context(|| format!("{} state {k}", suite.tasks[t].label()))?);
    }
    let mut failed = 0;
    let mut worst_drift: Option<(f64, String)> = None;
    for (index, (task, mine)) in suite.tasks.iter().zip(&per_task).enumerate() {
        let bad: Vec<String> = mine.iter().enumerate().filter(|(_, c)| !c.ok()).map(|(k, c)| format!("state {k}: {}", c.problems.join("; "))).collect();
        failed += bad.len();
        let shift = mine.iter().map(|c| c.settle_shift).fold(0.0, f64::max);
        let mut line = format!("{}/{index} {:<60} {} states, max settle shift {:.3} µm", suite.name, short(task), mine.len(), shift * 1e6);
        let largest = mine.iter().enumerate().filter_map(|(k, c)| c.drift.as_ref().map(|(d, who)| (*d, who, k))).max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((d, who, k)) = largest {
            line += &format!(", max drift over {DRIFT_STEPS} steps {:.3} µm ({who}, state {k})", d * 1e6);
            if worst_drift.as_ref().is_none_or(|w| d > w.0) {
                worst_drift = Some((d, format!("{}/{index} {who} state {k}", suite.name)));
            }
        }
        println!("{line}{}", if bad.is_empty() { String::new() } else { format!(", {} bad", bad.len()) });
        for b in bad {
            println!("    {b}");
        }
    }
    if let Some((d, at)) = worst_drift {
        let verdict = if d <= MAX_DRIFT { "within" } else { "OVER" };
        println!("{}: largest drift {:.3} µm ({at}), {verdict} the {:.0} µm gate", suite.name, d * 1e6, MAX_DRIFT * 1e6);
    }
    Ok(failed)
}
