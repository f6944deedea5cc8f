//! Looks of the TurboSquid movables. Colours:
//! - wine bottle: glass rgba (0.004, 0.036, 0.002) from its XML material, cork foil = mean of
//!   `cork_texture.png` (227, 178, 115), label = light texels of `label_wine.png`;
//! - moka pot: mean of `metal_diff.png` (151, 148, 146) and `rubber_black.png` (30, 30, 30);
//! - mugs: the reference render's stand-ins (white 240, red (170, 30, 30), pale yellow
//!   (240, 230, 160), here split into a white outside and a yellow inside and handle);
//! - book: black cover, white pages (`black_book_texture.png` is 76 % white, 18 % black).

use super::kit::{copies_of, cuboid, cylinder, lathe, part, rgb, tube};
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

const ROOT: usize = 0;

pub(crate) fn wine_bottle(_: &ObjectDef) -> Vec<VisualPart> {
    let glass = [
        (0.0, 0.0011),
        (0.0205, 0.0011),
        (0.0215, 0.004),
        (0.0215, 0.056),
        (0.0203, 0.066),
        (0.0182, 0.075),
        (0.0163, 0.084),
        (0.0122, 0.094),
        (0.0095, 0.103),
        (0.0079, 0.112),
        (0.0076, 0.122),
        (0.0079, 0.139),
        (0.0, 0.139),
    ];
    vec![
        part(ROOT, lathe(&glass), [0.0; 3], rgb(6, 20, 8)),
        part(
            ROOT,
            cylinder(0.0218, 0.021),
            [0.0, 0.0, 0.031],
            rgb(225, 215, 190),
        ),
        part(
            ROOT,
            cylinder(0.0082, 0.0095),
            [0.0, 0.0, 0.1485],
            rgb(227, 178, 115),
        ),
    ]
}

pub(crate) fn moka_pot(def: &ObjectDef) -> Vec<VisualPart> {
    // Octagonal aluminium pot as a lathe: boiler, pinched waist, jug, lid.
    let body = [
        (0.0, -0.0661),
        (0.0395, -0.0661),
        (0.0405, -0.022),
        (0.0345, -0.009),
        (0.030, 0.002),
        (0.0345, 0.013),
        (0.039, 0.054),
        (0.0395, 0.062),
        (0.022, 0.066),
        (0.0, 0.066),
    ];
    let metal = rgb(151, 148, 146);
    let black = rgb(30, 30, 30);
    let mut parts = vec![part(ROOT, lathe(&body), [0.0; 3], metal)];
    // Spout: the two collision boxes at -y.
    parts.extend(copies_of(&def.bodies[ROOT], ROOT, 7..9, metal));
    // Lid knob and the handle at +y.
    parts.push(part(
        ROOT,
        cylinder(0.005, 0.009),
        [0.0, -0.0013, 0.0745],
        black,
    ));
    parts.push(part(
        ROOT,
        cuboid([0.0052, 0.0058, 0.002]),
        [0.0, -0.0013, 0.0835],
        black,
    ));
    let handle = [
        [0.0, 0.038, 0.055],
        [0.0, 0.058, 0.063],
        [0.0, 0.076, 0.056],
        [0.0, 0.074, 0.028],
        [0.0, 0.063, 0.005],
        [0.0, 0.052, -0.004],
    ];
    parts.extend(tube(ROOT, &handle, 0.0062, black));
    parts
}

/// A mug around the vertical axis through `(cx, 0)`: outside and rim in `outside`, the inside in
/// `inside`, and a handle through `handle` (x, z points in the y = 0 plane).
fn mug(
    cx: f64,
    outer: &[(f64, f64)],
    inner: &[(f64, f64)],
    handle: &[[f64; 2]],
    outside: [f32; 4],
    inside: [f32; 4],
    grip: [f32; 4],
) -> Vec<VisualPart> {
    let points: Vec<[f64; 3]> = handle.iter().map(|p| [p[0], 0.0, p[1]]).collect();
    let mut parts = vec![
        part(ROOT, lathe(outer), [cx, 0.0, 0.0], outside),
        part(ROOT, lathe(inner), [cx, 0.0, 0.0], inside),
    ];
    parts.extend(tube(ROOT, &points, 0.0058, grip));
    parts
}

