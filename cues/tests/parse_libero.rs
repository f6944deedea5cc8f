//! The expected parse of LIBERO's 40 evaluation instructions (libero_spatial, libero_object,
//! libero_goal, libero_10, in suite order), and their grounding in the goal atoms.

mod common;

use common::FORTY;
use vifo_cues::parse::{GoalAtom, parse, parse_with_goals};

#[test]
fn the_forty_libero_instructions_parse_as_expected() {
    for task in &FORTY {
        let (instruction, _, expected) = task.row;
        let parsed = parse(instruction).unwrap_or_else(|e| panic!("{e}"));
        let got: Vec<_> = parsed
            .steps
            .iter()
            .map(|s| (s.source.as_str(), s.source_qualifier.as_deref(), s.relation, s.target.as_deref()))
            .collect();
        assert_eq!(got, expected, "{}/{}: {instruction}", task.suite, task.index);
        assert_eq!(
            (parsed.source.as_str(), parsed.relation, parsed.target.as_deref()),
            (expected[0].0, expected[0].2, expected[0].3)
        );
    }
}

#[test]
fn exactly_two_of_the_forty_move_no_object() {
    let static_tasks: Vec<&str> =
        FORTY.iter().map(|t| t.row.0).filter(|i| !parse(i).unwrap().moves_an_object()).collect();
    assert_eq!(static_tasks, ["open the middle drawer of the cabinet", "turn on the stove"]);
}

#[test]
fn goal_atoms_ground_every_step_that_has_one() {
    for task in &FORTY {
        let (instruction, goals, _) = task.row;
        let goals: Vec<GoalAtom> = goals.iter().map(|g| g.parse().unwrap()).collect();
        let parsed = parse_with_goals(instruction, &goals).unwrap();
        for atom in &goals {
            let used = parsed.steps.iter().any(|s| s.source_id.as_ref() == atom.args.first());
            // The only atom an instruction does not mention: the stove of "put both moka pots".
            let unmentioned = instruction.starts_with("put both moka pots") && atom.predicate == "Turnon";
            assert!(used || unmentioned, "{instruction}: {atom:?} not used in {:?}", parsed.steps);
        }
        for step in &parsed.steps {
            if step.source_id.is_some() && step.target.is_some() {
                assert!(step.target_id.is_some(), "{instruction}: {step:?}");
            }
        }
    }
}
