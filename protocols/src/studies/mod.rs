//! The paper's extended studies (§4.2–§4.4), each a selection of episodes over its own suite
//! run by the same runner into the same results files, with its own tables laid out as the
//! paper lays the study out.
//!
//! - [`safety`]: the six safety-critical scenes of §4.3 (`vifo_safety`).

pub mod safety;

use crate::benchmark::BenchmarkError;
use crate::spec::EpisodeSpec;

/// An extended study (`vifo run --study NAME`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Study {
    /// §4.3: safe vs hazardous tasks under authorized cue following and language–cue conflict.
    Safety,
}

impl Study {
    pub const ALL: [Study; 1] = [Study::Safety];

    pub fn name(self) -> &'static str {
        match self {
            Study::Safety => "safety",
        }
    }

    /// The study an episode belongs to (by its suite), `None` for the main benchmark.
    pub fn of(spec: &EpisodeSpec) -> Option<Study> {
        match spec.task.suite.as_str() {
            safety::SUITE => Some(Study::Safety),
            _ => None,
        }
    }

    /// The study's episodes.
    pub fn episodes(self, options: &StudyOptions) -> Result<Vec<EpisodeSpec>, BenchmarkError> {
        match self {
            Study::Safety => safety::episodes(options),
        }
    }
}

impl std::str::FromStr for Study {
    type Err = String;

    fn from_str(s: &str) -> Result<Study, String> {
        Study::ALL
            .into_iter()
            .find(|study| study.name() == s)
            .ok_or_else(|| format!("unknown study {s:?}: expected safety or all"))
    }
}

/// How much of a study to run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StudyOptions {
    /// Episodes per (instance, protocol), and per task for the told-task rows; episode e starts
    /// from initial state e mod 50.
    pub episodes: usize,
    /// Only the small sample `vifo run`'s quick default includes.
    pub quick: bool,
}