pub(crate) fn porcelain_mug(_: &ObjectDef) -> Vec<VisualPart> {
    let white = rgb(240, 240, 240);
    mug(
        0.0125,
        &[
            (0.0, 0.0024),
            (0.030, 0.0024),
            (0.038, 0.008),
            (0.044, 0.02),
            (0.047, 0.035),
            (0.0475, 0.06),
            (0.0475, 0.1085),
            (0.0435, 0.1085),
        ],
        &[
            (0.0435, 0.1085),
            (0.0435, 0.06),
            (0.042, 0.035),
            (0.036, 0.016),
            (0.0, 0.011),
        ],
        &[
            [-0.033, 0.094],
            [-0.048, 0.092],
            [-0.058, 0.080],
            [-0.0605, 0.057],
            [-0.057, 0.036],
            [-0.046, 0.024],
            [-0.033, 0.022],
        ],
        white,
        white,
        white,
    )
}

pub(crate) fn red_coffee_mug(_: &ObjectDef) -> Vec<VisualPart> {
    let red = rgb(170, 30, 30);
    mug(
        -0.0163,
        &[
            (0.0, -0.0018),
            (0.036, -0.0018),
            (0.039, 0.01),
            (0.042, 0.05),
            (0.0445, 0.1),
            (0.045, 0.1308),
            (0.0415, 0.1308),
        ],
        &[
            (0.0415, 0.1308),
            (0.041, 0.1),
            (0.038, 0.05),
            (0.035, 0.012),
            (0.0, 0.008),
        ],
        &[
            [0.027, 0.030],
            [0.045, 0.050],
            [0.055, 0.075],
            [0.0555, 0.098],
            [0.048, 0.112],
            [0.027, 0.113],
        ],
        red,
        rgb(150, 26, 26),
        red,
    )
}

pub(crate) fn white_yellow_mug(_: &ObjectDef) -> Vec<VisualPart> {
    let yellow = rgb(240, 205, 90);
    mug(
        -0.018,
        &[
            (0.0, 0.0002),
            (0.027, 0.0002),
            (0.036, 0.006),
            (0.042, 0.016),
            (0.050, 0.024),
            (0.0528, 0.035),
            (0.0528, 0.1031),
            (0.049, 0.1031),
        ],
        &[
            (0.049, 0.1031),
            (0.049, 0.035),
            (0.045, 0.022),
            (0.036, 0.012),
            (0.0, 0.0085),
        ],
        &[
            [0.033, 0.026],
            [0.058, 0.027],
            [0.0635, 0.040],
            [0.0635, 0.072],
            [0.058, 0.080],
            [0.033, 0.080],
        ],
        rgb(242, 240, 232),
        yellow,
        yellow,
    )
}

pub(crate) fn black_book(_: &ObjectDef) -> Vec<VisualPart> {
    // Standing book (collision box centre (-0.0005, -0.0122, 0.0694), half (0.0143, 0.0552,
    // 0.0672)): two boards and the spine at -y in black, the page block showing at +y, top, bottom.
    let (cx, cy, cz) = (-0.0005, -0.0122, 0.0694);
    let (hx, hy, hz) = (0.0143, 0.0552, 0.0672);
    let board = 0.0015;
    let black = rgb(22, 22, 24);
    let mut parts: Vec<VisualPart> = [-1.0, 1.0]
        .iter()
        .map(|s| {
            part(
                ROOT,
                cuboid([board, hy, hz]),
                [cx + s * (hx - board), cy, cz],
                black,
            )
        })
        .collect();
    parts.push(part(
        ROOT,
        cuboid([hx - 2.0 * board, board, hz]),
        [cx, cy - hy + board, cz],
        black,
    ));
    parts.push(part(
        ROOT,
        cuboid([hx - 2.0 * board, hy - 2.5 * board, hz - 1.5 * board]),
        [cx, cy + 0.5 * board, cz],
        rgb(235, 233, 225),
    ));
    parts
}
