//! Looks of the HOPE grocery items: a body in the main package colour plus a label band or panel
//! so the items tell apart. Their texture maps are not in our LIBERO copy; colours are read off
//! the reference renders (`libero_object_task0_init0_agentview_step00.png`,
//! `libero_10_task0_init0_agentview_step00.png`, `libero_spatial_task0_init0_agentview_step00.png`)
//! and brightened to albedo. BBQ sauce and chocolate pudding appear in no reference render; their
//! colours follow the real products (dark sauce with a yellow label, brown box).

use super::kit::{cuboid, cylinder, lathe, part, rgb, z_to_y};
use crate::catalog::frames;
use crate::catalog::model::VisualPart;
use crate::catalog::spec::ObjectDef;

const ROOT: usize = 0;

/// A flat box with a band of another colour wrapped round its middle (across x).
fn banded_box(
    center: [f64; 3],
    half: [f64; 3],
    body: [f32; 4],
    band_half_x: f64,
    band: [f32; 4],
) -> Vec<VisualPart> {
    let wrap = [band_half_x, half[1] + 0.0003, half[2] + 0.0003];
    vec![
        part(ROOT, cuboid(half), center, body),
        part(ROOT, cuboid(wrap), center, band),
    ]
}

/// A can lying along y: metal cylinder with a label round most of its length.
fn can(center: [f64; 3], radius: f64, half_length: f64, label: [f32; 4]) -> Vec<VisualPart> {
    vec![
        part(
            ROOT,
            cylinder(radius, half_length),
            center,
            rgb(185, 185, 190),
        )
        .turned(z_to_y()),
        part(
            ROOT,
            cylinder(radius + 0.0004, half_length - 0.008),
            center,
            label,
        )
        .turned(z_to_y()),
    ]
}

/// A gable-top carton lying along y (top towards +y): box, roof, sealed ridge and a label band.
fn carton(x: f64, side: [f32; 4], roof: [f32; 4], band: [f32; 4]) -> Vec<VisualPart> {
    let h = 0.02625;
    let roof_quat = frames::about_axis([1.0, 0.0, 0.0], core::f64::consts::FRAC_PI_4);
    vec![
        part(ROOT, cuboid([h, 0.05475, h]), [x, -0.015, 0.0], side),
        // A square prism turned 45° about x: its upper half is the roof, the ridge at y = 0.0614.
        // Roof and ridge are a little narrower in x than the box so their ends do not z-fight.
        part(
            ROOT,
            cuboid([
                h - 0.0004,
                h / core::f64::consts::SQRT_2,
                h / core::f64::consts::SQRT_2,
            ]),
            [x, 0.0351, 0.0],
            roof,
        )
        .turned(roof_quat),
        part(
            ROOT,
            cuboid([h - 0.0008, 0.0023, 0.0012]),
            [x, 0.0602, 0.0],
            roof,
        ),
        part(
            ROOT,
            cuboid([h + 0.0003, 0.012, h + 0.0003]),
            [x, -0.035, 0.0],
            band,
        ),
    ]
}

pub(crate) fn cookies(_: &ObjectDef) -> Vec<VisualPart> {
    // Red box with the cookie picture on both large faces.
    let mut parts = vec![part(
        ROOT,
        cuboid([0.031, 0.0413, 0.0094]),
        [0.0; 3],
        rgb(190, 70, 55),
    )];
    for z in [-0.0096, 0.0096] {
        parts.push(part(
            ROOT,
            cuboid([0.024, 0.033, 0.0004]),
            [0.0, 0.0, z],
            rgb(215, 170, 80),
        ));
    }
    parts
}

pub(crate) fn alphabet_soup(_: &ObjectDef) -> Vec<VisualPart> {
    can([0.0, -0.0005, -0.0037], 0.031, 0.038, rgb(45, 75, 145))
}

pub(crate) fn tomato_sauce(_: &ObjectDef) -> Vec<VisualPart> {
    let center = [0.0, -0.0005, -0.0033];
    let mut parts = can(center, 0.031, 0.038, rgb(165, 45, 18));
    parts.push(part(ROOT, cylinder(0.0317, 0.008), center, rgb(35, 115, 45)).turned(z_to_y()));
    parts
}

