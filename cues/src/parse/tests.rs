//! Parser behaviour beyond the LIBERO tables (those are in `tests/parse_libero.rs`): other
//! phrasings, grounding details, errors and JSON.

use super::*;

fn atoms(strings: &[&str]) -> Vec<GoalAtom> {
    strings.iter().map(|s| s.parse().unwrap()).collect()
}

#[test]
fn goal_atoms_need_balanced_parentheses_a_known_predicate_and_its_arguments() {
    assert_eq!("(On akita_black_bowl_1 plate_1)".parse(), Ok(GoalAtom::new("On", &["akita_black_bowl_1", "plate_1"])));
    assert_eq!(" Open  drawer_1 ".parse(), Ok(GoalAtom::new("Open", &["drawer_1"])));
    for (bad, why) in [
        ("(On bowl plate", "without its closing"),
        ("(On bowl plate))) junk", "nothing before or after"),
        ("(On bogus)", "On takes 2 arguments, found 1"),
        ("(Open a b)", "Open takes 1 argument, found 2"),
        ("(Foo x y)", "unknown predicate \"Foo\""),
        ("()", "found nothing"),
    ] {
        let err = bad.parse::<GoalAtom>().unwrap_err();
        assert!(err.contains(why), "{bad}: {err}");
    }
}

