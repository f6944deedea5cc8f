//! Building blocks for the procedural looks: colours, part constructors, swept-capsule tubes,
//! and visual copies of collision geoms.

use crate::catalog::frames;
use crate::catalog::model::{ColliderShape, Recipe, VisualPart};
use crate::catalog::spec::{BodyDef, IDENTITY};

/// Opaque colour from 8-bit sRGB components (the textures' and reference images' units).
pub(crate) const fn rgb(r: u8, g: u8, b: u8) -> [f32; 4] {
    [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0]
}

/// Quarter turn about x that maps the recipe's axis (local z) onto +y, for items whose long
/// axis is the object's y.
pub(crate) fn z_to_y() -> [f64; 4] {
    frames::about_axis([1.0, 0.0, 0.0], -core::f64::consts::FRAC_PI_2)
}

/// An axis-aligned part at `pos`.
pub(crate) fn part(body: usize, recipe: Recipe, pos: [f64; 3], rgba: [f32; 4]) -> VisualPart {
    VisualPart {
        body,
        recipe,
        pos,
        quat_wxyz: IDENTITY,
        scale: [1.0; 3],
        rgba,
    }
}

impl VisualPart {
    /// The same part rotated by `quat` about its own origin.
    pub(crate) fn turned(mut self, quat: [f64; 4]) -> Self {
        self.quat_wxyz = frames::normalize(quat);
        self
    }

    /// The same part stretched along its local axes before rotation.
    pub(crate) fn stretched(mut self, scale: [f64; 3]) -> Self {
        self.scale = scale;
        self
    }
}

pub(crate) fn cuboid(half: [f64; 3]) -> Recipe {
    Recipe::Box { half }
}

pub(crate) fn cylinder(radius: f64, half_height: f64) -> Recipe {
    Recipe::Cylinder {
        radius,
        half_height,
    }
}

/// A surface of revolution through `(radius, z)` points; see [`Recipe::Lathe`].
pub(crate) fn lathe(profile: &[(f64, f64)]) -> Recipe {
    Recipe::Lathe {
        profile: profile.to_vec(),
        closed: false,
    }
}

/// A bent rod (mug or pot handle) as capsules between consecutive points.
pub(crate) fn tube(
    body: usize,
    points: &[[f64; 3]],
    radius: f64,
    rgba: [f32; 4],
) -> Vec<VisualPart> {
    points
        .windows(2)
        .map(|w| {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let mid = [
                (w[0][0] + w[1][0]) / 2.0,
                (w[0][1] + w[1][1]) / 2.0,
                (w[0][2] + w[1][2]) / 2.0,
            ];
            let capsule = Recipe::Capsule {
                radius,
                half_height: len / 2.0,
            };
            part(body, capsule, mid, rgba).turned(z_onto([d[0] / len, d[1] / len, d[2] / len]))
        })
        .collect()
}

/// Shortest rotation taking +z onto the unit vector `d` (half-way quaternion; `d = -z` turns
/// about x).
fn z_onto(d: [f64; 3]) -> [f64; 4] {
    if d[2] < -1.0 + 1e-12 {
        return [0.0, 1.0, 0.0, 0.0];
    }
    frames::normalize([1.0 + d[2], -d[1], d[0], 0.0])
}

/// Visual copies of collision geoms `indices` of `def`, so a box-built object looks exactly
/// where its physics is.
pub(crate) fn copies_of(
    def: &BodyDef,
    body: usize,
    indices: core::ops::Range<usize>,
    rgba: [f32; 4],
) -> Vec<VisualPart> {
    def.geoms[indices]
        .iter()
        .map(|g| {
            let recipe = match g.shape {
                ColliderShape::Box { half_size } => cuboid(half_size),
                ColliderShape::Capsule {
                    radius,
                    half_length,
                } => Recipe::Capsule {
                    radius,
                    half_height: half_length,
                },
            };
            part(body, recipe, g.pos, rgba).turned(g.quat)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tube_segments_join_the_points() {
        let pts = [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.1, 0.0, 0.2]];
        let parts = tube(0, &pts, 0.01, rgb(0, 0, 0));
        assert_eq!(parts.len(), 2);
        for (p, w) in parts.iter().zip(pts.windows(2)) {
            let Recipe::Capsule { half_height, .. } = p.recipe else {
                panic!("not a capsule")
            };
            let tip = frames::rotate(p.quat_wxyz, [0.0, 0.0, half_height]);
            let end = [p.pos[0] + tip[0], p.pos[1] + tip[1], p.pos[2] + tip[2]];
            for k in 0..3 {
                assert!((end[k] - w[1][k]).abs() < 1e-12, "{end:?} vs {:?}", w[1]);
            }
        }
    }

    #[test]
    fn z_onto_handles_every_direction() {
        for d in [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ] {
            let v = frames::rotate(z_onto(d), [0.0, 0.0, 1.0]);
            for k in 0..3 {
                assert!((v[k] - d[k]).abs() < 1e-12, "{d:?} -> {v:?}");
            }
        }
        let y = frames::rotate(z_to_y(), [0.0, 0.0, 1.0]);
        assert!((y[1] - 1.0).abs() < 1e-12, "{y:?}");
    }
}