pub(crate) fn bbq_sauce(_: &ObjectDef) -> Vec<VisualPart> {
    // Standing bottle with an oval cross-section (x 0.0235, y 0.0145): a lathe squeezed in y.
    let squeeze = [1.0, 0.0145 / 0.0235, 1.0];
    let bottle = [
        (0.0, -0.0546),
        (0.0225, -0.0546),
        (0.0235, -0.051),
        (0.0235, -0.004),
        (0.0205, 0.006),
        (0.0181, 0.016),
        (0.0143, 0.027),
        (0.0, 0.027),
    ];
    vec![
        part(ROOT, lathe(&bottle), [0.0; 3], rgb(95, 35, 18)).stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0238, 0.015),
            [0.0, 0.0, -0.028],
            rgb(215, 170, 75),
        )
        .stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0131, 0.0134),
            [0.0, 0.0, 0.0391],
            rgb(40, 20, 15),
        ),
    ]
}

pub(crate) fn butter(_: &ObjectDef) -> Vec<VisualPart> {
    banded_box(
        [0.0; 3],
        [0.0381, 0.0198, 0.0087],
        rgb(215, 110, 30),
        0.012,
        rgb(228, 224, 215),
    )
}

pub(crate) fn chocolate_pudding(_: &ObjectDef) -> Vec<VisualPart> {
    banded_box(
        [-0.0005, 0.0, 0.0006],
        [0.0401, 0.0232, 0.0137],
        rgb(110, 60, 30),
        0.014,
        rgb(220, 190, 140),
    )
}

pub(crate) fn cream_cheese(_: &ObjectDef) -> Vec<VisualPart> {
    banded_box(
        [0.0; 3],
        [0.0406, 0.0213, 0.0089],
        rgb(60, 75, 160),
        0.013,
        rgb(200, 205, 215),
    )
}

pub(crate) fn ketchup(_: &ObjectDef) -> Vec<VisualPart> {
    // Squeeze bottle lying along y, oval (x 0.028, z 0.018), white cap at +y.
    let squeeze = [1.0, 0.018 / 0.0278, 1.0];
    let bottle = [
        (0.0, -0.0724),
        (0.0265, -0.0724),
        (0.0278, -0.069),
        (0.0278, -0.010),
        (0.0245, 0.008),
        (0.021, 0.020),
        (0.0185, 0.034),
        (0.0, 0.034),
    ];
    let axis = [0.0004, 0.0, 0.0008];
    vec![
        part(ROOT, lathe(&bottle), axis, rgb(175, 40, 20))
            .turned(z_to_y())
            .stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0281, 0.018),
            [0.0004, -0.035, 0.0008],
            rgb(235, 225, 200),
        )
        .turned(z_to_y())
        .stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0155, 0.0185),
            [0.0004, 0.0547, 0.0008],
            rgb(235, 235, 230),
        )
        .turned(z_to_y()),
    ]
}

pub(crate) fn salad_dressing(_: &ObjectDef) -> Vec<VisualPart> {
    // Bottle lying along y, oval (x 0.026, z 0.0173), green cap at +y.
    let squeeze = [1.0, 0.0173 / 0.026, 1.0];
    let bottle = [
        (0.0, -0.0727),
        (0.018, -0.0727),
        (0.022, -0.066),
        (0.026, -0.052),
        (0.026, -0.010),
        (0.024, 0.001),
        (0.018, 0.013),
        (0.0135, 0.036),
        (0.0, 0.036),
    ];
    let axis = [-0.001, 0.0, 0.0002];
    vec![
        part(ROOT, lathe(&bottle), axis, rgb(165, 170, 150))
            .turned(z_to_y())
            .stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0263, 0.016),
            [-0.001, -0.03, 0.0002],
            rgb(225, 215, 170),
        )
        .turned(z_to_y())
        .stretched(squeeze),
        part(
            ROOT,
            cylinder(0.0155, 0.0187),
            [0.0001, 0.0542, 0.0004],
            rgb(20, 90, 45),
        )
        .turned(z_to_y()),
    ]
}

pub(crate) fn milk(_: &ObjectDef) -> Vec<VisualPart> {
    carton(
        0.00037,
        rgb(190, 45, 25),
        rgb(232, 228, 222),
        rgb(240, 238, 232),
    )
}

pub(crate) fn orange_juice(_: &ObjectDef) -> Vec<VisualPart> {
    carton(
        -0.00037,
        rgb(230, 140, 25),
        rgb(245, 215, 120),
        rgb(240, 235, 225),
    )
}
