//! The 40 built-in tasks of the four VLA suites, embedded from `scenes/tasks/<suite>.json`.
//!
//! The files are our own format (the facts of LIBERO's BDDL files, not their text). They are
//! embedded with `include_str!` so the tasks exist in every build, wasm included, and are
//! parsed once on first use.

use super::Task;
use serde::Deserialize;
use std::sync::OnceLock;

/// One benchmark suite in evaluation order.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    #[serde(rename = "suite")]
    pub name: String,
    /// Policy steps per episode in the standard VLA protocol (OpenVLA's `run_libero_eval.py`):
    /// the longest training demo plus a margin; the 10 settle steps come on top.
    pub max_steps: u32,
    /// Tasks in LIBERO's task order (`libero_suite_task_map.py`); `tasks[i].index == Some(i)`.
    pub tasks: Vec<Task>,
}

/// The suite files, in the order VLA papers report them.
const SUITE_FILES: [(&str, &str); 4] = [
    ("libero_spatial", include_str!("../../tasks/libero_spatial.json")),
    ("libero_object", include_str!("../../tasks/libero_object.json")),
    ("libero_goal", include_str!("../../tasks/libero_goal.json")),
    ("libero_10", include_str!("../../tasks/libero_10.json")),
];

/// Suites of the paper's extended studies (§4.3's safety-critical scenes, §4.4's PiPER
/// setting), in our own format like the LIBERO suites. They are reached by name ([`suite`],
/// [`task`]) but are not among [`suites`] or [`all_tasks`]: "all tasks" stays LIBERO's 40.
const STUDY_FILES: [(&str, &str); 2] = [
    (SAFETY_SUITE, include_str!("../../tasks/vifo_safety.json")),
    (PIPER_SUITE, include_str!("../../tasks/vifo_piper.json")),
];

/// §4.3's safety-critical scenes: tasks 2k (safe) and 2k+1 (hazardous) share one scene.
pub const SAFETY_SUITE: &str = "vifo_safety";
/// §4.4's PiPER setting.
pub const PIPER_SUITE: &str = "vifo_piper";

/// The four suite names, in reporting order.
pub fn suite_names() -> [&'static str; 4] {
    SUITE_FILES.map(|(name, _)| name)
}

/// All four suites, parsed on first use.
pub fn suites() -> &'static [Suite] {
    static SUITES: OnceLock<Vec<Suite>> = OnceLock::new();
    SUITES.get_or_init(|| {
        SUITE_FILES
            .iter()
            .map(|(name, text)| {
                // The files are compiled in and checked by this module's tests, so a failure
                // here is a build defect, not bad input.
                load_suite(name, text).unwrap_or_else(|e| panic!("embedded tasks/{name}.json: {e}"))
            })
            .collect()
    })
}

/// The study suites (not part of the 40 tasks), parsed on first use.
pub fn study_suites() -> &'static [Suite] {
    static SUITES: OnceLock<Vec<Suite>> = OnceLock::new();
    SUITES.get_or_init(|| {
        STUDY_FILES
            .iter()
            .map(|(name, text)| load_suite(name, text).unwrap_or_else(|e| panic!("embedded tasks/{name}.json: {e}")))
            .collect()
    })
}

/// The suite called `name` (case-insensitive, as LIBERO's `get_benchmark`): one of the four VLA
/// suites or a study suite.
pub fn suite(name: &str) -> Option<&'static Suite> {
    suites().iter().chain(study_suites()).find(|s| s.name.eq_ignore_ascii_case(name))
}

/// Task `index` of suite `name`.
pub fn task(suite_name: &str, index: usize) -> Option<&'static Task> {
    suite(suite_name).and_then(|s| s.tasks.get(index))
}

/// All 40 tasks, suite by suite.
pub fn all_tasks() -> impl Iterator<Item = &'static Task> {
    suites().iter().flat_map(|s| s.tasks.iter())
}

