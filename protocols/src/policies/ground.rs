//! From an instruction to goal atoms of a scene, for the language-following expert.
//!
//! The cue parser splits the instruction into steps (source, relation, target, and a locating
//! qualifier such as "next to the ramekin"). Each step is matched against the scene's goal pool
//! ([`goal_pool`]: the goal atoms of the built-in and constructed tasks that exist in this
//! scene, i.e. the vocabulary of LIBERO's goals) and takes the best atom by, in order:
//!
//! 1. name match — twice the words the phrase shares with the id and the instruction-style
//!    name of what it names (`porcelain_mug_1` is "white mug"), minus the words of that name
//!    the phrase does not say ("white mug" prefers the white mug to the yellow and white one);
//! 2. the predicate the relation states ("on" prefers `On`, "in" prefers `In`; LIBERO writes
//!    "in the bowl" as `On`, which is still allowed);
//! 3. for objects of one category (two black bowls), the qualifier against where each one
//!    starts: its words against the initial support, plus one when its preposition ("in",
//!    "on") is the support's predicate.
//!
//! A plural source ("both moka pots") takes every best atom with a distinct source. Steps
//! that match nothing are dropped (LIBERO's goals often leave out a preparatory step: "open
//! the top drawer and put the bowl inside" is only `In`); an instruction that parses to
//! nothing matchable grounds to `None`, and the expert then does nothing.

use std::collections::BTreeSet;

use vifo_cues::{Relation, Step};
use vifo_scenes::Task;
use vifo_scenes::task::{Atom, Predicate};

use crate::benchmark::instances::human_name;
use crate::benchmark::language::{goal_pool, initial_support};

/// The goal atoms `instruction` asks for in `scene`, or `None` when it names no task there.
pub fn ground(instruction: &str, scene: &Task) -> Option<Vec<Atom>> {
    let parsed = vifo_cues::parse(instruction).ok()?;
    let pool = goal_pool(scene);
    let mut used = vec![false; pool.len()];
    let mut out = Vec::new();
    for step in &parsed.steps {
        let scored: Vec<(Score, usize)> = (0..pool.len())
            .filter(|&i| !used[i])
            .filter_map(|i| score(step, &pool[i], scene).map(|s| (s, i)))
            .collect();
        let Some(best) = scored.iter().map(|(s, _)| *s).max() else { continue };
        let mut sources = BTreeSet::new();
        for &(_, i) in scored.iter().filter(|(s, _)| *s == best) {
            if sources.insert(pool[i].args[0].clone()) {
                used[i] = true;
                out.push(pool[i].clone());
            }
            if !is_plural(&step.source) {
                break;
            }
        }
    }
    (!out.is_empty()).then_some(out)
}

/// (name match, predicate agreement, qualifier match); compared in that order.
type Score = (i32, i32, i32);

fn score(step: &Step, atom: &Atom, scene: &Task) -> Option<Score> {
    let exact = match (atom.predicate, step.relation) {
        (Predicate::Open, Relation::Open)
        | (Predicate::Close, Relation::Close)
        | (Predicate::TurnOn, Relation::TurnOn)
        | (Predicate::TurnOff, Relation::TurnOff) => 0,
        (Predicate::On, r) if r.moves_source() => i32::from(r == Relation::On),
        (Predicate::In, r) if r.moves_source() => i32::from(r == Relation::In),
        _ => return None,
    };
    let source = name_match(&step.source, &atom.args[0], scene)?;
    let target = match (&step.target, atom.args.get(1)) {
        (Some(phrase), Some(id)) => name_match(phrase, id, scene)?,
        (None, None) => 0,
        _ => return None,
    };
    let qualifier = step.source_qualifier.as_deref().map_or(0, |q| qualifier_match(q, &atom.args[0], scene));
    Some((source + target, exact, qualifier))
}

