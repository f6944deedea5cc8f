//! BDDL import: reads LIBERO's task files (all of them, LIBERO-90 included) into a [`Task`].
//!
//! Follows what LIBERO's `bddl_utils.robosuite_parse_problem` accepts, with its quirks:
//! identifiers are case-insensitive (LIBERO lower-cases the file), region keys are
//! `target + "_" + name`, regions whose target is not declared are dropped, and a goal may be a
//! single atom instead of `(And ...)`. Object categories are not checked here, so files naming
//! assets we do not model still parse. It is stricter where LIBERO would fail later or silently
//! lose data: unknown sections or predicates, wrong arities, names that are neither an object,
//! a fixture nor a region key, repeated sections, and a category given in two groups (LIBERO
//! keys groups by category, so the first would vanish) are errors.
//!
//! Every error is a [`BddlError`] naming the file, line, column, what was expected and what was
//! found. No input makes the parser panic.

mod error;
mod grammar;
mod lexer;
mod resolve;

pub use error::BddlError;

use crate::task::Task;
use std::path::Path;

/// Parses BDDL `text`. `path` names the file in errors, and its stem becomes [`Task::name`]
/// (from which [`Task::instruction`] is derived). `suite` and `index` are left unset: they are
/// the caller's to know.
pub fn parse(text: &str, path: &Path) -> Result<Task, BddlError> {
    let file = path.display().to_string();
    let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let raw = grammar::read(text, &file)?;
    resolve::resolve(raw, &name, &file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::{Predicate, ProblemClass};

    /// A made-up task in LIBERO's style (not one of LIBERO's files).
    const CUP_TASK: &str = "\
(define (problem LIBERO_Kitchen_Tabletop_Manipulation)
  (:domain robosuite)
  (:language Put the red cup  on the tray) ; comment
  (:regions
    (cup_init_region
        (:target kitchen_table)
        (:ranges (
            (-0.1 0.05 -0.05 0.1)
          )
        )
        (:yaw_rotation (
            (0.0 3.141592653589793)
          )
        )
    )
    (tray_init_region
        (:target kitchen_table)
        (:ranges ((0.060000000000000005 -0.2 0.1 -0.15) (0.2 0.2 0.3 0.3)))
        (:rgba (0.1 0.2 0.3 1))
    )
    (cook_region
        (:target flat_stove_1)
    )
    (left_region
        (:target dish_rack_1)
    )
  )
  (:fixtures
    kitchen_table - kitchen_table
    flat_stove_1 - flat_stove
  )
  (:objects
    red_cup_1 red_cup_2 - red_cup
    Tray_1 - tray
  )
  (:obj_of_interest
    red_cup_1
    flat_stove_1_cook_region
  )
  (:init
    (On red_cup_1 kitchen_table_cup_init_region)
    (On tray_1 kitchen_table_tray_init_region)
    (Turnon flat_stove_1)
  )
  (:goal
    (And (On red_cup_1 tray_1) (TURNOFF flat_stove_1))
  )
)
";

    fn parse_cup(text: &str) -> Result<Task, BddlError> {
        parse(text, Path::new("tasks/KITCHEN_SCENE3_put_the_red_cup_on_the_tray.bddl"))
    }

    #[test]
    fn reads_a_complete_file() {
        let task = parse_cup(CUP_TASK).unwrap();
        assert_eq!(task.name, "KITCHEN_SCENE3_put_the_red_cup_on_the_tray");
        assert_eq!(task.instruction, "put the red cup on the tray");
        assert_eq!(task.language, "Put the red cup on the tray");
        assert_eq!(task.problem, ProblemClass::KitchenTabletop);
        assert_eq!((task.suite.as_deref(), task.index), (None, None));
        let names = |v: &[crate::task::Entity]| v.iter().map(|e| format!("{}:{}", e.name, e.category)).collect::<Vec<_>>();
        assert_eq!(names(&task.fixtures), ["kitchen_table:kitchen_table", "flat_stove_1:flat_stove"]);
        assert_eq!(names(&task.objects), ["red_cup_1:red_cup", "red_cup_2:red_cup", "tray_1:tray"]);
        // dish_rack_1 is not declared, so its region is dropped.
        let keys: Vec<&str> = task.regions.iter().map(|r| r.key.as_str()).collect();
        assert_eq!(keys, ["kitchen_table_cup_init_region", "kitchen_table_tray_init_region", "flat_stove_1_cook_region"]);
        let cup = &task.regions[0];
        assert_eq!(cup.ranges, [[-0.1, 0.05, -0.05, 0.1]]);
        assert_eq!(cup.yaw_rotation, Some([0.0, std::f64::consts::PI]));
        let tray = &task.regions[1];
        assert_eq!(tray.ranges[0][0].to_bits(), 0.060000000000000005f64.to_bits());
        assert_eq!(tray.ranges.len(), 2);
        assert_eq!(tray.rgba, Some([0.1, 0.2, 0.3, 1.0]));
        assert!(!task.regions[2].is_ranged());
        assert_eq!(task.obj_of_interest, ["red_cup_1", "flat_stove_1_cook_region"]);
        let init: Vec<String> = task.init.iter().map(|a| a.to_string()).collect();
        assert_eq!(
            init,
            ["(On red_cup_1 kitchen_table_cup_init_region)", "(On tray_1 kitchen_table_tray_init_region)", "(TurnOn flat_stove_1)"]
        );
        assert_eq!(task.goal[1].predicate, Predicate::TurnOff);
        assert_eq!(task.goal[0].args, ["red_cup_1", "tray_1"]);
    }

    #[test]
    fn a_goal_may_be_a_single_atom_and_sections_may_be_omitted() {
        let text = "(define (problem libero_floor_manipulation) (:fixtures floor - floor) (:objects a_1 - box) (:goal (up a_1)))";
        let task = parse(text, Path::new("lift_the_box.bddl")).unwrap();
        assert_eq!(task.problem, ProblemClass::Floor);
        assert_eq!(task.goal.len(), 1);
        assert_eq!(task.goal[0].to_string(), "(Up a_1)");
        assert_eq!(task.language, "");
        assert!(task.init.is_empty() && task.regions.is_empty());
    }

    fn error_for(text: &str) -> BddlError {
        parse(text, Path::new("bad.bddl")).expect_err("the input is malformed")
    }

    fn replaced(from: &str, to: &str) -> BddlError {
        assert!(CUP_TASK.contains(from), "test edit {from:?} must apply");
        error_for(&CUP_TASK.replacen(from, to, 1))
    }

    #[test]
    fn truncation_names_the_open_section() {
        let cut = CUP_TASK.find("Tray_1").unwrap();
        let err = error_for(&CUP_TASK[..cut]);
        assert_eq!(err.to_string(), format!("bad.bddl:34:5: expected a name, '-' or ')' closing (:objects, found end of file"));
        let err = error_for(&CUP_TASK[..CUP_TASK.len() - 2]);
        assert_eq!((err.expected.as_str(), err.found.as_str()), ("'(' starting a section or ')' closing (define", "end of file"));
    }

    #[test]
    fn structural_errors_say_what_was_expected_where() {
        let err = replaced("(problem LIBERO_Kitchen_Tabletop_Manipulation)", "(problem LIBERO_Garage)");
        assert_eq!((err.line, err.column), (1, 18));
        assert!(err.expected.starts_with("a LIBERO problem class ("), "{err}");
        assert_eq!(err.found, "'LIBERO_Garage'");

        let err = replaced("(:domain robosuite)", "(:domain igibson)");
        assert_eq!((err.line, err.column, err.found.as_str()), (2, 12, "'igibson'"));

        let err = replaced("(:obj_of_interest", "(:objects_of_interest");
        assert!(err.expected.starts_with("a section name ("), "{err}");

        let err = replaced("Tray_1 - tray", "Tray_1 tray_2");
        assert_eq!(err.expected, "'- <category>' after 'Tray_1 tray_2'");

        let err = replaced("Tray_1 - tray", "Tray_1 - red_cup");
        assert!(err.expected.contains("all 'red_cup' names in one group"), "{err}");

        let err = replaced("(0.2 0.2 0.3 0.3)", "(0.2 0.2 0.3)");
        assert_eq!((err.expected.as_str(), err.found.as_str()), ("a number (x_min, y_min, x_max, y_max)", "')'"));

        let err = replaced("(0.2 0.2 0.3 0.3)", "(0.4 0.2 0.3 0.3)");
        assert_eq!(err.found, "(0.4 0.2 0.3 0.3)");

        let err = replaced("(:rgba (0.1 0.2 0.3 1))", "(:rgba (0.1 0.2 red 1))");
        assert_eq!(err.found, "'red'");

        let err = replaced("(0.0 3.141592653589793)", "(0.0 3.14) (1 2)");
        assert!(err.expected.contains("one range per region"), "{err}");

        let err = replaced("(:target flat_stove_1)", "(:where flat_stove_1)");
        assert!(err.expected.starts_with("a region attribute"), "{err}");

        let err = replaced("(:target flat_stove_1)", "");
        assert_eq!(err.expected, "a (:target NAME) attribute in (cook_region");

        let err = replaced("(:domain robosuite)", "(:domain robosuite) (:domain robosuite)");
        assert_eq!(err.found, "a second (:domain");

        let err = replaced("(:goal", "(:gaol");
        assert!(err.expected.starts_with("a section name"), "{err}");

        let err = error_for(&CUP_TASK.replace(&CUP_TASK[CUP_TASK.find("  (:goal").unwrap()..CUP_TASK.len() - 2], ""));
        assert_eq!(err.expected, "a (:goal ...) section");

        let err = replaced("(And (On red_cup_1 tray_1) (TURNOFF flat_stove_1))", "(And)");
        assert_eq!(err.expected, "at least one goal atom in (And");

        let err = error_for(&format!("{CUP_TASK} (extra)"));
        assert_eq!(err.expected, "end of file after the ')' closing (define");

        let err = error_for("problem");
        assert_eq!(err.to_string(), "bad.bddl:1:1: expected '(' starting (define ...), found 'problem'");

        // A file of one huge word (or of NUL bytes) is named by its start, escaped.
        let err = error_for(&format!("\0\u{1b}{}", "x".repeat(5_000_000)));
        let shown = err.to_string();
        assert!(shown.len() < 300 && shown.contains("\\u{0}\\u{1b}xxx") && shown.ends_with("… (5000004 characters)"), "{shown}");
    }

    #[test]
    fn atoms_are_checked_against_the_declared_names() {
        let err = replaced("(Turnon flat_stove_1)", "(Stack red_cup_1 tray_1)");
        assert_eq!((err.line, err.column), (43, 6));
        assert!(err.expected.starts_with("a predicate LIBERO knows (true, false, in, on, up,"), "{err}");
        assert_eq!(err.found, "'Stack' in (Stack red_cup_1 tray_1)");

        let err = replaced("(On red_cup_1 tray_1)", "(On red_cup_1 tray_9)");
        assert_eq!(err.expected, "an object, fixture or region key as argument 2 of (On red_cup_1 tray_9)");
        assert_eq!((err.line, err.found.as_str()), (46, "'tray_9'"));

        // A negated goal is named as a nested group LIBERO's grammar has no place for.
        let err = replaced("(On red_cup_1 tray_1)", "(Not (On red_cup_1 tray_1))");
        assert!(err.expected.contains("without Not, Or or nesting"), "{err}");
        assert_eq!((err.line, err.found.as_str()), (46, "'(Not (' opening a nested group"));

        let err = replaced("(Turnon flat_stove_1)", "(Turnon flat_stove_1 red_cup_1)");
        assert_eq!((err.expected.as_str(), err.found.as_str()), ("1 argument for TurnOn", "2 in (Turnon flat_stove_1 red_cup_1)"));

        let err = replaced("(On tray_1 kitchen_table_tray_init_region)", "(On tray_1)");
        assert_eq!(err.expected, "2 arguments for On");

        // The dropped region cannot be used.
        let err = replaced("(Turnon flat_stove_1)", "(On red_cup_2 dish_rack_1_left_region)");
        assert_eq!(err.found, "'dish_rack_1_left_region'");

        let err = replaced("flat_stove_1_cook_region\n  )", "stove\n  )");
        assert_eq!(err.expected, "an object, fixture or region key in (:obj_of_interest");

        let err = replaced("red_cup_1 red_cup_2 - red_cup", "red_cup_1 flat_stove_1 - red_cup");
        assert!(err.expected.starts_with("a name not declared before"), "{err}");

        let err = replaced("(left_region", "(cook_region (:target flat_stove_1)) (left_region");
        assert!(err.expected.starts_with("a region key not defined before"), "{err}");
    }

    /// A small deterministic generator (xorshift64) for the mutation test; no dependency needed.
    struct Rng(u64);

    impl Rng {
        fn below(&mut self, n: usize) -> usize {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 % n as u64) as usize
        }
    }

    #[test]
    fn never_panics_on_truncated_or_mutated_input() {
        let chars: Vec<char> = CUP_TASK.chars().collect();
        for cut in 0..=chars.len() {
            let text: String = chars[..cut].iter().collect();
            let result = parse_cup(&text);
            assert_eq!(result.is_ok(), cut == chars.len() || chars[cut..].iter().all(|c| c.is_whitespace()));
        }
        let alphabet = ['(', ')', ' ', '\n', ';', '-', 'a', '0', '.', 'é', ':'];
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut failures = 0;
        for _ in 0..3000 {
            let mut text = chars.clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(text.len());
                match rng.below(3) {
                    0 => {
                        text.remove(at);
                    }
                    1 => text.insert(at, alphabet[rng.below(alphabet.len())]),
                    _ => text[at] = alphabet[rng.below(alphabet.len())],
                }
            }
            let text: String = text.into_iter().collect();
            if let Err(err) = parse_cup(&text) {
                failures += 1;
                assert!(err.line >= 1 && err.column >= 1 && !err.expected.is_empty(), "{err}");
            }
        }
        assert!(failures > 1000, "most mutations must be rejected, got {failures}");
    }
}
