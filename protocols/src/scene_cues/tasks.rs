//! The instance sets of the 40 built-in LIBERO tasks, and looking instances up by id.

use std::sync::OnceLock;

use vifo_cues::instances::{InstanceError, InstanceSet, TaskDescription};
use vifo_cues::parse::GoalAtom;
use vifo_cues::{CueSpec, SetName};
use vifo_scenes::Task;

use super::SceneCueError;
use crate::studies::SuiteCue;

/// What the instance generator needs of a task: its key, instruction, goal atoms (so steps are
/// grounded to the simulator's names) and the scene's object and fixture names.
pub fn describe(task: &Task) -> TaskDescription {
    TaskDescription {
        suite: task.suite.clone().unwrap_or_default(),
        index: task.index.unwrap_or_default(),
        instruction: task.instruction.clone(),
        goals: task.goal.iter().map(|a| GoalAtom { predicate: a.predicate.name().to_string(), args: a.args.clone() }).collect(),
        objects: task.objects.iter().map(|e| e.name.clone()).collect(),
        fixtures: task.fixtures.iter().map(|e| e.name.clone()).collect(),
    }
}

/// The `full` instance set of the 40 built-in tasks (built once); every instance of either
/// set is in it.
pub fn builtin_instances() -> Result<&'static InstanceSet, SceneCueError> {
    static SET: OnceLock<Result<InstanceSet, InstanceError>> = OnceLock::new();
    let set = SET.get_or_init(|| {
        let tasks: Vec<TaskDescription> = vifo_scenes::all_tasks().map(describe).collect();
        InstanceSet::build(&tasks)
    });
    set.as_ref().map_err(|e| SceneCueError::Instances(e.clone()))
}

/// Every cue instance of the study suites' tasks (`vifo_safety`; built once). Kept apart from
/// the 40 tasks' sets, so the paper set and its counts stay LIBERO's.
pub fn study_instances() -> Result<&'static InstanceSet, SceneCueError> {
    static SET: OnceLock<Result<InstanceSet, InstanceError>> = OnceLock::new();
    let set = SET.get_or_init(|| {
        // A suite whose cue is a note in the scene has no library instances.
        let tasks: Vec<TaskDescription> = vifo_scenes::study_suites()
            .iter()
            .filter(|s| SuiteCue::of(&s.name) == SuiteCue::Library)
            .flat_map(|s| &s.tasks)
            .map(describe)
            .collect();
        InstanceSet::build(&tasks)
    });
    set.as_ref().map_err(|e| SceneCueError::Instances(e.clone()))
}

/// One named instance set of the 40 built-in tasks (built once).
pub fn builtin_set(set: SetName) -> Result<&'static InstanceSet, SceneCueError> {
    let full = builtin_instances()?;
    if set == SetName::Full {
        return Ok(full);
    }
    static PAPER: OnceLock<Result<InstanceSet, String>> = OnceLock::new();
    PAPER
        .get_or_init(|| full.paper().map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|why| SceneCueError::Unsupported { cue: "paper set".into(), why: why.clone() })
}

/// The built-in instance with this id (`libero_goal/3/F2/curved_arrow_yellow`, or a study
/// task's `vifo_safety/1/F1/caption_bar`).
pub fn instance(id: &str) -> Result<&'static CueSpec, SceneCueError> {
    let set = set_of(id)?;
    set.instances
        .iter()
        .find(|s| s.id() == id)
        .ok_or_else(|| SceneCueError::UnknownInstance { id: id.to_string(), hint: hint_in(set, id) })
}

/// Why `id` names no built-in instance, and what comes close: the id's expected form, the
/// task's variants of the family it names, or the variant's instances on the task.
pub fn unknown_instance_hint(id: &str) -> String {
    set_of(id).map_or_else(|e| e.to_string(), |set| hint_in(set, id))
}

/// The set an id is looked up in: the study tasks' (`vifo_...`) or the 40 tasks' full set.
fn set_of(id: &str) -> Result<&'static InstanceSet, SceneCueError> {
    if id.starts_with("vifo_") { study_instances() } else { builtin_instances() }
}

fn hint_in(set: &InstanceSet, id: &str) -> String {
    let parts: Vec<&str> = id.split('/').collect();
    let [suite, index, family, shown] = parts[..] else {
        return "expected <suite>/<index>/<family>/<variant>, e.g. libero_goal/3/F2/curved_arrow_yellow".into();
    };
    let key = format!("{suite}/{index}");
    // `variant@n` is the instance showing step n.
    let variant = shown.split_once('@').map_or(shown, |(v, _)| v);
    let of_task: Vec<&str> = set.instances.iter().filter(|s| s.task == key).map(|s| s.variant.as_str()).collect();
    if of_task.is_empty() {
        return format!("no built-in task {key} (suites: {}; indices 0-9)", vifo_scenes::suite_names().join(", "));
    }
    let listed = format!("`vifo cues list --ids --task {key}` lists its ids");
    match vifo_cues::variants::find(variant) {
        None => {
            let mut of_family: Vec<&str> =
                set.instances.iter().filter(|s| s.task == key && s.family.to_string() == family).map(|s| s.variant.as_str()).collect();
            of_family.dedup();
            if of_family.is_empty() {
                format!("no variant '{variant}' ({listed})")
            } else {
                format!("no variant '{variant}'; task {key} carries these of {family}: {} ({listed})", of_family.join(", "))
            }
        }
        Some(v) if !of_task.contains(&variant) => format!("task {key} cannot carry {variant} (needs: {:?}; {listed})", v.needs),
        Some(v) if v.family.to_string() != family => format!("{variant} belongs to family {}", v.family),
        Some(_) => {
            let ids: Vec<String> = set.instances.iter().filter(|s| s.task == key && s.variant == variant).map(|s| s.id()).collect();
            format!("task {key} has these {variant} instances: {}", ids.join(", "))
        }
    }
}

/// The built-in task a spec's `task` key (`suite/index`) names.
pub fn task_of(spec: &CueSpec) -> Result<&'static Task, SceneCueError> {
    spec.task
        .split_once('/')
        .and_then(|(suite, index)| vifo_scenes::task(suite, index.parse().ok()?))
        .ok_or_else(|| SceneCueError::UnknownInstance {
            id: spec.id(),
            hint: format!("'{}' is not a built-in task (expected <suite>/<index>)", spec.task),
        })
}
