//! Parallel, resumable, shardable episode runs.
//!
//! [`run`] executes one closure per [`EpisodeSpec`] on a rayon pool, the suites with the longest
//! step budget first (each worker takes the next episode when it is free), and appends each finished
//! [`EpisodeRecord`] to a JSONL file as soon as it finishes (see [`results`] for the crash
//! guarantees). With `resume`, specs whose key already has a completed record are skipped and
//! earlier errors run again. Sharding splits a spec list across machines by a stable hash of
//! the key, so `--shard 0/4 … 3/4` cover every spec exactly once whatever the list order.
//! Record contents never depend on the thread count; only the line order does.

mod progress;
pub mod results;
pub mod seed;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::{Arc, Mutex};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use thiserror::Error;

use vifo_cues::SetName;

pub(crate) use self::progress::Progress;
use crate::spec::{EpisodeRecord, EpisodeSpec, Outcome, RESULTS_VERSION};

pub use results::{Loaded, ResultsWriter, RunLock, create_dir, create_folder, final_records, parse_records, read_records};
pub use seed::{episode_seed, fnv1a64, seed_for, stable_hash};

/// Why a run could not proceed.
#[derive(Debug, Error)]
pub enum RunError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}:{line}: {message}")]
    BadLine { path: PathBuf, line: usize, message: String },
    #[error("{0} already holds results; continue it with `--resume` (`resume=True` from Python), or choose another output")]
    Exists(PathBuf),
    #[error("another run is writing {results} (it holds {lock}); wait for it to finish or choose another output")]
    Locked { results: PathBuf, lock: PathBuf },
    #[error(
        "{path} holds records of results version {found}, this benchmark writes version {expected}: \
         their episodes were run under other rules; keep that file and write to another output"
    )]
    OtherVersion { path: PathBuf, found: u32, expected: u32 },
    #[error("thread pool: {0}")]
    Pool(String),
    #[error("{path} holds episodes of the {found} instance set, this run is of the {wanted} set; resume it with that set or choose another file")]
    OtherSet { path: PathBuf, found: SetName, wanted: SetName },
    #[error("{path} holds completed episodes of the policy {found}, not of {wanted} (was the file renamed?): resuming would skip them as done; choose another output")]
    OtherPolicy { path: PathBuf, found: String, wanted: String },
}

impl RunError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> RunError {
        RunError::Io { path: path.to_path_buf(), source }
    }
}

/// One of `count` disjoint parts of a spec list: `"i/n"` with `0 <= i < n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: u64,
    pub count: u64,
}

