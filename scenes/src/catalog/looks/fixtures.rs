//! Looks of the fixtures. They are built from boxes in LIBERO too, so most parts are visual
//! copies of the collision geoms, coloured per piece. Colours are texture means:
//! `dark_fine_wood.png` (52, 45, 39), `white_wood.png` (215, 213, 214), the handles' `metal.png`
//! (108, 108, 108, drawn lighter as it is polished), the microwave's `micro_black` (0.2) and
//! `metal1.png` (133, 132, 131), the wine rack's `light-wood.png` (208, 171, 133) and
//! `mahogany.png` (77, 24, 7), and the reference stand-in for the desk caddy (120, 80, 50).
//! The stove's plate is near-white and its burner dark grey in the reference renders.

use super::kit::{copies_of, cuboid, cylinder, part, rgb};
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

const ROOT: usize = 0;

/// Carcass and drawers in `wood`; each drawer's handle bar and its two standoffs (its last three
/// geoms) in metal.
fn cabinet(def: &ObjectDef, wood: [f32; 4]) -> Vec<VisualPart> {
    let metal = rgb(150, 150, 152);
    let mut parts = copies_of(
        &def.bodies[ROOT],
        ROOT,
        0..def.bodies[ROOT].geoms.len(),
        wood,
    );
    for (index, drawer) in def.bodies.iter().enumerate().skip(1) {
        let n = drawer.geoms.len();
        parts.extend(copies_of(drawer, index, 0..n - 3, wood));
        parts.extend(copies_of(drawer, index, n - 3..n, metal));
    }
    parts
}

pub(crate) fn wooden_cabinet(def: &ObjectDef) -> Vec<VisualPart> {
    cabinet(def, rgb(52, 45, 39))
}

pub(crate) fn white_cabinet(def: &ObjectDef) -> Vec<VisualPart> {
    cabinet(def, rgb(215, 213, 214))
}

pub(crate) fn flat_stove(def: &ObjectDef) -> Vec<VisualPart> {
    // The plate box, then a dark burner just below the red `burner` site (z 0.0215-0.0225) so
    // the site covers it when the stove is on; the knob is its own collision boxes in black.
    let burner = [0.15, 0.0, 0.0];
    let mut parts = copies_of(&def.bodies[ROOT], ROOT, 0..1, rgb(205, 205, 202));
    parts.push(part(
        ROOT,
        cylinder(0.07, 0.0007),
        [burner[0], 0.0, 0.0207],
        rgb(55, 55, 55),
    ));
    parts.push(part(
        ROOT,
        cylinder(0.045, 0.0001),
        [burner[0], 0.0, 0.02145],
        rgb(95, 95, 95),
    ));
    parts.push(part(
        ROOT,
        cylinder(0.02, 0.0001),
        [burner[0], 0.0, 0.02155],
        rgb(55, 55, 55),
    ));
    let knob = &def.bodies[1];
    parts.extend(copies_of(knob, 1, 0..knob.geoms.len(), rgb(25, 25, 25)));
    parts
}

pub(crate) fn microwave(def: &ObjectDef) -> Vec<VisualPart> {
    let black = rgb(51, 51, 51);
    let metal = rgb(133, 132, 131);
    let shell = &def.bodies[ROOT];
    let mut parts = copies_of(shell, ROOT, 0..shell.geoms.len(), black);
    // Two buttons on the control panel (the shell's last box, front face at y = -0.1105).
    for z in [0.15, 0.12] {
        parts.push(part(
            ROOT,
            cuboid([0.022, 0.0015, 0.007]),
            [0.13, -0.1115, z],
            metal,
        ));
    }
    // Door: panel, a dark window on its outer face, and the capsule handle.
    let door = &def.bodies[1];
    parts.extend(copies_of(door, 1, 3..4, black));
    parts.push(part(
        1,
        cuboid([0.09, 0.0006, 0.065]),
        [0.11, -0.0256, 0.0],
        rgb(30, 32, 36),
    ));
    parts.extend(copies_of(door, 1, 0..3, metal));
    parts
}

pub(crate) fn wine_rack(def: &ObjectDef) -> Vec<VisualPart> {
    // Four tilted planks in light wood on a mahogany stand.
    let root = &def.bodies[ROOT];
    let mut parts = copies_of(root, ROOT, 0..4, rgb(208, 171, 133));
    parts.extend(copies_of(root, ROOT, 4..root.geoms.len(), rgb(77, 24, 7)));
    parts
}

pub(crate) fn desk_caddy(def: &ObjectDef) -> Vec<VisualPart> {
    let root = &def.bodies[ROOT];
    copies_of(root, ROOT, 0..root.geoms.len(), rgb(120, 80, 50))
}