/// Twice the shared words minus the unsaid words of the name; `None` when nothing is shared.
fn name_match(phrase: &str, id: &str, scene: &Task) -> Option<i32> {
    let said = words(phrase);
    let (vocabulary, name) = vocabulary(id, scene);
    let shared = said.iter().filter(|w| vocabulary.contains(*w)).count() as i32;
    let unsaid = name.iter().filter(|w| !said.contains(*w)).count() as i32;
    (shared > 0).then_some(2 * shared - unsaid)
}

/// How well a locating phrase describes where `id` starts in `scene`.
fn qualifier_match(qualifier: &str, id: &str, scene: &Task) -> i32 {
    let Some((predicate, support)) = initial_support(scene, id) else { return 0 };
    let said = words(qualifier);
    let (vocabulary, _) = vocabulary(support, scene);
    let shared = said.iter().filter(|w| vocabulary.contains(*w)).count() as i32;
    let preposition = match qualifier.split_whitespace().next() {
        Some("in" | "inside") => predicate == Predicate::In,
        Some("on") => predicate == Predicate::On,
        _ => false,
    };
    shared + i32::from(preposition)
}

/// The words that may name `id` (its own and its category's instruction-style name) and the
/// words of the name a phrase should say (the instruction-style name, else the id's).
fn vocabulary(id: &str, scene: &Task) -> (BTreeSet<String>, BTreeSet<String>) {
    let own = words(id);
    let human = scene.entity(id).and_then(|e| human_name(&e.category)).map(|n| words(&n));
    match human {
        Some(human) => (own.union(&human).cloned().collect(), human),
        None => (own.clone(), own),
    }
}

/// Lower-case words of a phrase or id, singular, without articles and numbers.
fn words(text: &str) -> BTreeSet<String> {
    text.split(|c: char| !c.is_ascii_alphanumeric())
        .map(str::to_ascii_lowercase)
        .filter(|w| !w.is_empty() && !w.chars().all(|c| c.is_ascii_digit()))
        .filter(|w| !matches!(w.as_str(), "the" | "a" | "an" | "of" | "and" | "both"))
        .map(|w| singular(&w).to_string())
        .collect()
}

fn singular(word: &str) -> &str {
    if word.len() > 3 && word.ends_with('s') && !word.ends_with("ss") { &word[..word.len() - 1] } else { word }
}

fn is_plural(phrase: &str) -> bool {
    phrase.rsplit(' ').next().is_some_and(|w| singular(w) != w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::benchmark::language::conflict;

    fn same_atoms(a: &[Atom], b: &[Atom]) -> bool {
        a.len() == b.len() && a.iter().all(|x| b.contains(x))
    }

    #[test]
    fn every_instruction_grounds_to_its_goal() {
        for task in vifo_scenes::all_tasks() {
            let got = ground(&task.instruction, task).unwrap_or_else(|| panic!("{}: nothing grounded", task.label()));
            // libero_10/8's goal also keeps the stove on, which the words do not say (and which
            // holds from the start).
            let expected: Vec<Atom> = if task.instruction == "put both moka pots on the stove" {
                task.goal.iter().filter(|a| a.predicate != Predicate::TurnOn).cloned().collect()
            } else {
                task.goal.clone()
            };
            assert!(same_atoms(&got, &expected), "{}: {got:?} vs {expected:?}", task.label());
        }
    }

    #[test]
    fn every_conflict_instruction_grounds_to_the_conflict_goal() {
        for task in vifo_scenes::all_tasks() {
            let pair = conflict(task).unwrap();
            let got = ground(&pair.instruction, task).unwrap_or_else(|| panic!("{}: nothing grounded", task.label()));
            assert!(same_atoms(&got, &pair.goal), "{}: {:?} grounds to {got:?}, not {:?}", task.label(), pair.instruction, pair.goal);
        }
    }

    #[test]
    fn sentences_without_a_task_ground_to_nothing() {
        let scene = vifo_scenes::task("libero_goal", 0).unwrap();
        assert_eq!(ground(crate::Protocol::AUTHORIZED_INSTRUCTION, scene), None);
        assert_eq!(ground("", scene), None);
        assert_eq!(ground("put the alphabet soup in the basket", scene), None);
    }
}