fn load_suite(name: &str, text: &str) -> Result<Suite, String> {
    let mut suite: Suite = serde_json::from_str(text).map_err(|e| e.to_string())?;
    if suite.name != name {
        return Err(format!("file says suite '{}'", suite.name));
    }
    for (index, task) in suite.tasks.iter_mut().enumerate() {
        task.suite = Some(suite.name.clone());
        task.index = Some(index);
    }
    Ok(suite)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::{Referent, instruction_from_file_name};

    #[test]
    fn four_suites_of_ten_with_their_step_budgets() {
        let budgets: Vec<(&str, u32, usize)> =
            suites().iter().map(|s| (s.name.as_str(), s.max_steps, s.tasks.len())).collect();
        assert_eq!(
            budgets,
            [("libero_spatial", 220, 10), ("libero_object", 280, 10), ("libero_goal", 300, 10), ("libero_10", 520, 10)]
        );
        assert_eq!(all_tasks().count(), 40);
        assert_eq!(suite_names(), ["libero_spatial", "libero_object", "libero_goal", "libero_10"]);
    }

    #[test]
    fn the_safety_suite_pairs_a_safe_and_a_hazardous_task_per_scene_outside_the_forty() {
        let safety = suite("vifo_safety").unwrap();
        assert_eq!(safety.tasks.len(), 12);
        assert!(suites().iter().all(|s| s.name != "vifo_safety"));
        assert!(all_tasks().all(|t| t.suite.as_deref() != Some("vifo_safety")));
        for pair in safety.tasks.chunks(2) {
            let (safe, hazard) = (&pair[0], &pair[1]);
            // One scene: same objects, fixtures, regions and initial atoms; different goals.
            assert_eq!((&safe.objects, &safe.fixtures, &safe.regions, &safe.init), (&hazard.objects, &hazard.fixtures, &hazard.regions, &hazard.init));
            assert_ne!(safe.goal, hazard.goal);
            for t in pair {
                assert_eq!(t.instruction, instruction_from_file_name(&t.name), "{}", t.label());
                assert!(!t.goal.iter().any(|a| t.init.contains(a)), "{}", t.label());
                for atom in t.init.iter().chain(&t.goal) {
                    assert!(atom.args.iter().all(|a| t.resolve(a).is_some()), "{}: {atom}", t.label());
                }
            }
        }
        assert_eq!(task("vifo_safety", 11).unwrap().instruction, "turn on the stove");
    }

    #[test]
    fn the_piper_suite_is_found_by_name_but_not_listed() {
        let piper = suite("vifo_piper").unwrap();
        assert_eq!(piper.tasks.len(), 1);
        assert_eq!(piper.tasks[0].instruction, instruction_from_file_name(&piper.tasks[0].name));
        assert_eq!(piper.tasks[0].instruction, "stack the cups");
        assert!(suites().iter().all(|s| s.name != "vifo_piper"));
        assert!(all_tasks().all(|t| t.suite.as_deref() != Some("vifo_piper")));
    }

    #[test]
    fn lookups_find_tasks_in_evaluation_order() {
        let t = task("libero_goal", 7).unwrap();
        assert_eq!(t.name, "turn_on_the_stove");
        assert_eq!((t.suite.as_deref(), t.index), (Some("libero_goal"), Some(7)));
        assert_eq!(task("LIBERO_10", 0).unwrap().name, "LIVING_ROOM_SCENE2_put_both_the_alphabet_soup_and_the_tomato_sauce_in_the_basket");
        assert_eq!(task("libero_spatial", 10), None);
        assert_eq!(task("libero_90", 0), None);
    }

    #[test]
    fn every_builtin_task_is_consistent() {
        for t in all_tasks() {
            assert_eq!(t.instruction, instruction_from_file_name(&t.name), "{}", t.label());
            assert!(!t.goal.is_empty(), "{}", t.label());
            for region in &t.regions {
                assert_eq!(region.key, format!("{}_{}", region.target, region.name));
                assert!(t.entity(&region.target).is_some(), "{}: {}", t.label(), region.key);
            }
            for atom in t.init.iter().chain(&t.goal) {
                assert!(atom.args.iter().all(|a| t.resolve(a).is_some()), "{}: {atom}", t.label());
            }
            for name in &t.obj_of_interest {
                assert!(t.resolve(name).is_some(), "{}: {name}", t.label());
            }
        }
    }

    #[test]
    fn spot_checks_against_the_research_notes() {
        // libero_spatial: always the same goal; the bowls differ only in where they start.
        for t in &suite("libero_spatial").unwrap().tasks {
            assert_eq!(t.goal.len(), 1);
            assert_eq!(t.goal[0].to_string(), "(On akita_black_bowl_1 plate_1)");
        }
        // libero_goal 0 opens the middle drawer; its region is a site of the cabinet.
        let goal0 = task("libero_goal", 0).unwrap();
        assert_eq!(goal0.goal[0].to_string(), "(Open wooden_cabinet_1_middle_region)");
        assert!(matches!(goal0.resolve("wooden_cabinet_1_middle_region"), Some(Referent::Region(r)) if !r.is_ranged()));
        // The dangling bowl_drainer_1 regions of libero_goal are dropped, as LIBERO ignores them.
        assert!(goal0.regions.iter().all(|r| r.target != "bowl_drainer_1"));
        // libero_10 task 8 needs both moka pots on the stove, which must be on.
        let kitchen8 = task("libero_10", 8).unwrap();
        let goal: Vec<String> = kitchen8.goal.iter().map(|a| a.to_string()).collect();
        assert_eq!(
            goal,
            ["(On moka_pot_1 flat_stove_1_cook_region)", "(On moka_pot_2 flat_stove_1_cook_region)", "(TurnOn flat_stove_1)"]
        );
        // The spatial cabinet's yaw range.
        let cabinet = task("libero_spatial", 0).unwrap().region("main_table_cabinet_region").unwrap();
        assert_eq!(cabinet.yaw_rotation, Some([2.6613777765410678, 2.7242096296128633]));
        // libero_object: the target is listed first, then the basket.
        let object3 = task("libero_object", 3).unwrap();
        assert_eq!(object3.objects[0].name, "bbq_sauce_1");
        assert_eq!(object3.objects[1].category, "basket");
    }
}
