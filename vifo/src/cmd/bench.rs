//! `vifo bench physics|render|replay|scaling|cues`: speed figures.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Subcommand};
use vifo::bench;
use vifo::look::LookArgs;
use vifo::start::InitSource;

#[derive(Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
    /// Print JSON instead of a table.
    #[arg(long, global = true)]
    pub json: bool,
}

#[derive(Subcommand)]
pub enum BenchWhat {
    /// Control steps per second (20 Hz steps of 25 physics substeps), one thread.
    Physics {
        /// Control steps to time per configuration.
        #[arg(long, default_value_t = 400, value_parser = super::at_least_one)]
        steps: usize,
    },
    /// Camera frames per second on the full libero_spatial scene through one expert episode (256², one thread).
    Render {
        /// LIBERO's init_files folder, to render LIBERO's initial state 0 of libero_spatial task 0
        /// instead of the shipped one.
        #[arg(long, value_name = "DIR")]
        libero_init: Option<PathBuf>,
        /// Timed passes over the expert's episode (the median is reported).
        #[arg(long, default_value_t = 5, value_parser = super::at_least_one)]
        passes: usize,
        #[command(flatten)]
        look: LookArgs,
    },
    /// Control steps per second replaying recorded LIBERO episodes (`*_init0.json`, as for
    /// `vifo xval`) in the full scene, without cameras and with both 256² cameras, one thread.
    Replay {
        /// Directory of recordings, e.g. ../shared/xval/libero_reference.
        dir: PathBuf,
        /// Timed episodes per recording and configuration (the median is reported).
        #[arg(long, default_value_t = 5, value_parser = super::at_least_one)]
        repeats: usize,
        #[command(flatten)]
        look: LookArgs,
    },
    /// Episodes per second of the runner at 1, 2, … N worker threads on one fixed sample of
    /// the whole benchmark (built-in expert-cue policy), and the memory per worker.
    Scaling {
        /// Largest thread count (default: every core); each count from 1 up is timed.
        #[arg(long, conflicts_with = "threads", value_parser = super::thread_count)]
        max_threads: Option<usize>,
        /// Only these thread counts, e.g. `1,2,4,8,16` (one thread among them: the speedup is
        /// against it), for a many-core machine where timing every count takes too long.
        #[arg(long, value_delimiter = ',', value_parser = super::thread_count)]
        threads: Vec<usize>,
        /// Episodes in the sample (the same ones for every thread count; at least one per
        /// protocol, so a count below four rounds up).
        #[arg(long, default_value_t = 24, value_parser = super::at_least_one)]
        episodes: usize,
        /// Skip the cameras (the expert reads the simulator; by default both 256² cameras are
        /// rendered after every step, as for an image policy).
        #[arg(long)]
        no_render: bool,
        /// Folder for the throwaway results files.
        #[arg(long, default_value = "vifo-bench-scaling")]
        scratch: PathBuf,
        /// Time every count this many times, alternating, each speedup against its own round's
        /// one-thread run, and print the median over rounds (for a machine whose speed drifts).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100))]
        rounds: u64,
    },
    /// Cost of drawing a cue instance into a 256² frame, per family, on real frames.
    Cues {
        /// Tasks (<suite>/<index>) whose instances are timed; repeatable.
        #[arg(long = "task", default_values_t = bench::cues::TASKS.map(String::from))]
        tasks: Vec<String>,
        /// Timed batches of about 40 ms per instance and camera (the median is reported).
        #[arg(long, default_value_t = 3, value_parser = super::at_least_one)]
        batches: usize,
    },
}

