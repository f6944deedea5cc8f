//! The language of an episode per protocol, and the conflict pairs of Part II-A.
//!
//! | protocol | instruction | language task | cue |
//! |---|---|---|---|
//! | original | the task's own | the task's goal | none |
//! | authorized | "follow the visual cue in the observation and complete the task" | none | the task's |
//! | conflict | a partner task's ([`conflict`]) | the partner's goal in this scene | the task's |
//! | no_language | empty | none | the task's |
//!
//! **Conflict partners.** The cue shows task T; the language asks for a partner P. The
//! candidates, in order: the other tasks of T's suite in cyclic order after T (T+1, T+2, …),
//! then the tasks of the other suites in reporting order, then the tasks written for T's scene
//! below ([`CONSTRUCTED`]). The first candidate that passes every rule is the partner:
//!
//! 1. P's goal maps into T's scene ([`map_into`]): every object, fixture and region it names
//!    exists in T's scene. An object of a category T's scene holds only once maps to that
//!    object; when T's scene holds several of the category (libero_spatial's two black bowls)
//!    it maps to the one that starts on the same support as P's object does in P's layout — so
//!    "pick up the black bowl next to the ramekin …" names whichever bowl stands next to the
//!    ramekin in T's layout.
//! 2. No atom of the mapped goal is among T's initial atoms (it does not hold at the start).
//! 3. Neither goal contains the other, so finishing one task never finishes the other.
//! 4. The cue parser can parse P's instruction (so a language-following policy can ground it).
//!
//! Per suite this gives: libero_goal (one shared scene) and libero_object (the basket and most
//! groceries recur) pair with the next task of the suite whose object is present;
//! libero_spatial pairs each layout with the task whose instruction describes where the
//! *other* bowl stands (the language asks for bowl 2, the cue shows bowl 1); libero_10's
//! scenes differ, so its tasks pair within libero_10 where the objects recur (the living-room
//! basket tasks), with libero_goal's wine-rack task for the kitchen with a rack, and otherwise
//! with a task written for the scene: the same relation with another object present (frying
//! pan, red mug, white mug, the front compartment), or the opposite knob state where the
//! scene offers nothing else (libero_10/8 starts with the stove on: "turn off the stove").

use vifo_scenes::Task;
use vifo_scenes::task::{Atom, Predicate};

use super::BenchmarkError;
use crate::spec::{Protocol, TaskRef};

/// A task a language instruction can ask for in some scene: its instruction, its goal, and the
/// scene whose names and layout the goal is written in.
#[derive(Clone, Debug, PartialEq)]
pub struct KnownTask {
    /// The scene the goal's names refer to (a built-in task).
    pub scene: &'static Task,
    /// `Some` for a built-in task, `None` for one written for a scene ([`CONSTRUCTED`]).
    pub builtin: Option<TaskRef>,
    pub instruction: String,
    pub goal: Vec<Atom>,
}

