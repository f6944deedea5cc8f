//! Looks of the scanned tableware. Profiles follow the collision boxes (and, where LIBERO ships
//! it, the visual mesh's outline); colours:
//! - bowl: near-black glaze, as the reference render's stand-in texture (30, 30, 30);
//! - plate: white (230, 230, 230);
//! - ramekin: white porcelain (texture: 30 % of texels ≈ 240) seen grey-silver in
//!   `libero_spatial_task0_init0_agentview_step00.png`;
//! - basket: wicker brown (150, 110, 70), the reference render's stand-in;
//! - frying pan: dark non-stick (texture mean of the non-background texels ≈ 40).

use super::kit::{copies_of, lathe, part, rgb};
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

const ROOT: usize = 0;

pub(crate) fn akita_black_bowl(_: &ObjectDef) -> Vec<VisualPart> {
    // Outside from the foot up to the rim, then the inside back down to the centre.
    let profile = [
        (0.0, 0.0016),
        (0.029, 0.0016),
        (0.036, 0.007),
        (0.041, 0.012),
        (0.045, 0.018),
        (0.0475, 0.026),
        (0.0495, 0.036),
        (0.0515, 0.045),
        (0.0535, 0.052),
        (0.0495, 0.052),
        (0.0475, 0.043),
        (0.0455, 0.034),
        (0.042, 0.023),
        (0.036, 0.0135),
        (0.027, 0.0085),
        (0.0, 0.0068),
    ];
    vec![part(ROOT, lathe(&profile), [0.0; 3], rgb(30, 30, 32))]
}

pub(crate) fn plate(_: &ObjectDef) -> Vec<VisualPart> {
    let profile = [
        (0.0, 0.0),
        (0.045, 0.0),
        (0.0475, 0.0016),
        (0.0525, 0.0033),
        (0.0565, 0.005),
        (0.060, 0.0066),
        (0.063, 0.0083),
        (0.066, 0.010),
        (0.0686, 0.0125),
        (0.0686, 0.0160),
        (0.0655, 0.0160),
        (0.062, 0.0125),
        (0.055, 0.0085),
        (0.047, 0.0058),
        (0.0, 0.0052),
    ];
    vec![part(ROOT, lathe(&profile), [0.0; 3], rgb(230, 230, 230))]
}

pub(crate) fn glazed_rim_porcelain_ramekin(_: &ObjectDef) -> Vec<VisualPart> {
    let body = [
        (0.0, 0.0007),
        (0.038, 0.0007),
        (0.0402, 0.004),
        (0.0408, 0.013),
        (0.0415, 0.025),
        (0.043, 0.035),
        (0.0445, 0.0405),
        (0.0445, 0.0427),
        (0.040, 0.0427),
        (0.0378, 0.035),
        (0.0352, 0.015),
        (0.030, 0.0078),
        (0.0, 0.0075),
    ];
    // The glazed rim: a slightly darker band round the top of the wall.
    let rim = [(0.0448, 0.0368), (0.0449, 0.0408)];
    vec![
        part(ROOT, lathe(&body), [0.0; 3], rgb(214, 216, 220)),
        part(ROOT, lathe(&rim), [0.0; 3], rgb(150, 156, 165)),
    ]
}

pub(crate) fn basket(def: &ObjectDef) -> Vec<VisualPart> {
    // Floor (darker) and four slightly splayed walls, exactly the collision boxes.
    let root = &def.bodies[ROOT];
    let mut parts = copies_of(root, ROOT, 0..1, rgb(120, 86, 52));
    parts.extend(copies_of(root, ROOT, 1..5, rgb(150, 110, 70)));
    parts
}

pub(crate) fn chefmate_8_frypan(def: &ObjectDef) -> Vec<VisualPart> {
    let pan = [
        (0.0, 0.001),
        (0.070, 0.001),
        (0.084, 0.005),
        (0.093, 0.018),
        (0.098, 0.0415),
        (0.094, 0.0415),
        (0.089, 0.019),
        (0.080, 0.0135),
        (0.0, 0.0130),
    ];
    let mut parts = vec![part(ROOT, lathe(&pan), [0.0; 3], rgb(40, 40, 42))];
    // The handle is the three collision boxes along +x.
    parts.extend(copies_of(&def.bodies[ROOT], ROOT, 0..3, rgb(24, 24, 24)));
    parts
}
