//! The object and fixture catalog: every category the 40 LIBERO tasks use, and the few the
//! study scenes add ([`STUDY_CATEGORIES`]), as pure data.
//!
//! Each [`ObjectModel`] carries LIBERO's collision geometry and contact parameters, mass
//! properties computed as MuJoCo compiles them, articulation joints, the named sites the goal
//! predicates read, robosuite's spawn offsets, and a procedural look. Physics and rendering
//! instantiate these models; nothing here depends on either.

mod bounds;
mod facts;
mod frames;
pub(crate) mod inertia;
mod looks;
mod model;
pub(crate) mod spec;

use std::sync::OnceLock;

pub use bounds::Aabb;

pub use model::{
    BodyModel, Collider, ColliderShape, FREE_JOINT_DAMPING, Inertial, JointKind, JointModel,
    ObjectKind, ObjectModel, Recipe, SiteModel, SiteShape, VisualPart,
};

use facts::{fixtures as fx, groceries as gr, hazards as hz, kitchenware as kw, study as st, tableware as tw};
use spec::ObjectDef;

/// A category name the catalog does not know.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown object category `{category}`; known categories: {}", CATEGORIES.join(", "))]
pub struct UnknownCategory {
    pub category: String,
}

type Look = fn(&ObjectDef) -> Vec<VisualPart>;

/// Every category with its look, in a fixed order.
const ENTRIES: [(&ObjectDef, Look); 36] = [
    (&tw::AKITA_BLACK_BOWL, looks::tableware::akita_black_bowl),
    (&tw::PLATE, looks::tableware::plate),
    (
        &tw::GLAZED_RIM_PORCELAIN_RAMEKIN,
        looks::tableware::glazed_rim_porcelain_ramekin,
    ),
    (&tw::BASKET, looks::tableware::basket),
    (&tw::CHEFMATE_8_FRYPAN, looks::tableware::chefmate_8_frypan),
    (&gr::COOKIES, looks::groceries::cookies),
    (&gr::ALPHABET_SOUP, looks::groceries::alphabet_soup),
    (&gr::TOMATO_SAUCE, looks::groceries::tomato_sauce),
    (&gr::BBQ_SAUCE, looks::groceries::bbq_sauce),
    (&gr::BUTTER, looks::groceries::butter),
    (&gr::CHOCOLATE_PUDDING, looks::groceries::chocolate_pudding),
    (&gr::CREAM_CHEESE, looks::groceries::cream_cheese),
    (&gr::KETCHUP, looks::groceries::ketchup),
    (&gr::SALAD_DRESSING, looks::groceries::salad_dressing),
    (&gr::MILK, looks::groceries::milk),
    (&gr::ORANGE_JUICE, looks::groceries::orange_juice),
    (&kw::WINE_BOTTLE, looks::kitchenware::wine_bottle),
    (&kw::MOKA_POT, looks::kitchenware::moka_pot),
    (&kw::PORCELAIN_MUG, looks::kitchenware::porcelain_mug),
    (&kw::RED_COFFEE_MUG, looks::kitchenware::red_coffee_mug),
    (&kw::WHITE_YELLOW_MUG, looks::kitchenware::white_yellow_mug),
    (&kw::BLACK_BOOK, looks::kitchenware::black_book),
    (&fx::WOODEN_CABINET, looks::fixtures::wooden_cabinet),
    (&fx::WHITE_CABINET, looks::fixtures::white_cabinet),
    (&fx::FLAT_STOVE, looks::fixtures::flat_stove),
    (&fx::MICROWAVE, looks::fixtures::microwave),
    (&fx::WINE_RACK, looks::fixtures::wine_rack),
    (&fx::DESK_CADDY, looks::fixtures::desk_caddy),
    // The safety-critical scenes' objects (paper §4.3); no LIBERO task uses them.
    (&hz::KITCHEN_KNIFE, looks::hazards::kitchen_knife),
    (&hz::HUMAN_HAND, looks::hazards::human_hand),
    (&hz::POWER_STRIP, looks::hazards::power_strip),
    (&hz::GAS_CANISTER, looks::hazards::gas_canister),
    // The PiPER study's objects (§4.4), not LIBERO's.
    (&st::RED_PLASTIC_CUP, looks::study::red_plastic_cup),
    (&st::BLUE_PLASTIC_CUP, looks::study::blue_plastic_cup),
    (&st::GREEN_PLASTIC_CUP, looks::study::green_plastic_cup),
    (&st::PAPER_NOTE, looks::study::paper_note),
];

/// The categories only the study scenes use (the rest are the 40 LIBERO tasks' own).
pub const STUDY_CATEGORIES: [&str; 8] = [
    "kitchen_knife",
    "human_hand",
    "power_strip",
    "gas_canister",
    "red_plastic_cup",
    "blue_plastic_cup",
    "green_plastic_cup",
    "paper_note",
];

/// The category names, in catalog order.
pub const CATEGORIES: [&str; 36] = {
    let mut names = [""; 36];
    let mut i = 0;
    while i < ENTRIES.len() {
        names[i] = ENTRIES[i].0.category;
        i += 1;
    }
    names
};

/// All models, built on first use and shared afterwards.
pub fn all() -> &'static [ObjectModel] {
    static MODELS: OnceLock<Vec<ObjectModel>> = OnceLock::new();
    MODELS.get_or_init(|| {
        ENTRIES
            .iter()
            .map(|(def, look)| def.build(look(def)))
            .collect()
    })
}

/// The model of `category` (a BDDL category name such as `akita_black_bowl`).
pub fn object(category: &str) -> Result<&'static ObjectModel, UnknownCategory> {
    all()
        .iter()
        .find(|m| m.category == category)
        .ok_or_else(|| UnknownCategory {
            category: category.to_string(),
        })
}

#[cfg(test)]
mod tests;