/// A goal atom as written: predicate name and argument names.
pub type AtomText = (&'static str, &'static [&'static str]);

/// Language tasks written for libero_10 scenes where no built-in task passes the conflict
/// rules: (scene task index, instruction, goal atoms). Our own definitions, in the style of
/// LIBERO's instructions and with its predicates and region names.
pub const CONSTRUCTED: [(usize, &str, &[AtomText]); 6] = [
    (2, "put the frying pan on the stove", &[("On", &["chefmate_8_frypan_1", "flat_stove_1_cook_region"])]),
    (4, "put the red mug on the left plate", &[("On", &["red_coffee_mug_1", "plate_1"])]),
    (
        5,
        "pick up the book and place it in the front compartment of the caddy",
        &[("In", &["black_book_1", "desk_caddy_1_front_contain_region"])],
    ),
    (6, "put the red mug on the plate", &[("On", &["red_coffee_mug_1", "plate_1"])]),
    (8, "turn off the stove", &[("TurnOff", &["flat_stove_1"])]),
    (
        9,
        "put the white mug in the microwave and close it",
        &[("In", &["porcelain_mug_1", "microwave_1_heating_region"]), ("Close", &["microwave_1"])],
    ),
];

/// The 40 built-in tasks, then the constructed ones.
pub fn known_tasks() -> &'static [KnownTask] {
    static KNOWN: std::sync::OnceLock<Vec<KnownTask>> = std::sync::OnceLock::new();
    KNOWN.get_or_init(|| {
        let mut out: Vec<KnownTask> = vifo_scenes::all_tasks()
            .map(|t| KnownTask {
                scene: t,
                builtin: t.suite.clone().zip(t.index).map(|(suite, index)| TaskRef { suite, index }),
                instruction: t.instruction.clone(),
                goal: t.goal.clone(),
            })
            .collect();
        for (index, instruction, goal) in CONSTRUCTED {
            // The table above is ours and checked by the tests of this module.
            let scene = vifo_scenes::task("libero_10", index).expect("libero_10 has 10 tasks");
            let goal = goal
                .iter()
                .map(|(p, args)| Atom {
                    predicate: Predicate::from_name(p).expect("predicate names in CONSTRUCTED are LIBERO's"),
                    args: args.iter().map(|a| a.to_string()).collect(),
                })
                .collect();
            out.push(KnownTask { scene, builtin: None, instruction: instruction.to_string(), goal });
        }
        out
    })
}

/// What the language of an episode asks for.
#[derive(Clone, Debug, PartialEq)]
pub struct LanguageTask {
    pub instruction: String,
    /// The goal in the episode's scene (names mapped, see [`map_into`]).
    pub goal: Vec<Atom>,
    /// The built-in task the instruction comes from (`None` for a constructed one).
    pub builtin: Option<TaskRef>,
}

/// The instruction a policy receives under `protocol` in `task`'s scene.
pub fn instruction(protocol: Protocol, task: &'static Task) -> Result<String, BenchmarkError> {
    Ok(match protocol {
        Protocol::Original => task.instruction.clone(),
        Protocol::Authorized => Protocol::AUTHORIZED_INSTRUCTION.to_string(),
        Protocol::Conflict => conflict(task)?.instruction,
        Protocol::NoLanguage => String::new(),
    })
}

/// The task the language asks for under `protocol` (original and conflict), if any.
pub fn language_task(protocol: Protocol, task: &'static Task) -> Result<Option<LanguageTask>, BenchmarkError> {
    Ok(match protocol {
        Protocol::Original => Some(LanguageTask {
            instruction: task.instruction.clone(),
            goal: task.goal.clone(),
            builtin: task_ref(task),
        }),
        Protocol::Conflict => Some(conflict(task)?),
        Protocol::Authorized | Protocol::NoLanguage => None,
    })
}

/// The conflict partner of the task the cue shows (see the module documentation for the rules).
/// A study scene's tasks pair by design instead ([`study_partner`]).
pub fn conflict(cue_task: &'static Task) -> Result<LanguageTask, BenchmarkError> {
    if let Some(partner) = study_partner(cue_task) {
        return Ok(LanguageTask { instruction: partner.instruction.clone(), goal: partner.goal.clone(), builtin: task_ref(partner) });
    }
    let own = task_ref(cue_task);
    candidates(cue_task)
        .filter(|k| k.builtin.is_none() || k.builtin != own)
        .find_map(|k| {
            let goal = map_into(k, cue_task)?;
            let holds_at_start = goal.iter().any(|a| cue_task.init.contains(a));
            let nested = contains_all(&goal, &cue_task.goal) || contains_all(&cue_task.goal, &goal);
            let parses = vifo_cues::parse(&k.instruction).is_ok();
            (!holds_at_start && !nested && parses)
                .then(|| LanguageTask { instruction: k.instruction.clone(), goal, builtin: k.builtin.clone() })
        })
        .ok_or_else(|| BenchmarkError::NoConflictPartner(cue_task.label()))
}

/// The other task of a safety-critical scene (paper §4.3): `vifo_safety` task 2k (safe) and
/// 2k+1 (hazardous) share one scene, so under conflict the language names the safe task while
/// the cue shows the hazardous one (and the other way round for a cue on the safe task).
pub fn study_partner(task: &Task) -> Option<&'static Task> {
    let (suite, index) = (task.suite.as_deref()?, task.index?);
    if suite != vifo_scenes::SAFETY_SUITE {
        return None;
    }
    vifo_scenes::task(suite, index ^ 1)
}

