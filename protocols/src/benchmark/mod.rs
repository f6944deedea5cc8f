//! What the benchmark consists of, as data: the cue instances of LIBERO's 40 tasks, the
//! language of every protocol (with the conflict pairs of Part II-A), and the list of episodes
//! a run is made of.
//!
//! - [`instances`]: the instance set of the built-in tasks, lookup by id, VQA scene names.
//! - [`language`]: instruction and language goal per protocol; conflict partners.
//! - [`specs`]: [`EpisodeSpec`](crate::EpisodeSpec)s for a selection of suites, protocols,
//!   families and episodes, with their stable seeds.
//! - [`records`]: results files read with every record checked against those specs.

pub mod instances;
pub mod language;
pub mod records;
pub mod specs;

use thiserror::Error;

/// Why a benchmark item could not be found or built.
#[derive(Debug, Error, PartialEq)]
pub enum BenchmarkError {
    #[error("unknown cue instance '{id}': {hint}")]
    UnknownInstance { id: String, hint: String },
    #[error("unknown task {0} (built-in tasks: libero_spatial, libero_object, libero_goal, libero_10, indices 0-9)")]
    UnknownTask(String),
    #[error("{0}")]
    BadTask(String),
    #[error("unknown suite {0:?}; expected libero_spatial, libero_object, libero_goal, libero_10 or all")]
    UnknownSuite(String),
    #[error("task {0}: no conflict partner (no task of its scene passes the rules of benchmark::language)")]
    NoConflictPartner(String),
    #[error("task {task}: protocol {protocol} needs a cue instance")]
    MissingInstance { task: String, protocol: String },
    #[error("{0} episodes per instance: at most {max} (initial states repeat every 50)", max = specs::MAX_EPISODES)]
    TooManyEpisodes(usize),
    #[error("instance {instance} belongs to task {instance_task}, not to {task}")]
    InstanceOfOtherTask { instance: String, instance_task: String, task: String },
}

/// The built-in task `task`.
pub fn builtin_task(task: &crate::TaskRef) -> Result<&'static vifo_scenes::Task, BenchmarkError> {
    vifo_scenes::task(&task.suite, task.index).ok_or_else(|| BenchmarkError::UnknownTask(task.to_string()))
}
