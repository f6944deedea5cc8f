//! Task-conditioned instance set: for each task, every (family, variant) whose needs the task
//! meets, as a ready [`CueSpec`].
//!
//! Compatibility follows [`Needs`]: ghost trajectories and grasping hands need a step that
//! moves an object, arrows, paths and zone signs need a step with a target, the sticky note
//! needs a short instruction; everything else fits every task. A variant shows the first step
//! that meets its needs (so "open the top drawer and put the bowl inside" gets its arrow from
//! the bowl to the drawer). On LIBERO's 40 evaluation tasks this gives 1,468 instances, close
//! to the paper's 1,347 (see the README for the per-family comparison).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::parse::{self, GoalAtom, ParseError, ParsedTask};
use crate::spec::{CueSpec, Family};
use crate::variants::{Needs, VARIANTS, Variant};

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
#[error("task {task}: {source}")]
pub struct InstanceError {
    pub task: String,
    pub source: ParseError,
}

/// The step of `parsed` a variant with these needs shows, or `None` if the task cannot
/// carry the variant.
pub fn step_for(parsed: &ParsedTask, needs: Needs) -> Option<usize> {
    match needs {
        Needs::Nothing => Some(0),
        Needs::Target => parsed.steps.iter().position(|s| s.target.is_some()),
        Needs::MovingSource => parsed.steps.iter().position(|s| s.relation.moves_source()),
        Needs::ShortText(n) => (parsed.instruction.chars().count() <= n).then_some(0),
    }
}

/// The variants a task can carry, with the step each shows.
pub fn compatible(parsed: &ParsedTask) -> Vec<(&'static Variant, usize)> {
    VARIANTS.iter().filter_map(|v| step_for(parsed, v.needs).map(|s| (v, s))).collect()
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
    /// Builds the set: tasks in the given order, variants in catalogue order.
    pub fn build(tasks: &[TaskDescription]) -> Result<InstanceSet, InstanceError> {
        let mut instances = Vec::new();
        for task in tasks {
            let key = task.key();
            let parsed = task.parse().map_err(|source| InstanceError { task: key.clone(), source })?;
            for (variant, step) in compatible(&parsed) {
                // `step` comes from `parsed.steps`, so the spec is always constructible.
                if let Ok(spec) = CueSpec::new(&key, &parsed, step, variant) {
                    instances.push(spec);
                }
            }
        }
        Ok(InstanceSet { instances })
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