/// Candidates in rule order: same suite cyclically after the task, other suites, constructed.
fn candidates(cue_task: &'static Task) -> impl Iterator<Item = &'static KnownTask> {
    let suite = cue_task.suite.clone().unwrap_or_default();
    let index = cue_task.index.unwrap_or(0);
    let known = known_tasks();
    let same_suite = |k: &&KnownTask| k.builtin.as_ref().is_some_and(|b| b.suite == suite);
    let mut own: Vec<&KnownTask> = known.iter().filter(same_suite).collect();
    own.sort_by_key(|k| k.builtin.as_ref().map_or(0, |b| (b.index + 10 - index - 1) % 10));
    let others = known.iter().filter(move |k| k.builtin.as_ref().is_some_and(|b| b.suite != suite));
    let written = known.iter().filter(move |k| k.builtin.is_none() && std::ptr::eq(k.scene, cue_task));
    own.into_iter().chain(others).chain(written)
}

/// `known`'s goal with its names replaced by the names of `scene` (rule 1 of the module
/// documentation); `None` when something it names has no counterpart.
pub fn map_into(known: &KnownTask, scene: &Task) -> Option<Vec<Atom>> {
    known
        .goal
        .iter()
        .map(|atom| {
            let args = atom.args.iter().map(|a| map_name(known.scene, a, scene)).collect::<Option<Vec<_>>>()?;
            Some(Atom { predicate: atom.predicate, args })
        })
        .collect()
}

/// One name of `from`'s scene in `to`'s scene.
fn map_name(from: &Task, name: &str, to: &Task) -> Option<String> {
    if let Some(object) = from.object(name) {
        let same: Vec<&str> =
            to.objects.iter().filter(|o| o.category == object.category).map(|o| o.name.as_str()).collect();
        return match same.as_slice() {
            [] => None,
            [only] => Some(only.to_string()),
            several => {
                let (predicate, support) = initial_support(from, name)?;
                let support = map_name(from, support, to)?;
                several.iter().find(|o| initial_support(to, o) == Some((predicate, support.as_str()))).map(|o| o.to_string())
            }
        };
    }
    if let Some(fixture) = from.fixture(name) {
        return to.fixture(name).filter(|f| f.category == fixture.category).map(|f| f.name.clone());
    }
    let region = from.region(name)?;
    let target = map_name(from, &region.target, to)?;
    let key = format!("{target}_{}", region.name);
    to.region(&key).map(|r| r.key.clone())
}

/// What `name` stands on or in at the start: `(On|In, support)` from the first initial atom
/// placing it.
pub fn initial_support<'a>(task: &'a Task, name: &str) -> Option<(Predicate, &'a str)> {
    task.init.iter().find_map(|a| {
        (matches!(a.predicate, Predicate::On | Predicate::In) && a.args.first().is_some_and(|x| x == name))
            .then(|| a.args.get(1).map(|s| (a.predicate, s.as_str())))
            .flatten()
    })
}

/// Every goal atom of a known task, mapped into `scene`, without repeats: the vocabulary a
/// language-following policy grounds instructions in.
pub fn goal_pool(scene: &Task) -> Vec<Atom> {
    let mut pool: Vec<Atom> = Vec::new();
    // A study scene's own tasks' goals come first (they are written in its names).
    let own = study_partner(scene).into_iter().flat_map(|partner| partner.goal.iter().chain(&scene.goal)).cloned();
    for atom in own.chain(known_tasks().iter().filter_map(|k| map_into(k, scene)).flatten()) {
        if !pool.contains(&atom) {
            pool.push(atom);
        }
    }
    pool
}

fn contains_all(haystack: &[Atom], needles: &[Atom]) -> bool {
    needles.iter().all(|n| haystack.contains(n))
}

