//! Task-conditioned instance sets: for each task, every (family, variant, step) whose needs the
//! task meets, as a ready [`CueSpec`] (the `full` set), and the paper's 1,347-instance subset
//! ([`paper`]).
//!
//! Compatibility follows [`Needs`]: ghost trajectories and grasping hands need a step that
//! moves an object, arrows, paths and zone signs need a step with a target, the sticky note
//! needs a short instruction, prohibition, maintenance and system-state signs a state change,
//! hazard and hand-over signs a step handling a hot or fragile thing or a carrier; everything
//! else fits every task.
//!
//! Fixed-region variants (text, pictures, codes) show the whole task: one instance per task,
//! showing the first step that meets their needs. Scene-anchored and ghost variants show one
//! step: one instance per step that meets their needs, except a step whose marked things
//! ([`Marks`]) an earlier instance of the variant already marks (a crosshair on the basket
//! for "put both the soup and the sauce in the basket" is one instance). An instance showing
//! the variant's first fitting step has the id `<task>/<family>/<variant>`; one showing a later
//! step adds `@<step number>` (`libero_10/4/F2/straight_arrow_red@2`).

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use crate::parse::{self, GoalAtom, ParseError, ParsedTask, Step};
use crate::spec::{CueSpec, Family};
use crate::variants::{Marks, Needs, VARIANTS, Variant};

pub mod paper;

pub use paper::SetName;

/// What the generator needs to know about a task.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TaskDescription {
    pub suite: String,
    pub index: usize,
    pub instruction: String,
    /// Goal atoms, used to link steps to simulator bodies (`source_id`, `target_id`).
    #[serde(default)]
    pub goals: Vec<GoalAtom>,
    /// Object and fixture names of the scene, used for linking when there are no goals.
    #[serde(default)]
    pub objects: Vec<String>,
    #[serde(default)]
    pub fixtures: Vec<String>,
}

impl TaskDescription {
    /// The task key used in cue ids: `<suite>/<index>`.
    pub fn key(&self) -> String {
        format!("{}/{}", self.suite, self.index)
    }

    /// Parses the instruction, grounding steps in the goals or else in the scene's names.
    pub fn parse(&self) -> Result<ParsedTask, ParseError> {
        if self.goals.is_empty() {
            let mut parsed = parse::parse(&self.instruction)?;
            let names: Vec<&str> = self.objects.iter().chain(&self.fixtures).map(String::as_str).collect();
            parse::ground_to_names(&mut parsed.steps, &names);
            Ok(parsed)
        } else {
            parse::parse_with_goals(&self.instruction, &self.goals)
        }
    }
}

/// Why the instance set could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InstanceError {
    #[error("task {task}: {source}")]
    Parse { task: String, source: ParseError },
    /// Its instances' ids would repeat, and a run would count their episodes twice.
    #[error("task {0} is described more than once (each task once: cue ids are made from it)")]
    Repeated(String),
}

/// The step of `parsed` a variant with these needs shows first, or `None` if the task cannot
/// carry the variant.
pub fn step_for(parsed: &ParsedTask, needs: Needs) -> Option<usize> {
    first_step(&parsed.steps, &parsed.instruction, needs)
}

/// [`step_for`] on a task's steps and instruction.
pub fn first_step(steps: &[Step], instruction: &str, needs: Needs) -> Option<usize> {
    if let Needs::ShortText(n) = needs {
        return (!steps.is_empty() && instruction.chars().count() <= n).then_some(0);
    }
    steps.iter().position(|s| needs.met_by(s))
}

/// The steps of `parsed` a variant shows, one instance each (see the module docs).
pub fn steps_shown(parsed: &ParsedTask, variant: &Variant) -> Vec<usize> {
    let Some(first) = step_for(parsed, variant.needs) else { return Vec::new() };
    if variant.marks == Marks::Region {
        return vec![first];
    }
    let mut shown: Vec<usize> = Vec::new();
    let mut marked: Vec<(Option<&str>, Option<&str>)> = Vec::new();
    for (i, step) in parsed.steps.iter().enumerate().skip(first) {
        if !variant.needs.met_by(step) {
            continue;
        }
        let source = step.source_id.as_deref().or(Some(step.source.as_str()));
        let target = step.target_id.as_deref().or(step.target.as_deref());
        let things = match variant.marks {
            Marks::Source => (source, None),
            Marks::Target => (target.or(source), None),
            Marks::Both | Marks::Region => (source, target),
        };
        if !marked.contains(&things) {
            marked.push(things);
            shown.push(i);
        }
    }
    shown
}

/// The (variant, step) pairs a task carries, variants in catalogue order.
pub fn compatible(parsed: &ParsedTask) -> Vec<(&'static Variant, usize)> {
    VARIANTS.iter().flat_map(|v| steps_shown(parsed, v).into_iter().map(move |s| (v, s))).collect()
}

/// All task-conditioned cue instances.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstanceSet {
    pub instances: Vec<CueSpec>,
}

/// Instance counts of one family.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FamilyCount {
    pub instances: usize,
    /// Tasks with at least one instance of the family.
    pub tasks: usize,
    /// Share of all instances.
    pub share: f64,
}

impl InstanceSet {
    /// Builds the `full` set: tasks in the given order, variants in catalogue order, steps in
    /// task order.
    pub fn build(tasks: &[TaskDescription]) -> Result<InstanceSet, InstanceError> {
        let mut instances = Vec::new();
        let mut seen = BTreeSet::new();
        for task in tasks {
            let key = task.key();
            if !seen.insert(key.clone()) {
                return Err(InstanceError::Repeated(key));
            }
            let parsed = task.parse().map_err(|source| InstanceError::Parse { task: key.clone(), source })?;
            for (variant, step) in compatible(&parsed) {
                // `step` comes from `parsed.steps`, so the spec is always constructible.
                if let Ok(spec) = CueSpec::new(&key, &parsed, step, variant) {
                    instances.push(spec);
                }
            }
        }
        Ok(InstanceSet { instances })
    }

    /// The `paper` set chosen from this (`full`) set by the rule of [`paper`].
    pub fn paper(&self) -> Result<InstanceSet, paper::PaperSetError> {
        paper::select(self)
    }

    /// Per-family counts, in family order.
    pub fn composition(&self) -> BTreeMap<Family, FamilyCount> {
        let total = self.instances.len().max(1) as f64;
        Family::ALL
            .iter()
            .map(|&f| {
                let of_family: Vec<&CueSpec> = self.instances.iter().filter(|s| s.family == f).collect();
                let mut tasks: Vec<&str> = of_family.iter().map(|s| s.task.as_str()).collect();
                tasks.sort_unstable();
                tasks.dedup();
                (
                    f,
                    FamilyCount {
                        instances: of_family.len(),
                        tasks: tasks.len(),
                        share: of_family.len() as f64 / total,
                    },
                )
            })
            .collect()
    }
}
