//! The cue instances of LIBERO's 40 tasks (both named sets), and the names their scenes give
//! things.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use vifo_cues::{CueSpec, SetName};
use vifo_scenes::task::Entity;

use super::BenchmarkError;
use crate::scene_cues;
use crate::spec::{CueForm, TaskRef};
use crate::vqa::{Question, Scene, SceneEntity, VqaError};

/// Every cue instance of a named set of the 40 built-in tasks, in suite, task and catalogue
/// order.
pub fn all(set: SetName) -> &'static [CueSpec] {
    // The tasks and the parser are compiled in and `benchmark` tests build both sets, so a
    // failure here is a build defect, not bad input.
    &scene_cues::builtin_set(set).unwrap_or_else(|e| panic!("{set} instance set of the built-in tasks: {e}")).instances
}

/// The instance with this id (`libero_goal/3/F2/curved_arrow_yellow`), from either set (the
/// `full` set holds every instance), or from the study suites' instances.
pub fn find(id: &str) -> Result<&'static CueSpec, BenchmarkError> {
    static BY_ID: OnceLock<BTreeMap<String, usize>> = OnceLock::new();
    let full = all(SetName::Full);
    let index = BY_ID.get_or_init(|| full.iter().enumerate().map(|(i, s)| (s.id(), i)).collect());
    if let Some(&i) = index.get(id) {
        return Ok(&full[i]);
    }
    study()
        .iter()
        .find(|s| s.id() == id)
        .ok_or_else(|| BenchmarkError::UnknownInstance { id: id.to_string(), hint: scene_cues::unknown_instance_hint(id) })
}

/// Every cue instance of the study suites' tasks (`vifo_safety/1/F1/caption_bar`, ...).
pub fn study() -> &'static [CueSpec] {
    // Built from compiled-in tasks with the compiled-in parser and tested, as `all`.
    &scene_cues::study_instances().unwrap_or_else(|e| panic!("instances of the study tasks: {e}")).instances
}

/// The task an instance belongs to.
pub fn task_of(spec: &CueSpec) -> Result<TaskRef, BenchmarkError> {
    spec.task.parse().map_err(BenchmarkError::BadTask)
}

/// A name in the style of the instructions for a LIBERO asset category; `None` for the floor.
pub fn human_name(category: &str) -> Option<String> {
    Some(
        match category {
            "floor" => return None,
            "akita_black_bowl" => "black bowl",
            "glazed_rim_porcelain_ramekin" => "ramekin",
            "cookies" => "cookie box",
            "flat_stove" => "stove",
            "kitchen_knife" => "knife",
            "black_book" => "book",
            "chefmate_8_frypan" => "frying pan",
            "desk_caddy" => "caddy",
            "porcelain_mug" => "white mug",
            "red_coffee_mug" => "red mug",
            "white_yellow_mug" => "yellow and white mug",
            "kitchen_table" | "living_room_table" | "study_table" => "table",
            other => return Some(other.replace('_', " ")),
        }
        .to_string(),
    )
}

/// The Part I-A questions of `set` with the images in `form`. The object form asks the overlay
/// form's questions of its families (F1, F6, F8) with the same options and answer letters
/// (generating them for that subset alone would balance the letters anew), so that the two
/// forms' scores differ only in what the images show.
pub fn questions(set: SetName, form: CueForm) -> Result<Vec<Question>, VqaError> {
    let questions = crate::vqa::generate(all(set), &vqa_scenes())?;
    Ok(questions.into_iter().filter(|q| form == CueForm::Overlay || vifo_cues::OBJECT_FAMILIES.contains(&q.family)).collect())
}

/// The VQA distractor pool of every built-in task (`libero_goal/3` → objects and fixtures with
/// instruction-style names).
pub fn vqa_scenes() -> BTreeMap<String, Scene> {
    let entities = |list: &[Entity]| -> Vec<SceneEntity> {
        list.iter().filter_map(|e| Some(SceneEntity::new(&e.name, &human_name(&e.category)?))).collect()
    };
    vifo_scenes::all_tasks()
        .map(|t| {
            let d = scene_cues::describe(t);
            (d.key(), Scene { objects: entities(&t.objects), fixtures: entities(&t.fixtures) })
        })
        .collect()
}
