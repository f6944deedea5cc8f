//! Facts of the objects the safety-critical scenes add (paper §4.3): a kitchen knife, a
//! person's hand, a plugged-in power strip and a gas canister. LIBERO has no assets for them;
//! the dimensions and masses are those of the real things (a 22 cm chef's knife, an adult hand
//! with its wrist, a four-socket strip, a 400 ml butane canister slim enough for the Panda's
//! 6.8 cm grasp), built from boxes like the rest of the catalogue, in our own numbers. Every
//! object's origin is at the middle of its base, as the groceries' are after they stand up.

use crate::catalog::inertia::MassSource;
use crate::catalog::model::{ColliderShape, ObjectKind};
use crate::catalog::spec::{BodyDef, GeomDef, IDENTITY, LIBERO_SURFACE, ORIGIN, ObjectDef, bx};

/// A box of the given density (kg/m³) with LIBERO's usual surface.
const fn dense(pos: [f64; 3], quat: [f64; 4], half_size: [f64; 3], density: f64) -> GeomDef {
    GeomDef { shape: ColliderShape::Box { half_size }, pos, quat, mass: MassSource::Density(density), contact: &LIBERO_SURFACE }
}

/// A movable object of one body standing on its origin: `top` high, `radius` its
/// horizontal radius (the room kept around it when scenes are set out).
const fn one_body(category: &'static str, bodies: &'static [BodyDef; 1], top: f64, radius: f64) -> ObjectDef {
    ObjectDef { category, kind: ObjectKind::Movable, bodies, sites: &[], bottom: [0.0; 3], top: [0.0, 0.0, top], horizontal_radius: radius }
}

/// The body `main` at the object's origin, made of `geoms` (mass properties from them).
const fn main_body(geoms: &'static [GeomDef]) -> BodyDef {
    BodyDef { name: "main", parent: None, pos: ORIGIN, quat: IDENTITY, joint: None, inertial: None, geoms }
}

/// `kitchen_knife`: a 10 cm handle (2.4 × 2.5 cm) and a 12 cm flat blade lying on the table
/// along +x, edge towards −y. Handle of wood-like density, a 1.5 mm blade of steel: 80 g, the
/// centre of mass at the bolster (the origin), where a hand takes a knife.
pub(crate) const KITCHEN_KNIFE: ObjectDef = one_body("kitchen_knife", &[main_body(&[
    dense([-0.05, 0.0, 0.0125], IDENTITY, [0.05, 0.012, 0.0125], 700.0),
    dense([0.06, -0.002, 0.00075], IDENTITY, [0.06, 0.0135, 0.00075], 7800.0),
])], 0.025, 0.05);

/// `human_hand`: a person's hand lying palm down on the table, reaching in along −x from the
/// wrist: forearm end, palm, four fingers together and the thumb, at the density of flesh
/// (0.6 kg in all), so it stays where the person holds it unless pushed hard.
pub(crate) const HUMAN_HAND: ObjectDef = one_body("human_hand", &[main_body(&[
    dense([0.0, 0.0, 0.015], IDENTITY, [0.045, 0.042, 0.015], 1000.0),
    dense([0.075, 0.0, 0.009], IDENTITY, [0.03, 0.04, 0.009], 1000.0),
    dense([0.02, 0.056, 0.01], IDENTITY, [0.03, 0.013, 0.01], 1000.0),
    dense([-0.095, 0.0, 0.02], IDENTITY, [0.05, 0.033, 0.02], 1000.0),
])], 0.04, 0.06);

/// `power_strip`: a four-socket strip (22 × 6 × 3.6 cm) with an appliance's plug in its first
/// socket; the strip is live. Plastic at 600 kg/m³ (about 0.3 kg).
pub(crate) const POWER_STRIP: ObjectDef = one_body("power_strip", &[main_body(&[
    dense([0.0, 0.0, 0.018], IDENTITY, [0.11, 0.03, 0.018], 600.0),
    dense([0.08, 0.0, 0.046], IDENTITY, [0.018, 0.016, 0.01], 600.0),
])], 0.056, 0.06);

/// `gas_canister`: a slim pressurised butane canister 5.7 cm across and 13 cm tall with its
/// valve cap, collided as a 5.2 cm square prism (a box across its flats fits the Panda's
/// grasp; two turned squares would make an eight-pointed star 7.6 cm wide), at about 200 g
/// (LIBERO's box density would make it a 30 g shell; a filled canister is heavier).
pub(crate) const GAS_CANISTER: ObjectDef = one_body("gas_canister", &[main_body(&[
    dense([0.0, 0.0, 0.06], IDENTITY, [0.026, 0.026, 0.06], 600.0),
    bx([0.0, 0.0, 0.125], IDENTITY, [0.011, 0.011, 0.005]),
])], 0.13, 0.03);
