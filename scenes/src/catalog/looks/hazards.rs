//! Looks of the safety scenes' objects (no LIBERO textures exist for them): colours of the real
//! things — a black-handled steel knife, skin, a white strip with dark sockets and a black plug,
//! a red canister with a yellow hazard band and a silver valve.

use super::kit::{copies_of, cuboid, cylinder, part, rgb};
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

const ROOT: usize = 0;

pub(crate) fn kitchen_knife(def: &ObjectDef) -> Vec<VisualPart> {
    let mut parts = copies_of(&def.bodies[0], ROOT, 0..1, rgb(30, 30, 32));
    parts.extend(copies_of(&def.bodies[0], ROOT, 1..2, rgb(200, 203, 208)));
    // Three rivets on the handle.
    for x in [-0.08, -0.05, -0.02] {
        parts.push(part(ROOT, cylinder(0.003, 0.0004), [x, 0.0, 0.0252], rgb(190, 190, 195)));
    }
    parts
}

pub(crate) fn human_hand(def: &ObjectDef) -> Vec<VisualPart> {
    let skin = rgb(224, 172, 140);
    let mut parts = copies_of(&def.bodies[0], ROOT, 0..3, skin);
    // A shirt sleeve over the forearm end.
    parts.extend(copies_of(&def.bodies[0], ROOT, 3..4, rgb(60, 90, 150)));
    // Finger gaps drawn as thin dark lines across the fingers' top.
    for y in [-0.02, 0.0, 0.02] {
        parts.push(part(ROOT, cuboid([0.028, 0.0008, 0.0003]), [0.077, y, 0.0182], rgb(170, 120, 95)));
    }
    parts
}

pub(crate) fn power_strip(def: &ObjectDef) -> Vec<VisualPart> {
    let mut parts = copies_of(&def.bodies[0], ROOT, 0..1, rgb(235, 235, 230));
    parts.extend(copies_of(&def.bodies[0], ROOT, 1..2, rgb(25, 25, 25)));
    // Four sockets on top (the first holds the plug) and a red lit switch at the far end.
    for x in [-0.04, 0.0, 0.04] {
        parts.push(part(ROOT, cylinder(0.014, 0.0004), [x, 0.0, 0.0362], rgb(70, 70, 72)));
    }
    parts.push(part(ROOT, cuboid([0.008, 0.012, 0.0015]), [-0.09, 0.0, 0.0365], rgb(220, 30, 30)));
    parts
}

pub(crate) fn gas_canister(def: &ObjectDef) -> Vec<VisualPart> {
    vec![
        part(ROOT, cylinder(0.0285, 0.06), [0.0, 0.0, 0.06], rgb(200, 30, 30)),
        part(ROOT, cylinder(0.0289, 0.012), [0.0, 0.0, 0.075], rgb(245, 200, 20)),
        part(ROOT, cylinder(0.02, 0.004), [0.0, 0.0, 0.122], rgb(185, 185, 190)),
        copies_of(&def.bodies[0], ROOT, 1..2, rgb(185, 185, 190)).remove(0),
    ]
}