#[test]
fn goal_atoms_from_json_are_checked_as_from_text() {
    let read = |json: &str| serde_json::from_str::<GoalAtom>(json).map_err(|e| e.to_string());
    assert_eq!(read(r#"{"predicate": "On", "args": ["bowl_1", "plate_1"]}"#), Ok(GoalAtom::new("On", &["bowl_1", "plate_1"])));
    for (bad, why) in [
        (r#"{"predicate": "On", "args": ["bowl_1"]}"#, "On takes 2 arguments, found 1"),
        (r#"{"predicate": "Stack", "args": ["a", "b"]}"#, "unknown predicate \"Stack\""),
        (r#"{"predicate": "Open", "args": ["top drawer"]}"#, "single names"),
        (r#"{"predicate": "Open", "args": [""]}"#, "single names"),
    ] {
        let err = read(bad).unwrap_err();
        assert!(err.contains(why), "{bad}: {err}");
    }
}

#[test]
fn names_ground_steps_without_goal_atoms() {
    let mut parsed = parse("put the cream cheese in the bowl").unwrap();
    ground_to_names(&mut parsed.steps, &["plate_1", "akita_black_bowl_1", "cream_cheese_1", "flat_stove_1"]);
    assert_eq!(parsed.steps[0].source_id.as_deref(), Some("cream_cheese_1"));
    assert_eq!(parsed.steps[0].target_id.as_deref(), Some("akita_black_bowl_1"));
}

#[test]
fn grounding_picks_the_right_mug_and_splits_plural_sources() {
    let mugs = parse_with_goals(
        "put the white mug on the left plate and put the yellow and white mug on the right plate",
        &atoms(&["(On porcelain_mug_1 plate_1)", "(On white_yellow_mug_1 plate_2)"]),
    )
    .unwrap();
    assert_eq!(mugs.steps[0].source_id.as_deref(), Some("porcelain_mug_1"));
    assert_eq!(mugs.steps[0].target_id.as_deref(), Some("plate_1"));
    assert_eq!(mugs.steps[1].source_id.as_deref(), Some("white_yellow_mug_1"));
    assert_eq!(mugs.steps[1].target_id.as_deref(), Some("plate_2"));

    let pots = parse_with_goals(
        "put both moka pots on the stove",
        &atoms(&[
            "(On moka_pot_1 flat_stove_1_cook_region)",
            "(On moka_pot_2 flat_stove_1_cook_region)",
            "(Turnon flat_stove_1)",
        ]),
    )
    .unwrap();
    let ids: Vec<_> = pots.steps.iter().map(|s| s.source_id.as_deref().unwrap()).collect();
    assert_eq!(ids, ["moka_pot_1", "moka_pot_2"]);

    let drawer = parse_with_goals(
        "put the black bowl in the bottom drawer of the cabinet and close it",
        &atoms(&["(Close white_cabinet_1_bottom_region)", "(In akita_black_bowl_1 white_cabinet_1_bottom_region)"]),
    )
    .unwrap();
    assert_eq!(drawer.steps[1].source_id.as_deref(), Some("white_cabinet_1_bottom_region"));
}

#[test]
fn task_names_become_instructions() {
    assert_eq!(
        text::instruction_from_task_name("KITCHEN_SCENE10_close_the_top_drawer_of_the_cabinet"),
        "close the top drawer of the cabinet"
    );
    assert_eq!(text::instruction_from_task_name("put_the_bowl_on_the_plate"), "put the bowl on the plate");
    assert_eq!(parse("Put the Bowl on the Plate.").unwrap().instruction, "put the bowl on the plate");
}

#[test]
fn other_phrasings_of_the_closed_relation_set() {
    let cases: &[(&str, Relation, Option<&str>)] = &[
        ("turn off the stove", Relation::TurnOff, None),
        ("turn the stove off", Relation::TurnOff, None),
        ("close the microwave", Relation::Close, None),
        ("put the frying pan under the cabinet shelf", Relation::Under, Some("cabinet shelf")),
        ("put the red mug to the left of the plate", Relation::LeftOf, Some("plate")),
        ("put the mug in front of the plate", Relation::FrontOf, Some("plate")),
        ("put the mug next to the plate", Relation::NextTo, Some("plate")),
        ("put the mug behind the plate", Relation::Behind, Some("plate")),
        ("pick up the book", Relation::PickUp, None),
        (
            "stack the black bowl at the front on the black bowl in the middle",
            Relation::On,
            Some("black bowl in the middle"),
        ),
    ];
    for (instruction, relation, target) in cases {
        let parsed = parse(instruction).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((parsed.relation, parsed.target.as_deref()), (*relation, *target), "{instruction}");
    }
    let stacked = parse("stack the left bowl on the right bowl and place them in the tray").unwrap();
    let got: Vec<_> = stacked.steps.iter().map(|s| (s.source.as_str(), s.relation, s.target.as_deref())).collect();
    assert_eq!(
        got,
        [
            ("left bowl", Relation::On, Some("right bowl")),
            ("left bowl", Relation::In, Some("tray")),
            ("right bowl", Relation::In, Some("tray"))
        ]
    );
    let qualified = parse("put the butter at the back in the top drawer of the cabinet and close it").unwrap();
    assert_eq!(qualified.steps[0].source_qualifier.as_deref(), Some("at the back"));
    assert_eq!(qualified.steps[1].source, "top drawer of the cabinet");
}

#[test]
fn unknown_phrasing_is_a_clear_error() {
    let cases: &[(&str, usize, &str)] = &[
        ("", 0, "an instruction"),
        ("fly the bowl to the moon", 0, "a verb"),
        ("put the bowl", 12, "a placement preposition"),
        ("put the bowl on", 15, "an object name"),
        ("turn the stove", 5, "'on' or 'off'"),
        ("pick the bowl", 5, "'up'"),
        ("put it on the plate", 0, "an earlier object for 'it'"),
        ("put the bowl on the plate and", 29, "a verb after 'and'"),
        ("put the bowl on the plate & close it", 26, "a letter"),
        ("open", 4, "an object name"),
        // Read wrongly before (target "plate and the mug on the plate", source "mug and the
        // plate", "bowl -> bowl"), now refused.
        ("put the bowl on the plate and the mug on the plate", 30, "a verb after 'and'"),
        ("put both the bowl and the mug and the plate in the basket", 30, "two objects after 'both'"),
        ("pick up the bowl and put it in them", 21, "a target other than the bowl"),
    ];
    for (instruction, position, expected) in cases {
        let err = parse(instruction).expect_err(instruction);
        assert_eq!(err.position, *position, "{instruction}: {err}");
        assert!(err.expected.starts_with(expected), "{instruction}: {err}");
        assert!(err.to_string().contains("cannot parse instruction"));
    }
}

#[test]
fn json_has_the_documented_fields_and_round_trips() {
    let parsed = parse_with_goals(
        "turn on the stove and put the moka pot on it",
        &atoms(&["(Turnon flat_stove_1)", "(On moka_pot_1 flat_stove_1_cook_region)"]),
    )
    .unwrap();
    let json = serde_json::to_value(&parsed).unwrap();
    assert_eq!(json["source"], "stove");
    assert_eq!(json["relation"], "turn_on");
    assert!(json["target"].is_null() && json["steps"][0]["target"].is_null());
    assert_eq!(json["steps"][1]["target"], "stove");
    assert_eq!(json["steps"][1]["target_id"], "flat_stove_1_cook_region");
    let back: ParsedTask = serde_json::from_value(json).unwrap();
    assert_eq!(back, parsed);
}

#[test]
fn word_soup_never_panics() {
    // Every 3-word sequence and 4000 pseudo-random 2–9-word sequences over a vocabulary of verbs,
    // prepositions, pronouns and names: each either parses or gives an error.
    const WORDS: &[&str] = &[
        "put", "pick", "up", "and", "it", "them", "the", "both", "on", "in", "to", "of", "top", "left", "right",
        "turn", "off", "open", "close", "push", "inside", "bowl", "plate", "at", "back", "front", "next", "stack",
    ];
    let check = |words: &[&str]| {
        let text = words.join(" ");
        if let Ok(p) = parse(&text) {
            assert!(!p.steps.is_empty() && p.steps.iter().all(|s| !s.source.is_empty()), "{text}");
        }
    };
    for a in WORDS {
        for b in WORDS {
            for c in WORDS {
                check(&[a, b, c]);
            }
        }
    }
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    for _ in 0..4000 {
        let mut words = Vec::new();
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let len = 2 + (state >> 60) as usize % 8;
        for _ in 0..len {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            words.push(WORDS[(state >> 33) as usize % WORDS.len()]);
        }
        check(&words);
    }
}
