//! Closed-loop runs against the misbehaving server ([`crate::fault_server`]): what the fault
//! test and `examples/policy_faults.rs` measure.
//!
//! One trial set: the faults given, each `trials` times, are injected in order by one server at
//! the second request of a connection (at the handshake for a bad handshake). As many episodes
//! of libero_spatial's task 0 (original protocol) plus one run in a row with one worker, so each
//! episode but the last is hit by one fault, in order, and the last runs clean. Then the run is
//! resumed against the same server (its faults spent): the retry policy is that error records
//! are run again on resume, while the client opens a fresh connection at the next episode after
//! any failure.

use std::path::Path;

use vifo_protocols::benchmark::specs::spec;
use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::remote::{RemoteConfig, RemotePolicy};
use vifo_protocols::runner::{RunOptions, final_records, read_records};
use vifo_protocols::spec::{Outcome, Protocol, TaskRef};
use vifo_protocols::{EpisodeSpec, Policy};
use vifo_scenes::view::CameraName;

use crate::fault_server::{CLIENT_TIMEOUT, Fault, FaultServer};

/// What the runs of one fault gave.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub episodes: usize,
    /// Faults the server injected.
    pub fired: usize,
    /// Error records whose message names the fault that hit the episode.
    pub errors_named: usize,
    /// Error records that do not name it (or name something else).
    pub errors_unnamed: usize,
    /// Faults injected without an error record for them: episodes scored as success or
    /// failure although the fault hit them.
    pub wrongly_scored: usize,
    /// Episodes that panicked (a crash caught by the runner) or runs that stopped with an error.
    pub crashes: usize,
    /// Episodes without a completed record after the resume.
    pub lost: usize,
    /// Records of the first run missing from the file after the resume.
    pub overwritten: usize,
    /// `fault: message` of each error that does not name its fault.
    pub unnamed: Vec<String>,
}

fn specs(n: usize) -> Vec<EpisodeSpec> {
    let task = TaskRef { suite: "libero_spatial".into(), index: 0 };
    (0..n).map(|i| spec(&task, Protocol::Original, None, i % 50, i / 50).expect("libero_spatial/0 specs")).collect()
}

/// Runs `trials` rounds of `faults` with results in `dir`.
pub fn run_faults(faults: &[Fault], trials: usize, dir: &Path) -> Result<Counts, String> {
    let schedule: Vec<Fault> = (0..trials).flat_map(|_| faults.iter().copied()).collect();
    let server = FaultServer::start(schedule.clone(), 2).map_err(|e| format!("starting the server: {e}"))?;
    let all = specs(schedule.len() + 1);
    let path = dir.join("results-faulty.jsonl");
    let config = EnvConfig { size: 32, cameras: CameraName::ALL.to_vec(), ..EnvConfig::default() };
    let url = server.url();
    let make = || -> Result<Box<dyn Policy>, String> {
        let mut c = RemoteConfig::new(&url);
        c.request_timeout = CLIENT_TIMEOUT;
        c.connect_timeout = CLIENT_TIMEOUT;
        c.image_size = 32;
        c.name = Some("faulty".into());
        RemotePolicy::with_config(c).map(|p| Box::new(p) as Box<dyn Policy>).map_err(|e| e.to_string())
    };
    let options = RunOptions { threads: 1, quiet: true, policy: "faulty".into(), ..RunOptions::new(&path) };
    let rollout = RolloutOptions::default();
    let mut counts = Counts { episodes: all.len(), ..Counts::default() };
    if run_episodes(&all, make, config.clone(), &rollout, &options).is_err() {
        counts.crashes += 1;
    }
    counts.fired = server.fired();
    let first = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let records = read_records(&path).map_err(|e| e.to_string())?.records;
    // One worker runs the episodes in order, so the n-th error met the n-th fault.
    let mut hit = schedule.iter();
    for r in &records {
        if let Outcome::Error { message } = &r.outcome {
            let fault = hit.next();
            if message.contains("panicked") {
                counts.crashes += 1;
            } else if fault.is_some_and(|f| f.named_by().iter().any(|w| message.contains(w))) {
                counts.errors_named += 1;
            } else {
                counts.errors_unnamed += 1;
                counts.unnamed.push(format!("{}: {message}", fault.map_or("no fault", |f| f.name())));
            }
        }
    }
    counts.wrongly_scored = counts.fired.saturating_sub(counts.errors_named + counts.errors_unnamed);

    let resumed = RunOptions { resume: true, ..options };
    if run_episodes(&all, make, config, &rollout, &resumed).is_err() {
        counts.crashes += 1;
    }
    let after = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let first_lines = first.split(|&b| b == b'\n').filter(|l| !l.is_empty()).count();
    counts.overwritten = if after.starts_with(&first) { 0 } else { first_lines };
    let finals = final_records(read_records(&path).map_err(|e| e.to_string())?.records);
    counts.lost = all
        .iter()
        .filter(|s| !finals.get(&s.key()).is_some_and(|r| matches!(r.outcome, Outcome::Completed { .. })))
        .count();
    Ok(counts)
}
