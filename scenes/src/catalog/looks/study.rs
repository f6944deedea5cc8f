//! Looks of the study objects (`facts/study.rs`): the cups in three saturated plastic colours
//! (so an instruction or a note can name them), the note plain white (its text is drawn on it
//! by the environment).

use super::kit::{cuboid, lathe, part, rgb};
use crate::catalog::facts::study::{CUP_FOOT_RADIUS, CUP_HEIGHT, CUP_RIM_RADIUS, NOTE_HALF};
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

/// Foot to rim outside, then the inside back down to the centre of the floor.
fn cup(rgba: [f32; 4]) -> Vec<VisualPart> {
    let wall = 0.0025;
    let profile = [
        (0.0, 0.0),
        (CUP_FOOT_RADIUS, 0.0),
        (CUP_RIM_RADIUS, CUP_HEIGHT),
        (CUP_RIM_RADIUS - wall, CUP_HEIGHT),
        (CUP_FOOT_RADIUS - wall, wall),
        (0.0, wall),
    ];
    vec![part(0, lathe(&profile), [0.0; 3], rgba)]
}

pub(crate) fn red_plastic_cup(_: &ObjectDef) -> Vec<VisualPart> {
    cup(rgb(200, 40, 40))
}

pub(crate) fn blue_plastic_cup(_: &ObjectDef) -> Vec<VisualPart> {
    cup(rgb(40, 80, 200))
}

pub(crate) fn green_plastic_cup(_: &ObjectDef) -> Vec<VisualPart> {
    cup(rgb(40, 160, 70))
}

pub(crate) fn paper_note(_: &ObjectDef) -> Vec<VisualPart> {
    vec![part(0, cuboid(NOTE_HALF), [0.0; 3], rgb(245, 245, 240))]
}
