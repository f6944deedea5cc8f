//! `vifo bench scaling`: episodes per second of `vifo run`'s runner at 1, 2, … N worker
//! threads on the same fixed sample of the whole benchmark, and the memory each worker adds.
//!
//! Wall-clock time is the measure here (threads share the machine on purpose), so the figures
//! are only as good as the machine is quiet: the load average before each run is printed. A
//! machine's per-core speed also drifts (on a 16-core VM the one-thread time moved by 11 % in
//! five minutes), so the counts can be timed in several rounds, each speedup taken against the
//! one-thread run of its own round, and the median over rounds reported beside every round.

use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use vifo_protocols::benchmark::specs::{self, Selection};
use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::policies::builtin;
use vifo_protocols::runner::{RunOptions, read_records};
use vifo_scenes::view::CameraName;

use super::memory;

/// The built-in policy every worker runs (the whole expert-cue pass is the gate's workload).
pub const POLICY: &str = "expert-cue";

/// One thread count in one round.
#[derive(Debug, Serialize)]
pub struct ScalingRow {
    /// The round (from 0) this row was timed in.
    pub round: usize,
    pub threads: usize,
    pub episodes: usize,
    pub seconds: f64,
    pub episodes_per_second: f64,
    /// Episodes/s over the same round's one-thread figure. It is `threads × busy / slowdown`
    /// against the one-thread row's `busy / slowdown`, which says where a shortfall comes from.
    pub speedup: f64,
    /// The workers' busy share of the run: summed episode times (each record's `wall_ms`) over
    /// `threads × seconds`. Below 1 where workers waited for the last episodes.
    pub busy: f64,
    /// Mean time of one episode (its record's `wall_ms`).
    pub ms_per_episode: f64,
    /// `ms_per_episode` over the one-thread row's: how much slower each episode ran beside the
    /// others (shared caches, memory, the clock of a fully loaded CPU).
    pub slowdown: f64,
    /// Wall time of `threads` copies of `spin` (a register-only loop) run together just before the episodes.
    pub spin_seconds: f64,
    /// The machine's own speedup at this count: `threads` × the one-thread row's `spin_seconds`
    /// over this row's. `spin` touches nothing but registers, so it is below `threads` only
    /// where the CPU runs each core slower with more of them busy (a lower all-core clock,
    /// cores that share hardware under a VM); `speedup / ceiling` is what the runner keeps.
    pub ceiling: f64,
    /// Peak resident memory added during the run, per worker thread (MB; Linux only).
    pub mb_per_worker: Option<f64>,
    /// One-minute load average when the run started (Linux only).
    pub load_before: Option<f64>,
}

#[derive(Debug, Serialize)]
pub struct Scaling {
    pub policy: &'static str,
    /// Whether both 256² cameras were rendered after every step.
    pub rendered: bool,
    pub cores: usize,
    pub rounds: usize,
    pub rows: Vec<ScalingRow>,
    /// Each thread count's speedup over the rounds.
    pub median: Vec<MedianSpeedup>,
}

/// One thread count's speedups over all rounds.
#[derive(Debug, Serialize, PartialEq)]
pub struct MedianSpeedup {
    pub threads: usize,
    /// The median (the mean of the middle two for an even number of rounds).
    pub speedup: f64,
    pub min: f64,
    pub max: f64,
}

/// The median, least and greatest speedup of every thread count in `rows`, by thread count.
pub fn medians(rows: &[ScalingRow]) -> Vec<MedianSpeedup> {
    let mut counts: Vec<usize> = rows.iter().map(|r| r.threads).collect();
    counts.sort_unstable();
    counts.dedup();
    counts
        .into_iter()
        .map(|threads| {
            let mut s: Vec<f64> = rows.iter().filter(|r| r.threads == threads).map(|r| r.speedup).collect();
            s.sort_by(f64::total_cmp);
            let n = s.len();
            let speedup = if n % 2 == 1 { s[n / 2] } else { (s[n / 2 - 1] + s[n / 2]) / 2.0 };
            MedianSpeedup { threads, speedup, min: s[0], max: s[n - 1] }
        })
        .collect()
}

