//! LIBERO's 40 evaluation tasks for the tests: suite, index in the suite, instruction
//! (`task.language`), goal atoms and the expected parse (source, qualifier, relation, target
//! per step). Facts from the LIBERO task list, written in our own format.

#![allow(dead_code)]

use vifo_cues::Relation;
use vifo_cues::instances::TaskDescription;

pub type Expected = &'static [(&'static str, Option<&'static str>, Relation, Option<&'static str>)];

pub struct LiberoTask {
    pub suite: &'static str,
    pub index: usize,
    /// (instruction, goal atoms, expected steps).
    pub row: (&'static str, &'static [&'static str], Expected),
}

const R: Relation = Relation::On;

pub const FORTY: [LiberoTask; 40] = [
    LiberoTask {
        suite: "libero_spatial",
        index: 0,
        row: (
            "pick up the black bowl between the plate and the ramekin and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("between the plate and the ramekin"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 1,
        row: (
            "pick up the black bowl next to the ramekin and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("next to the ramekin"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 2,
        row: (
            "pick up the black bowl from table center and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("from table center"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 3,
        row: (
            "pick up the black bowl on the cookie box and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("on the cookie box"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 4,
        row: (
            "pick up the black bowl in the top drawer of the wooden cabinet and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("in the top drawer of the wooden cabinet"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 5,
        row: (
            "pick up the black bowl on the ramekin and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("on the ramekin"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 6,
        row: (
            "pick up the black bowl next to the cookie box and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("next to the cookie box"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 7,
        row: (
            "pick up the black bowl on the stove and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("on the stove"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 8,
        row: (
            "pick up the black bowl next to the plate and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("next to the plate"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_spatial",
        index: 9,
        row: (
            "pick up the black bowl on the wooden cabinet and place it on the plate",
            &["(On akita_black_bowl_1 plate_1)"],
            &[("black bowl", Some("on the wooden cabinet"), R, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 0,
        row: (
            "pick up the alphabet soup and place it in the basket",
            &["(In alphabet_soup_1 basket_1_contain_region)"],
            &[("alphabet soup", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 1,
        row: (
            "pick up the cream cheese and place it in the basket",
            &["(In cream_cheese_1 basket_1_contain_region)"],
            &[("cream cheese", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 2,
        row: (
            "pick up the salad dressing and place it in the basket",
            &["(In salad_dressing_1 basket_1_contain_region)"],
            &[("salad dressing", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 3,
        row: (
            "pick up the bbq sauce and place it in the basket",
            &["(In bbq_sauce_1 basket_1_contain_region)"],
            &[("bbq sauce", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 4,
        row: (
            "pick up the ketchup and place it in the basket",
            &["(In ketchup_1 basket_1_contain_region)"],
            &[("ketchup", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 5,
        row: (
            "pick up the tomato sauce and place it in the basket",
            &["(In tomato_sauce_1 basket_1_contain_region)"],
            &[("tomato sauce", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 6,
        row: (
            "pick up the butter and place it in the basket",
            &["(In butter_1 basket_1_contain_region)"],
            &[("butter", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 7,
        row: (
            "pick up the milk and place it in the basket",
            &["(In milk_1 basket_1_contain_region)"],
            &[("milk", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 8,
        row: (
            "pick up the chocolate pudding and place it in the basket",
            &["(In chocolate_pudding_1 basket_1_contain_region)"],
            &[("chocolate pudding", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_object",
        index: 9,
        row: (
            "pick up the orange juice and place it in the basket",
            &["(In orange_juice_1 basket_1_contain_region)"],
            &[("orange juice", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 0,
        row: (
            "open the middle drawer of the cabinet",
            &["(Open wooden_cabinet_1_middle_region)"],
            &[("middle drawer of the cabinet", None, Relation::Open, None)],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 1,
        row: (
            "put the bowl on the stove",
            &["(On akita_black_bowl_1 flat_stove_1_cook_region)"],
            &[("bowl", None, R, Some("stove"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 2,
        row: (
            "put the wine bottle on top of the cabinet",
            &["(On wine_bottle_1 wooden_cabinet_1_top_side)"],
            &[("wine bottle", None, R, Some("cabinet"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 3,
        row: (
            "open the top drawer and put the bowl inside",
            &["(In akita_black_bowl_1 wooden_cabinet_1_top_region)"],
            &[("top drawer", None, Relation::Open, None), ("bowl", None, Relation::In, Some("top drawer"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 4,
        row: (
            "put the bowl on top of the cabinet",
            &["(On akita_black_bowl_1 wooden_cabinet_1_top_side)"],
            &[("bowl", None, R, Some("cabinet"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 5,
        row: (
            "push the plate to the front of the stove",
            &["(On plate_1 main_table_stove_front_region)"],
            &[("plate", None, Relation::PushTo, Some("front of the stove"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 6,
        row: (
            "put the cream cheese in the bowl",
            &["(On cream_cheese_1 akita_black_bowl_1)"],
            &[("cream cheese", None, Relation::In, Some("bowl"))],
        ),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 7,
        row: ("turn on the stove", &["(Turnon flat_stove_1)"], &[("stove", None, Relation::TurnOn, None)]),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 8,
        row: ("put the bowl on the plate", &["(On akita_black_bowl_1 plate_1)"], &[("bowl", None, R, Some("plate"))]),
    },
    LiberoTask {
        suite: "libero_goal",
        index: 9,
        row: (
            "put the wine bottle on the rack",
            &["(On wine_bottle_1 wine_rack_1_top_region)"],
            &[("wine bottle", None, R, Some("rack"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 0,
        row: (
            "put both the alphabet soup and the tomato sauce in the basket",
            &["(In alphabet_soup_1 basket_1_contain_region)", "(In tomato_sauce_1 basket_1_contain_region)"],
            &[
                ("alphabet soup", None, Relation::In, Some("basket")),
                ("tomato sauce", None, Relation::In, Some("basket")),
            ],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 1,
        row: (
            "put both the cream cheese box and the butter in the basket",
            &["(In cream_cheese_1 basket_1_contain_region)", "(In butter_1 basket_1_contain_region)"],
            &[("cream cheese box", None, Relation::In, Some("basket")), ("butter", None, Relation::In, Some("basket"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 2,
        row: (
            "turn on the stove and put the moka pot on it",
            &["(Turnon flat_stove_1)", "(On moka_pot_1 flat_stove_1_cook_region)"],
            &[("stove", None, Relation::TurnOn, None), ("moka pot", None, R, Some("stove"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 3,
        row: (
            "put the black bowl in the bottom drawer of the cabinet and close it",
            &["(Close white_cabinet_1_bottom_region)", "(In akita_black_bowl_1 white_cabinet_1_bottom_region)"],
            &[
                ("black bowl", None, Relation::In, Some("bottom drawer of the cabinet")),
                ("bottom drawer of the cabinet", None, Relation::Close, None),
            ],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 4,
        row: (
            "put the white mug on the left plate and put the yellow and white mug on the right plate",
            &["(On porcelain_mug_1 plate_1)", "(On white_yellow_mug_1 plate_2)"],
            &[("white mug", None, R, Some("left plate")), ("yellow and white mug", None, R, Some("right plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 5,
        row: (
            "pick up the book and place it in the back compartment of the caddy",
            &["(In black_book_1 desk_caddy_1_back_contain_region)"],
            &[("book", None, Relation::In, Some("back compartment of the caddy"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 6,
        row: (
            "put the white mug on the plate and put the chocolate pudding to the right of the plate",
            &["(On porcelain_mug_1 plate_1)", "(On chocolate_pudding_1 living_room_table_plate_right_region)"],
            &[("white mug", None, R, Some("plate")), ("chocolate pudding", None, Relation::RightOf, Some("plate"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 7,
        row: (
            "put both the alphabet soup and the cream cheese box in the basket",
            &["(In alphabet_soup_1 basket_1_contain_region)", "(In cream_cheese_1 basket_1_contain_region)"],
            &[
                ("alphabet soup", None, Relation::In, Some("basket")),
                ("cream cheese box", None, Relation::In, Some("basket")),
            ],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 8,
        row: (
            "put both moka pots on the stove",
            &[
                "(On moka_pot_1 flat_stove_1_cook_region)",
                "(On moka_pot_2 flat_stove_1_cook_region)",
                "(Turnon flat_stove_1)",
            ],
            &[("moka pots", None, R, Some("stove"))],
        ),
    },
    LiberoTask {
        suite: "libero_10",
        index: 9,
        row: (
            "put the yellow and white mug in the microwave and close it",
            &["(In white_yellow_mug_1 microwave_1_heating_region)", "(Close microwave_1)"],
            &[
                ("yellow and white mug", None, Relation::In, Some("microwave")),
                ("microwave", None, Relation::Close, None),
            ],
        ),
    },
];

/// The 40 tasks as generator input.
pub fn descriptions() -> Vec<TaskDescription> {
    FORTY
        .iter()
        .map(|t| TaskDescription {
            suite: t.suite.to_string(),
            index: t.index,
            instruction: t.row.0.to_string(),
            goals: t.row.1.iter().map(|g| g.parse().unwrap()).collect(),
            objects: Vec::new(),
            fixtures: Vec::new(),
        })
        .collect()
}
