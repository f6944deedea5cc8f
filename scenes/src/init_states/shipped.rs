//! The shipped states, embedded from `scenes/init_states/<suite>.json` (so they exist in every
//! build, wasm included) and parsed on first use.

use std::sync::OnceLock;

use thiserror::Error;

use super::EpisodeStart;
use super::format::{FormatError, SuiteStates, parse};
use crate::init_file::articulation_joints;
use crate::sim::ARENA_CATEGORIES;
use crate::task::Task;

const FILES: [(&str, &str); 6] = [
    ("libero_spatial", include_str!("../../init_states/libero_spatial.json")),
    ("libero_object", include_str!("../../init_states/libero_object.json")),
    ("libero_goal", include_str!("../../init_states/libero_goal.json")),
    ("libero_10", include_str!("../../init_states/libero_10.json")),
    ("vifo_safety", include_str!("../../init_states/vifo_safety.json")),
    // The PiPER study's scene (§4.4).
    ("vifo_piper", include_str!("../../init_states/vifo_piper.json")),
];

/// Why a task has no usable shipped states.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ShippedError {
    #[error("no initial states are shipped for suite '{0}'")]
    NoSuite(String),
    #[error("task {0} belongs to no suite")]
    NoTask(String),
    #[error("the states are for suite {found}, the task is in {expected}")]
    WrongSuite { expected: String, found: String },
    #[error(transparent)]
    Format(#[from] FormatError),
    #[error("the {suite} states have none for task {index} ({name})")]
    Missing { suite: String, index: usize, name: String },
    #[error("the {suite} states: task {index} {problem}")]
    Mismatch { suite: String, index: usize, problem: String },
}

/// A shipped suite file, parsed.
pub fn shipped_suite(name: &str) -> Result<&'static SuiteStates, ShippedError> {
    static PARSED: [OnceLock<Result<SuiteStates, FormatError>>; FILES.len()] = [const { OnceLock::new() }; FILES.len()];
    let i = FILES.iter().position(|(n, _)| *n == name).ok_or_else(|| ShippedError::NoSuite(name.to_string()))?;
    let (file, text) = FILES[i];
    PARSED[i].get_or_init(|| parse(text, &format!("init_states/{file}.json"))).as_ref().map_err(|e| e.clone().into())
}

/// The shipped initial states of a built-in task, checked against the task's objects, joints
/// and fixtures.
pub fn fixed(task: &Task) -> Result<&'static [EpisodeStart], ShippedError> {
    let suite = task.suite.as_deref().ok_or_else(|| ShippedError::NoTask(task.name.clone()))?;
    starts_for(shipped_suite(suite)?, task)
}

/// The states `stored` holds for `task` (a suite file read from anywhere), checked against the
/// task's objects, joints and fixtures.
pub fn starts_for<'a>(stored: &'a SuiteStates, task: &Task) -> Result<&'a [EpisodeStart], ShippedError> {
    let (Some(suite), Some(index)) = (task.suite.as_deref(), task.index) else {
        return Err(ShippedError::NoTask(task.name.clone()));
    };
    if stored.suite != suite {
        return Err(ShippedError::WrongSuite { expected: suite.to_string(), found: stored.suite.clone() });
    }
    let missing = || ShippedError::Missing { suite: suite.to_string(), index, name: task.name.clone() };
    let t = stored.tasks.iter().find(|t| t.index == index).ok_or_else(missing)?;
    let mismatch = |problem: String| ShippedError::Mismatch { suite: suite.to_string(), index, problem };
    if t.name != task.name {
        return Err(mismatch(format!("is stored as '{}', expected '{}'", t.name, task.name)));
    }
    let Some(first) = t.starts.first() else { return Err(missing()) };
    let objects: Vec<&str> = first.state.objects.iter().map(|o| o.name.as_str()).collect();
    let expected: Vec<&str> = task.objects.iter().map(|o| o.name.as_str()).collect();
    if objects != expected {
        return Err(mismatch(format!("names objects {objects:?}, the task has {expected:?}")));
    }
    let joints: Vec<(&str, &str)> = first.state.joints.iter().map(|j| (j.owner.as_str(), j.joint.as_str())).collect();
    let expected: Vec<(&str, &str)> = task
        .objects
        .iter()
        .chain(&task.fixtures)
        .flat_map(|e| articulation_joints(&e.category).iter().map(move |j| (e.name.as_str(), *j)))
        .collect();
    if joints != expected {
        return Err(mismatch(format!("names joints {joints:?}, the task has {expected:?}")));
    }
    let fixtures: Vec<&str> = first.fixtures.iter().map(|f| f.name.as_str()).collect();
    let expected: Vec<&str> =
        task.fixtures.iter().filter(|f| !ARENA_CATEGORIES.contains(&f.category.as_str())).map(|f| f.name.as_str()).collect();
    if fixtures != expected {
        return Err(mismatch(format!("names fixtures {fixtures:?}, the task has {expected:?}")));
    }
    Ok(&t.starts)
}