pub fn run(args: &BenchArgs) -> Result<()> {
    match &args.what {
        BenchWhat::Physics { steps } => {
            let results = bench::physics::run(*steps);
            if args.json {
                println!("{}", serde_json::to_string_pretty(&results)?);
            } else {
                println!("{:<30} {:>14} {:>16}", "scene", "steps/s", "ms/control step");
                for r in &results {
                    println!("{:<30} {:>14.1} {:>16.3}", r.scene, r.control_steps_per_second, r.ms_per_control_step);
                }
            }
        }
        BenchWhat::Render { libero_init, passes, look } => {
            let source = InitSource::from_libero_dir(libero_init.clone());
            let r = bench::render::run(source, *passes, look.look()?)?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                let outcome = if r.episode_success { "succeeded" } else { "cut" };
                println!("{} at {}², {}: the expert's episode ({} steps, {outcome}), median of {} passes", r.task, r.size, r.clock, r.episode_steps, r.passes);
                println!("triangles: {} in the scene, {} in agentview, {} in robot0_eye_in_hand", r.triangles, r.triangles_in_view_agentview, r.triangles_in_view_eye_in_hand);
                for (camera, c) in [("agentview", &r.culling_agentview), ("robot0_eye_in_hand", &r.culling_eye_in_hand)] {
                    println!(
                        "{camera}, per frame: {:.1} of {:.1} instances from the static layer; {:.0} clusters outside or facing away, {:.0} clusters or instances hidden; {:.0} triangles rasterized ({:.0} of them hidden), {:.0} vertices lit",
                        c.instances_reused, c.instances_drawn, c.clusters_culled, c.hidden, c.triangles_rasterized, c.triangles_hidden, c.vertices_lit
                    );
                }
                println!("agentview frame            {:>8.4} ms  ({:.0} fps)", r.ms_per_frame_agentview_256, r.fps_agentview_256);
                println!("robot0_eye_in_hand frame   {:>8.4} ms", r.ms_per_frame_eye_in_hand_256);
                println!("scene update               {:>8.4} ms", r.ms_per_update);
                println!("control step, 2 cameras    {:>8.4} ms  ({:.0} steps/s)", r.ms_per_step_two_cameras_256, r.steps_per_second_two_cameras_256);
                println!("  the same, drawn whole    {:>8.4} ms  (static layer off)", r.ms_per_step_two_cameras_256_whole);
                println!("look                       {}", r.look);
                println!("machine                    {}; code for {}", r.cpu.as_deref().unwrap_or("CPU not reported"), r.code_for);
                match r.peak_rss_mb_all_40_tasks {
                    Some(mb) => println!("peak memory, all 40 tasks' scenes built: {mb:.0} MB"),
                    None => println!("peak memory: not reported by this system"),
                }
                if r.gates.is_empty() {
                    let (ms, gb) = (bench::render::GATE_MS_PER_STEP, bench::render::GATE_PEAK_MB / 1024.0);
                    println!("(no gate applies: the {ms} ms and {gb} GB gates are for LIBERO's look; install its assets or give --assets DIR)");
                }
                for g in &r.gates {
                    let measured = g.measured.map_or("not reported".to_string(), |m| format!("{m:.2} {}", g.unit));
                    println!("gate: {} <= {} {}: {} ({measured})", g.what, g.limit, g.unit, if g.met { "met" } else { "MISSED" });
                }
            }
        }
        BenchWhat::Replay { dir, repeats, look } => {
            let results = bench::replay::run(dir, *repeats, look.look()?)?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&results)?);
            } else {
                println!("{:<34} {:>6} {:>16} {:>20}", "recording", "steps", "physics steps/s", "2 cameras steps/s");
                for r in &results {
                    println!("{:<34} {:>6} {:>16.1} {:>20.1}", r.file, r.control_steps, r.steps_per_second_physics, r.steps_per_second_two_cameras_256);
                }
                if let Some(r) = results.first() {
                    println!("(wall clock, median of {} episodes each; 256² cameras rendered after every step, look {})", r.repeats, r.look);
                }
            }
        }
        BenchWhat::Scaling { max_threads, threads, episodes, no_render, scratch, rounds } => {
            let threads = if threads.is_empty() {
                let cores = std::thread::available_parallelism().map_or(1, usize::from);
                (1..=max_threads.unwrap_or(cores).max(1)).collect()
            } else {
                let mut counts = threads.clone();
                counts.sort_unstable();
                counts.dedup();
                anyhow::ensure!(counts.first() == Some(&1), "--threads {}: name 1 among the counts (the speedup is against one thread)", list(threads));
                counts
            };
            let rounds = *rounds as usize;
            let progress = |row: &bench::scaling::ScalingRow| {
                let round = if rounds > 1 { format!("round {}/{rounds}, ", row.round + 1) } else { String::new() };
                eprintln!(
                    "{round}{} threads: {:.1} s, {:.3} episodes/s, {:.2}x (machine ceiling {:.2}x)",
                    row.threads, row.seconds, row.episodes_per_second, row.speedup, row.ceiling
                )
            };
            let r = bench::scaling::run(&threads, *episodes, !no_render, rounds, scratch, progress)?;
            let _ = std::fs::remove_dir(scratch);
            if args.json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!(
                    "{} on {} episodes of the whole benchmark, {}, {} cores (wall clock)",
                    r.policy,
                    r.rows.first().map_or(0, |row| row.episodes),
                    if r.rendered { "both 256² cameras rendered" } else { "no cameras" },
                    r.cores
                );
                println!(
                    "{:>5} {:>7} {:>10} {:>12} {:>9} {:>7} {:>14} {:>9} {:>9} {:>14} {:>12}",
                    "round", "threads", "seconds", "episodes/s", "speedup", "busy", "ms per episode", "slowdown", "ceiling", "MB per worker", "load before"
                );
                let opt = |v: Option<f64>, digits: usize| v.map_or_else(|| "-".into(), |v| format!("{v:.digits$}"));
                for row in &r.rows {
                    println!(
                        "{:>5} {:>7} {:>10.1} {:>12.3} {:>8.2}x {:>6.1}% {:>14.0} {:>8.3}x {:>8.2}x {:>14} {:>12}",
                        row.round + 1,
                        row.threads,
                        row.seconds,
                        row.episodes_per_second,
                        row.speedup,
                        100.0 * row.busy,
                        row.ms_per_episode,
                        row.slowdown,
                        row.ceiling,
                        opt(row.mb_per_worker, 0),
                        opt(row.load_before, 2)
                    );
                }
                println!("(speedup = threads × busy / slowdown, against the one-thread row of the same round: busy below 100 % is workers waiting for the last episodes, slowdown above 1 is each episode running slower beside the others; ceiling: the machine's own speedup, that many copies of a loop that touches only registers against one alone)");
                if r.rounds > 1 {
                    let medians: Vec<String> =
                        r.median.iter().skip(1).map(|m| format!("{} threads {:.2}x ({:.2}–{:.2}x)", m.threads, m.speedup, m.min, m.max)).collect();
                    println!("median speedup over {} rounds (least–greatest): {}", r.rounds, medians.join(", "));
                }
            }
        }
        BenchWhat::Cues { tasks, batches } => {
            let r = bench::cues::run(tasks, *batches)?;
            if args.json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!("cue insertion at {}², {}, median of {} batches; tasks {}", r.size, r.clock, r.batches, r.tasks.join(", "));
                println!("(ms per frame: anchors + ghost layers + drawing + compositing, not the scene render; F3 wrist renders its layers every frame)");
                println!("{:<28} {:>9} {:>16} {:>16} {:>12} {:>13}  slowest", "family", "instances", "agentview mean/max", "wrist mean/max", "prepare ms", "budget");
                for f in &r.families {
                    let budget = format!("{} {}", f.ms_budget, if f.within_budget { "met" } else { "OVER" });
                    println!(
                        "{} {:<25} {:>9} {:>8.3} / {:<7.3} {:>7.3} / {:<7.3} {:>12.1} {:>13}  {}",
                        f.family, f.family.name(), f.instances, f.ms_agentview_mean, f.ms_agentview_max, f.ms_wrist_mean, f.ms_wrist_max, f.ms_prepare_mean, budget, f.slowest
                    );
                }
                println!("(budget: ms per insertion for the slowest instance on either camera)");
                for id in &r.failed_demos {
                    println!("note: {id}: the expert's demonstration failed (timed all the same)");
                }
            }
        }
    }
    Ok(())
}

/// Thread counts as the command line gave them (`1,2,4`).
fn list(counts: &[usize]) -> String {
    counts.iter().map(ToString::to_string).collect::<Vec<_>>().join(",")
}