impl Shard {
    /// Whether the episode with this key belongs to the shard.
    pub fn contains(&self, key: &str) -> bool {
        stable_hash(key) % self.count == self.index
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("shard {s:?}: expected i/n with 0 <= i < n, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u64 = i.trim().parse().map_err(|_| bad())?;
        let count: u64 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// How to run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The JSONL results file.
    pub output: PathBuf,
    /// Worker threads; 0 uses one per core.
    pub threads: usize,
    /// Continue an existing results file (otherwise a non-empty file is an error).
    pub resume: bool,
    pub shard: Option<Shard>,
    /// No progress bar.
    pub quiet: bool,
    /// The policy's name ([`Policy::name`](crate::policy::Policy::name)), written into records
    /// the runner makes itself (a panicking episode). A file resumed under a name must hold no
    /// completed episode of another policy (a renamed file would have its episodes skipped as
    /// done); empty checks nothing.
    pub policy: String,
    /// The instance set written into every record; resuming a file of another set is an error.
    pub set: SetName,
    /// Set from elsewhere (a Ctrl-C that Python saw) to stop taking episodes: those running
    /// finish and are written, the rest stay to do (`resume` continues them).
    pub stop: Option<Arc<AtomicBool>>,
}

impl RunOptions {
    pub fn new(output: impl Into<PathBuf>) -> RunOptions {
        RunOptions {
            output: output.into(),
            threads: 0,
            resume: false,
            shard: None,
            quiet: false,
            policy: String::new(),
            set: SetName::Paper,
            stop: None,
        }
    }

    fn stopped(&self) -> bool {
        self.stop.as_ref().is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

/// What a run did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunSummary {
    /// Distinct specs given (repeated keys count once).
    pub specs: usize,
    /// Of those, the ones in this shard.
    pub in_shard: usize,
    /// Skipped because a completed record was already in the file.
    pub already_done: usize,
    /// Episodes run now.
    pub ran: usize,
    /// Of those, the ones that ended in an error record.
    pub errors: usize,
    /// The distinct messages of those errors, most frequent first (ties in the messages'
    /// order): what a user must fix before `resume` retries them.
    pub error_messages: Vec<ErrorTally>,
    /// Bytes of a cut-off last line found (and removed) when resuming.
    pub truncated_tail: usize,
}

/// One distinct error message of a run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ErrorTally {
    /// Episodes that ended with it.
    pub count: usize,
    pub message: String,
    /// The first of those episodes' keys in key order (whatever the threads' order), so the
    /// console can name one episode to look at.
    pub first: String,
}

/// Runs every spec of `specs` (of this shard, not yet done) with `episode` and appends the
/// records to `options.output`. The runner measures `wall_ms` itself. An episode that panics
/// or returns a record for another spec is recorded as an error; an I/O error on the results
/// file stops the run (records written so far stay valid). A run holds the results file's
/// lock throughout, and resumes only a file of this [`RESULTS_VERSION`].
pub fn run<F>(specs: &[EpisodeSpec], episode: F, options: &RunOptions) -> Result<RunSummary, RunError>
where
    F: Fn(&EpisodeSpec) -> EpisodeRecord + Sync,
{
    let mut summary = RunSummary::default();
    let mut keys = BTreeSet::new();
    let unique: Vec<&EpisodeSpec> = specs.iter().filter(|s| keys.insert(s.key())).collect();
    summary.specs = unique.len();
    let in_shard: Vec<&EpisodeSpec> =
        unique.into_iter().filter(|s| options.shard.is_none_or(|sh| sh.contains(&s.key()))).collect();
    summary.in_shard = in_shard.len();

    let OpenResults { lock: _lock, writer, done, truncated_tail } = open_results(options)?;
    summary.truncated_tail = truncated_tail;
    let mut todo: Vec<&EpisodeSpec> = in_shard.into_iter().filter(|s| !done.contains(&s.key())).collect();
    summary.already_done = summary.in_shard - todo.len();
    // Longest step budget first, each worker taking the next episode when it is free: the long
    // episodes then run side by side early instead of ending the run on a few busy workers.
    todo.sort_by_key(|s| std::cmp::Reverse(s.step_budget()));

    let writer = Mutex::new(writer);
    let failure: Mutex<Option<RunError>> = Mutex::new(None);
    let progress = Progress::stderr(todo.len() as u64, "episodes", options.quiet);
    let errors: Mutex<BTreeMap<String, (usize, String)>> = Mutex::new(BTreeMap::new());
    let next = AtomicUsize::new(0);
    let written = AtomicUsize::new(0);
    // No more workers than episodes: `--threads 3000` on a short list would only add start-up.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads.min(todo.len().max(1)))
        .build()
        .map_err(|e| RunError::Pool(e.to_string()))?;
    pool.broadcast(|_| {
        while let Some(spec) = todo.get(next.fetch_add(1, Ordering::Relaxed)) {
            if lock(&failure).is_some() || options.stopped() {
                return;
            }
            let record = EpisodeRecord { set: options.set, ..run_one(spec, &episode, &options.policy) };
            if let Outcome::Error { message } = &record.outcome {
                let mut errors = lock(&errors);
                let key = spec.key();
                let (count, first) = errors.entry(message.clone()).or_insert_with(|| (0, key.clone()));
                *count += 1;
                if key < *first {
                    *first = key;
                }
                progress.note(format!("errors: {}", errors.values().map(|(n, _)| n).sum::<usize>()));
            }
            match lock(&writer).write(&record) {
                Ok(()) => _ = written.fetch_add(1, Ordering::Relaxed),
                Err(e) => _ = lock(&failure).get_or_insert(e),
            }
            progress.inc();
        }
    });
    progress.finish();
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    // All of `todo`, unless a stop left some.
    summary.ran = written.into_inner();
    let mut messages: Vec<ErrorTally> = errors
        .into_inner()
        .unwrap_or_else(|p| p.into_inner())
        .into_iter()
        .map(|(message, (count, first))| ErrorTally { count, message, first })
        .collect();
    messages.sort_by_key(|t| std::cmp::Reverse(t.count));
    summary.errors = messages.iter().map(|t| t.count).sum();
    summary.error_messages = messages;
    Ok(summary)
}

/// A results file opened for a run (by [`run`], or by a driver that gets its records from
/// elsewhere, such as the Python wheel's Ray runner): locked, checked, ready to append.
pub struct OpenResults {
    /// Held while the file is written.
    pub lock: RunLock,
    pub writer: ResultsWriter,
    /// Keys of the episodes that already have a completed record.
    pub done: BTreeSet<String>,
    /// Bytes of a cut-off last line found (and removed).
    pub truncated_tail: usize,
}

/// Takes the lock on `options.output` and checks what it holds: without `resume` it must be
/// empty; with it, its records must be of this [`RESULTS_VERSION`] and `options.set`, and
/// its completed ones of `options.policy`.
pub fn open_results(options: &RunOptions) -> Result<OpenResults, RunError> {
    let lock = RunLock::take(&options.output)?;
    let loaded = read_records(&options.output)?;
    if !options.resume && (!loaded.records.is_empty() || loaded.truncated_tail > 0) {
        return Err(RunError::Exists(options.output.clone()));
    }
    if let Some(r) = loaded.records.iter().find(|r| r.version != RESULTS_VERSION) {
        return Err(RunError::OtherVersion {
            path: options.output.clone(),
            found: r.version,
            expected: RESULTS_VERSION,
        });
    }
    if let Some(other) = loaded.records.iter().find(|r| r.set != options.set) {
        return Err(RunError::OtherSet { path: options.output.clone(), found: other.set, wanted: options.set });
    }
    let completed = || loaded.records.iter().filter(|r| results::is_completed(r));
    if let Some(other) = completed().find(|r| !options.policy.is_empty() && r.policy != options.policy) {
        return Err(RunError::OtherPolicy {
            path: options.output.clone(),
            found: other.policy.clone(),
            wanted: options.policy.clone(),
        });
    }
    let done = completed().map(|r| r.spec.key()).collect();
    let writer = ResultsWriter::append(&options.output, loaded.valid_len)?;
    Ok(OpenResults { lock, writer, done, truncated_tail: loaded.truncated_tail })
}

/// One episode with its wall time; panics and mismatched records become error records.
fn run_one<F>(spec: &EpisodeSpec, episode: &F, policy: &str) -> EpisodeRecord
where
    F: Fn(&EpisodeSpec) -> EpisodeRecord,
{
    let start = Instant::now();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| episode(spec)));
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let error = |message: String| EpisodeRecord {
        version: RESULTS_VERSION,
        spec: spec.clone(),
        policy: policy.to_string(),
        outcome: Outcome::Error { message },
        wall_ms,
        set: SetName::Full,
        // Nothing of it was drawn for the policy, so it goes with any look (an empty look would
        // read as the built-in one and mix looks in a run drawn with LIBERO's); error records
        // are rerun on resume.
        look: crate::env::scenes::NO_IMAGES.to_string(),
    };
    match result {
        Ok(record) if record.spec.key() == spec.key() => EpisodeRecord { wall_ms, ..record },
        Ok(record) => error(format!("episode function returned a record for {} instead", record.spec.key())),
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            error(format!("episode panicked: {what}"))
        }
    }
}

/// Locks a mutex, also after a panic elsewhere (the data here stays consistent line by line).
pub(crate) fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}
