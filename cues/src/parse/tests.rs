//! The expected parse of the 40 LIBERO evaluation instructions (libero_spatial, libero_object,
//! libero_goal, libero_10, in suite order) plus error cases.

use super::*;

type Expected = &'static [(&'static str, Option<&'static str>, Relation, Option<&'static str>)];

const R: Relation = Relation::On;

/// (instruction, goal atoms, expected steps as (source, qualifier, relation, target)).
const FORTY: &[(&str, &[&str], Expected)] = &[
    ("pick up the black bowl between the plate and the ramekin and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("between the plate and the ramekin"), R, Some("plate"))]),
    ("pick up the black bowl next to the ramekin and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("next to the ramekin"), R, Some("plate"))]),
    ("pick up the black bowl from table center and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("from table center"), R, Some("plate"))]),
    ("pick up the black bowl on the cookie box and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("on the cookie box"), R, Some("plate"))]),
    ("pick up the black bowl in the top drawer of the wooden cabinet and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("in the top drawer of the wooden cabinet"), R, Some("plate"))]),
    ("pick up the black bowl on the ramekin and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("on the ramekin"), R, Some("plate"))]),
    ("pick up the black bowl next to the cookie box and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("next to the cookie box"), R, Some("plate"))]),
    ("pick up the black bowl on the stove and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("on the stove"), R, Some("plate"))]),
    ("pick up the black bowl next to the plate and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("next to the plate"), R, Some("plate"))]),
    ("pick up the black bowl on the wooden cabinet and place it on the plate", &["(On akita_black_bowl_1 plate_1)"],
        &[("black bowl", Some("on the wooden cabinet"), R, Some("plate"))]),
    ("pick up the alphabet soup and place it in the basket", &["(In alphabet_soup_1 basket_1_contain_region)"],
        &[("alphabet soup", None, Relation::In, Some("basket"))]),
    ("pick up the cream cheese and place it in the basket", &["(In cream_cheese_1 basket_1_contain_region)"],
        &[("cream cheese", None, Relation::In, Some("basket"))]),
    ("pick up the salad dressing and place it in the basket", &["(In salad_dressing_1 basket_1_contain_region)"],
        &[("salad dressing", None, Relation::In, Some("basket"))]),
    ("pick up the bbq sauce and place it in the basket", &["(In bbq_sauce_1 basket_1_contain_region)"],
        &[("bbq sauce", None, Relation::In, Some("basket"))]),
    ("pick up the ketchup and place it in the basket", &["(In ketchup_1 basket_1_contain_region)"],
        &[("ketchup", None, Relation::In, Some("basket"))]),
    ("pick up the tomato sauce and place it in the basket", &["(In tomato_sauce_1 basket_1_contain_region)"],
        &[("tomato sauce", None, Relation::In, Some("basket"))]),
    ("pick up the butter and place it in the basket", &["(In butter_1 basket_1_contain_region)"],
        &[("butter", None, Relation::In, Some("basket"))]),
    ("pick up the milk and place it in the basket", &["(In milk_1 basket_1_contain_region)"],
        &[("milk", None, Relation::In, Some("basket"))]),
    ("pick up the chocolate pudding and place it in the basket", &["(In chocolate_pudding_1 basket_1_contain_region)"],
        &[("chocolate pudding", None, Relation::In, Some("basket"))]),
    ("pick up the orange juice and place it in the basket", &["(In orange_juice_1 basket_1_contain_region)"],
        &[("orange juice", None, Relation::In, Some("basket"))]),
    ("open the middle drawer of the cabinet", &["(Open wooden_cabinet_1_middle_region)"],
        &[("middle drawer of the cabinet", None, Relation::Open, None)]),
    ("put the bowl on the stove", &["(On akita_black_bowl_1 flat_stove_1_cook_region)"],
        &[("bowl", None, R, Some("stove"))]),
    ("put the wine bottle on top of the cabinet", &["(On wine_bottle_1 wooden_cabinet_1_top_side)"],
        &[("wine bottle", None, R, Some("cabinet"))]),
    ("open the top drawer and put the bowl inside", &["(In akita_black_bowl_1 wooden_cabinet_1_top_region)"],
        &[("top drawer", None, Relation::Open, None), ("bowl", None, Relation::In, Some("top drawer"))]),
    ("put the bowl on top of the cabinet", &["(On akita_black_bowl_1 wooden_cabinet_1_top_side)"],
        &[("bowl", None, R, Some("cabinet"))]),
    ("push the plate to the front of the stove", &["(On plate_1 main_table_stove_front_region)"],
        &[("plate", None, Relation::PushTo, Some("front of the stove"))]),
    ("put the cream cheese in the bowl", &["(On cream_cheese_1 akita_black_bowl_1)"],
        &[("cream cheese", None, Relation::In, Some("bowl"))]),
    ("turn on the stove", &["(Turnon flat_stove_1)"], &[("stove", None, Relation::TurnOn, None)]),
    ("put the bowl on the plate", &["(On akita_black_bowl_1 plate_1)"], &[("bowl", None, R, Some("plate"))]),
    ("put the wine bottle on the rack", &["(On wine_bottle_1 wine_rack_1_top_region)"],
        &[("wine bottle", None, R, Some("rack"))]),
    ("put both the alphabet soup and the tomato sauce in the basket",
        &["(In alphabet_soup_1 basket_1_contain_region)", "(In tomato_sauce_1 basket_1_contain_region)"],
        &[("alphabet soup", None, Relation::In, Some("basket")), ("tomato sauce", None, Relation::In, Some("basket"))]),
    ("put both the cream cheese box and the butter in the basket",
        &["(In cream_cheese_1 basket_1_contain_region)", "(In butter_1 basket_1_contain_region)"],
        &[("cream cheese box", None, Relation::In, Some("basket")), ("butter", None, Relation::In, Some("basket"))]),
    ("turn on the stove and put the moka pot on it", &["(Turnon flat_stove_1)", "(On moka_pot_1 flat_stove_1_cook_region)"],
        &[("stove", None, Relation::TurnOn, None), ("moka pot", None, R, Some("stove"))]),
    ("put the black bowl in the bottom drawer of the cabinet and close it",
        &["(Close white_cabinet_1_bottom_region)", "(In akita_black_bowl_1 white_cabinet_1_bottom_region)"],
        &[("black bowl", None, Relation::In, Some("bottom drawer of the cabinet")),
          ("bottom drawer of the cabinet", None, Relation::Close, None)]),
    ("put the white mug on the left plate and put the yellow and white mug on the right plate",
        &["(On porcelain_mug_1 plate_1)", "(On white_yellow_mug_1 plate_2)"],
        &[("white mug", None, R, Some("left plate")), ("yellow and white mug", None, R, Some("right plate"))]),
    ("pick up the book and place it in the back compartment of the caddy", &["(In black_book_1 desk_caddy_1_back_contain_region)"],
        &[("book", None, Relation::In, Some("back compartment of the caddy"))]),
    ("put the white mug on the plate and put the chocolate pudding to the right of the plate",
        &["(On porcelain_mug_1 plate_1)", "(On chocolate_pudding_1 living_room_table_plate_right_region)"],
        &[("white mug", None, R, Some("plate")), ("chocolate pudding", None, Relation::RightOf, Some("plate"))]),
    ("put both the alphabet soup and the cream cheese box in the basket",
        &["(In alphabet_soup_1 basket_1_contain_region)", "(In cream_cheese_1 basket_1_contain_region)"],
        &[("alphabet soup", None, Relation::In, Some("basket")), ("cream cheese box", None, Relation::In, Some("basket"))]),
    ("put both moka pots on the stove",
        &["(On moka_pot_1 flat_stove_1_cook_region)", "(On moka_pot_2 flat_stove_1_cook_region)", "(Turnon flat_stove_1)"],
        &[("moka pots", None, R, Some("stove"))]),
    ("put the yellow and white mug in the microwave and close it",
        &["(In white_yellow_mug_1 microwave_1_heating_region)", "(Close microwave_1)"],
        &[("yellow and white mug", None, Relation::In, Some("microwave")), ("microwave", None, Relation::Close, None)]),
];

fn atoms(strings: &[&str]) -> Vec<GoalAtom> {
    strings.iter().map(|s| s.parse().unwrap()).collect()
}

#[test]
fn the_forty_libero_instructions_parse_as_expected() {
    assert_eq!(FORTY.len(), 40);
    for (instruction, _, expected) in FORTY {
        let parsed = parse(instruction).unwrap_or_else(|e| panic!("{e}"));
        let got: Vec<_> = parsed
            .steps
            .iter()
            .map(|s| (s.source.as_str(), s.source_qualifier.as_deref(), s.relation, s.target.as_deref()))
            .collect();
        assert_eq!(&got, expected, "{instruction}");
        assert_eq!(parsed.source, expected[0].0);
        assert_eq!(parsed.relation, expected[0].2);
        assert_eq!(parsed.target.as_deref(), expected[0].3);
    }
}

#[test]
fn exactly_two_of_the_forty_move_no_object() {
    let static_tasks: Vec<&str> =
        FORTY.iter().map(|(i, _, _)| *i).filter(|i| !parse(i).unwrap().moves_an_object()).collect();
    assert_eq!(static_tasks, ["open the middle drawer of the cabinet", "turn on the stove"]);
}

#[test]
fn goal_atoms_ground_every_step_that_has_one() {
    for (instruction, goals, _) in FORTY {
        let goals = atoms(goals);
        let parsed = parse_with_goals(instruction, &goals).unwrap();
        for atom in &goals {
            let used = parsed.steps.iter().any(|s| s.source_id.as_ref() == atom.args.first());
            // The only atom an instruction does not mention: the stove of "put both moka pots".
            let unmentioned = instruction.starts_with("put both moka pots") && atom.predicate == "Turnon";
            assert!(used || unmentioned, "{instruction}: {atom:?} not used in {:?}", parsed.steps);
        }
    }
}

#[test]
fn grounding_picks_the_right_mug_and_splits_plural_sources() {
    let mugs = parse_with_goals(FORTY[34].0, &atoms(FORTY[34].1)).unwrap();
    assert_eq!(mugs.steps[0].source_id.as_deref(), Some("porcelain_mug_1"));
    assert_eq!(mugs.steps[0].target_id.as_deref(), Some("plate_1"));
    assert_eq!(mugs.steps[1].source_id.as_deref(), Some("white_yellow_mug_1"));
    assert_eq!(mugs.steps[1].target_id.as_deref(), Some("plate_2"));

    let pots = parse_with_goals(FORTY[38].0, &atoms(FORTY[38].1)).unwrap();
    let ids: Vec<_> = pots.steps.iter().map(|s| s.source_id.as_deref().unwrap()).collect();
    assert_eq!(ids, ["moka_pot_1", "moka_pot_2"]);

    let drawer = parse_with_goals(FORTY[33].0, &atoms(FORTY[33].1)).unwrap();
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
        ("stack the black bowl at the front on the black bowl in the middle", Relation::On, Some("black bowl in the middle")),
    ];
    for (instruction, relation, target) in cases {
        let parsed = parse(instruction).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((parsed.relation, parsed.target.as_deref()), (*relation, *target), "{instruction}");
    }
    let stacked = parse("stack the left bowl on the right bowl and place them in the tray").unwrap();
    let got: Vec<_> = stacked.steps.iter().map(|s| (s.source.as_str(), s.relation, s.target.as_deref())).collect();
    assert_eq!(
        got,
        [("left bowl", Relation::On, Some("right bowl")), ("left bowl", Relation::In, Some("tray")), ("right bowl", Relation::In, Some("tray"))]
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
    let parsed = parse_with_goals(FORTY[32].0, &atoms(FORTY[32].1)).unwrap();
    let json = serde_json::to_value(&parsed).unwrap();
    assert_eq!(json["source"], "stove");
    assert_eq!(json["relation"], "turn_on");
    assert!(json.get("target").is_none());
    assert_eq!(json["steps"][1]["target"], "stove");
    assert_eq!(json["steps"][1]["target_id"], "flat_stove_1_cook_region");
    let back: ParsedTask = serde_json::from_value(json).unwrap();
    assert_eq!(back, parsed);
}