/// Runs `episodes` episodes of a fixed sample of the paper set's whole benchmark (every
/// protocol, in proportion) once per thread count in `threads` (the first is the one each
/// speedup is against), `rounds` times over, into throwaway results files under `scratch`. An
/// untimed warm-up pass first builds the scene models every run shares, so neither the first
/// timing nor the first memory figure carries them. `measured` sees each row as soon as it is
/// timed (a long bench cut short still leaves the rows it timed).
pub fn run(threads: &[usize], episodes: usize, rendered: bool, rounds: usize, scratch: &Path, mut measured: impl FnMut(&ScalingRow)) -> Result<Scaling> {
    let rounds = rounds.max(1);
    let all = specs::specs(&Selection::all(1))?;
    let sample = specs::sample(&all, episodes);
    let config = EnvConfig {
        size: 256,
        cameras: if rendered { CameraName::ALL.to_vec() } else { Vec::new() },
        ..EnvConfig::default()
    };
    // The expert reads the simulator; its frames are drawn as an image policy's would be.
    let rollout_options = RolloutOptions { draw_every_step: rendered, ..RolloutOptions::default() };
    let make = || builtin(POLICY).ok_or_else(|| format!("no built-in policy {POLICY}"));
    vifo_protocols::runner::create_folder(scratch)?;
    let warm_up = threads.iter().copied().max().unwrap_or(1);
    let mut rows: Vec<ScalingRow> = Vec::new();
    let timed = (0..rounds).flat_map(|round| threads.iter().map(move |&t| (t, Some(round))));
    for (t, round) in std::iter::once((warm_up, None)).chain(timed) {
        let output = scratch.join(format!("scaling-{t}-threads.jsonl"));
        let _ = std::fs::remove_file(&output);
        let options = RunOptions { threads: t, quiet: true, policy: POLICY.into(), ..RunOptions::new(&output) };
        let load_before = load_average();
        let spin_seconds = if round.is_some() { spin_seconds(t) } else { 0.0 };
        let base = memory::reset_peak().then(memory::rss_mb).flatten();
        let start = Instant::now();
        let summary = run_episodes(&sample, make, config.clone(), &rollout_options, &options)?;
        let seconds = start.elapsed().as_secs_f64();
        anyhow::ensure!(summary.errors == 0, "{} of {} episodes ended in errors (see {})", summary.errors, summary.ran, output.display());
        let mb_per_worker = base.zip(memory::peak_rss_mb()).map(|(b, p)| (p - b).max(0.0) / t as f64);
        let episode_ms: f64 = read_records(&output)?.records.iter().map(|r| r.wall_ms).sum();
        let _ = std::fs::remove_file(&output);
        let Some(round) = round else { continue };
        let timing = Timing { round, threads: t, episodes: summary.ran, seconds, episode_ms, spin_seconds };
        let one = rows.iter().find(|r| r.round == round);
        rows.push(timing.row(one, mb_per_worker, load_before));
        measured(rows.last().expect("pushed"));
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let median = medians(&rows);
    Ok(Scaling { policy: POLICY, rendered, cores, rounds, rows, median })
}

/// What one timed run measured: the run's wall time and its records' summed episode times.
struct Timing {
    round: usize,
    threads: usize,
    episodes: usize,
    seconds: f64,
    episode_ms: f64,
    spin_seconds: f64,
}

impl Timing {
    /// Its row, against the one-thread row `one` (`None`: this is that row).
    fn row(&self, one: Option<&ScalingRow>, mb_per_worker: Option<f64>, load_before: Option<f64>) -> ScalingRow {
        let episodes_per_second = self.episodes as f64 / self.seconds;
        let ms_per_episode = self.episode_ms / self.episodes.max(1) as f64;
        let (one_rate, one_ms, one_spin) =
            one.map_or((episodes_per_second, ms_per_episode, self.spin_seconds), |r| (r.episodes_per_second, r.ms_per_episode, r.spin_seconds));
        ScalingRow {
            round: self.round,
            threads: self.threads,
            episodes: self.episodes,
            seconds: self.seconds,
            episodes_per_second,
            speedup: episodes_per_second / one_rate,
            busy: self.episode_ms / 1e3 / (self.threads as f64 * self.seconds),
            ms_per_episode,
            slowdown: ms_per_episode / one_ms,
            spin_seconds: self.spin_seconds,
            ceiling: self.threads as f64 * one_spin / self.spin_seconds,
            mb_per_worker,
            load_before,
        }
    }
}

/// Rounds of [`spin`]'s loop per copy: about half a second on one core of the 2-core machine.
const SPIN_ROUNDS: u64 = 200_000_000;

/// A fixed amount of work that stays in registers (four xorshift streams, which the compiler
/// cannot shorten), so its time measures the core's speed and nothing the cores share.
fn spin(rounds: u64) -> u64 {
    let mut s = [0x9E37_79B9_7F4A_7C15_u64, 0xBF58_476D_1CE4_E5B9, 0x94D0_49BB_1331_11EB, 0x2545_F491_4F6C_DD1D];
    for _ in 0..std::hint::black_box(rounds) {
        for x in &mut s {
            *x ^= *x << 13;
            *x ^= *x >> 7;
            *x ^= *x << 17;
        }
    }
    s.iter().fold(0, |a, b| a ^ b)
}

/// Wall time of `threads` copies of [`spin`] started together.
fn spin_seconds(threads: usize) -> f64 {
    let start = Instant::now();
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| std::hint::black_box(spin(SPIN_ROUNDS)));
        }
    });
    start.elapsed().as_secs_f64()
}