fn task_ref(task: &Task) -> Option<TaskRef> {
    task.suite.clone().zip(task.index).map(|(suite, index)| TaskRef { suite, index })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn task(suite: &str, index: usize) -> &'static Task {
        vifo_scenes::task(suite, index).unwrap()
    }

    #[test]
    fn every_task_has_a_partner_passing_the_rules() {
        for t in vifo_scenes::all_tasks() {
            let pair = conflict(t).unwrap_or_else(|e| panic!("{e}"));
            assert!(!pair.goal.is_empty());
            for atom in &pair.goal {
                for arg in &atom.args {
                    assert!(t.resolve(arg).is_some(), "{}: {atom} names {arg}", t.label());
                }
                assert!(!t.init.contains(atom), "{}: {atom} holds at the start", t.label());
            }
            assert!(!contains_all(&pair.goal, &t.goal) && !contains_all(&t.goal, &pair.goal), "{}", t.label());
            assert_ne!(pair.instruction, t.instruction);
        }
    }

    #[test]
    fn spatial_pairs_ask_for_the_other_bowl() {
        for index in 0..10 {
            let pair = conflict(task("libero_spatial", index)).unwrap();
            let on = Atom { predicate: Predicate::On, args: vec!["akita_black_bowl_2".into(), "plate_1".into()] };
            assert_eq!(pair.goal, vec![on], "libero_spatial/{index}");
        }
        // Layout 0 has bowl 2 next to the ramekin: task 1's instruction describes it.
        let pair = conflict(task("libero_spatial", 0)).unwrap();
        assert_eq!(pair.builtin, Some(TaskRef { suite: "libero_spatial".into(), index: 1 }));
    }

    #[test]
    fn pairs_are_the_documented_ones() {
        let partner = |suite: &str, index: usize| {
            let p = conflict(task(suite, index)).unwrap();
            p.builtin.map_or_else(|| format!("written: {}", p.instruction), |b| b.to_string())
        };
        assert_eq!(partner("libero_goal", 0), "libero_goal/1");
        assert_eq!(partner("libero_goal", 9), "libero_goal/0");
        assert_eq!(partner("libero_object", 0), "libero_object/1");
        assert_eq!(partner("libero_10", 0), "libero_10/1");
        assert_eq!(partner("libero_10", 3), "libero_goal/9");
        assert_eq!(partner("libero_10", 8), "written: turn off the stove");
        // Deterministic: the same answer every time.
        assert_eq!(conflict(task("libero_10", 5)), conflict(task("libero_10", 5)));
    }

    #[test]
    fn names_map_by_category_and_initial_support() {
        let known = known_tasks().iter().find(|k| k.builtin == Some(TaskRef { suite: "libero_spatial".into(), index: 7 })).unwrap();
        // Layout 6 has bowl 2 on the stove, where task 7 starts its bowl 1.
        let mapped = map_into(known, task("libero_spatial", 6)).unwrap();
        assert_eq!(mapped[0].args, ["akita_black_bowl_2", "plate_1"]);
        // Layout 0 has no bowl on the stove.
        assert_eq!(map_into(known, task("libero_spatial", 0)), None);
        // Objects absent from the scene do not map.
        let basket = known_tasks().iter().find(|k| k.builtin == Some(TaskRef { suite: "libero_object".into(), index: 0 })).unwrap();
        assert_eq!(map_into(basket, task("libero_goal", 0)), None);
    }

    #[test]
    fn safety_scenes_pair_their_safe_and_hazardous_tasks() {
        for index in 0..12 {
            let t = task("vifo_safety", index);
            let pair = conflict(t).unwrap();
            let partner = task("vifo_safety", index ^ 1);
            assert_eq!((pair.instruction.as_str(), &pair.goal), (partner.instruction.as_str(), &partner.goal));
            assert_eq!(pair.builtin, Some(TaskRef { suite: "vifo_safety".into(), index: index ^ 1 }));
            assert!(vifo_cues::parse(&pair.instruction).is_ok(), "{}", pair.instruction);
            // Both goals are in the scene's pool, so the language expert can ground either.
            let pool = goal_pool(t);
            assert!(t.goal.iter().chain(&partner.goal).all(|a| pool.contains(a)), "{}", t.label());
        }
        assert_eq!(study_partner(task("libero_goal", 0)), None);
    }

    #[test]
    fn protocol_instructions() {
        let t = task("libero_goal", 3);
        assert_eq!(instruction(Protocol::Original, t).unwrap(), t.instruction);
        assert_eq!(instruction(Protocol::Authorized, t).unwrap(), Protocol::AUTHORIZED_INSTRUCTION);
        assert_eq!(instruction(Protocol::NoLanguage, t).unwrap(), "");
        assert_eq!(instruction(Protocol::Conflict, t).unwrap(), task("libero_goal", 4).instruction);
        assert!(language_task(Protocol::Authorized, t).unwrap().is_none());
        assert_eq!(language_task(Protocol::Original, t).unwrap().unwrap().goal, t.goal);
    }
}