/// The one-minute load average (Linux `/proc/loadavg`).
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_speedup_splits_into_busy_share_and_slowdown() {
        // One thread: 10 episodes of 100 ms in 1.0 s. Four threads: the same episodes at 120 ms
        // each, done in 0.4 s (the last worker finished alone).
        let one = Timing { round: 0, threads: 1, episodes: 10, seconds: 1.0, episode_ms: 1000.0, spin_seconds: 0.3 }.row(None, None, None);
        let four = Timing { round: 0, threads: 4, episodes: 10, seconds: 0.4, episode_ms: 1200.0, spin_seconds: 0.4 }.row(Some(&one), None, None);
        assert!((one.speedup - 1.0).abs() < 1e-12 && (one.busy - 1.0).abs() < 1e-12 && (one.slowdown - 1.0).abs() < 1e-12);
        assert!((four.speedup - 2.5).abs() < 1e-12, "{}", four.speedup);
        assert!((four.busy - 0.75).abs() < 1e-12, "{}", four.busy);
        assert!((four.slowdown - 1.2).abs() < 1e-12, "{}", four.slowdown);
        // Four copies of the register-only loop took 0.4 s against 0.3 s for one alone.
        assert!((four.ceiling - 3.0).abs() < 1e-12 && (one.ceiling - 1.0).abs() < 1e-12, "{} {}", four.ceiling, one.ceiling);
        let product = four.threads as f64 * four.busy / four.slowdown / (one.busy / one.slowdown);
        assert!((four.speedup - product).abs() < 1e-12, "{} vs {product}", four.speedup);
    }

    #[test]
    fn each_round_is_against_its_own_one_thread_run_and_the_median_spans_the_rounds() {
        // The machine ran 10 % slower in round 1, at one thread and at two alike.
        let rounds = [(1.0, 0.52), (1.1, 0.60), (1.0, 0.50)];
        let mut rows = Vec::new();
        for (round, (one_s, two_s)) in rounds.into_iter().enumerate() {
            let one = Timing { round, threads: 1, episodes: 10, seconds: one_s, episode_ms: one_s * 1e3, spin_seconds: one_s }.row(None, None, None);
            let two = Timing { round, threads: 2, episodes: 10, seconds: two_s, episode_ms: one_s * 1e3, spin_seconds: one_s }.row(Some(&one), None, None);
            rows.extend([one, two]);
        }
        let speedups: Vec<f64> = rows.iter().filter(|r| r.threads == 2).map(|r| r.speedup).collect();
        assert!((speedups[1] - 1.1 / 0.60).abs() < 1e-12, "{speedups:?}");
        let m = medians(&rows);
        assert_eq!(m.len(), 2);
        assert_eq!((m[0].threads, m[0].speedup, m[0].min, m[0].max), (1, 1.0, 1.0, 1.0));
        assert_eq!((m[1].threads, m[1].speedup, m[1].max), (2, 1.0 / 0.52, 1.0 / 0.50));
        assert!((m[1].min - 1.1 / 0.60).abs() < 1e-12, "{}", m[1].min);
        // An even number of rounds: the mean of the middle two.
        let even = medians(&rows[..4]);
        assert!((even[1].speedup - (1.0 / 0.52 + 1.1 / 0.60) / 2.0).abs() < 1e-12, "{}", even[1].speedup);
    }
}
