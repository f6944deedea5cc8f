//! Axis-aligned bounds of collision geoms and visual parts in their body frame: for overlap
//! checks when placing objects, and to check that a look sits where the physics is.

use serde::{Deserialize, Serialize};

use super::frames;
use super::model::{Collider, ColliderShape, ObjectModel, Recipe, VisualPart};

/// An axis-aligned box `[min, max]` in a body frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    /// The smallest box holding both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: [0, 1, 2].map(|k| self.min[k].min(other.min[k])),
            max: [0, 1, 2].map(|k| self.max[k].max(other.max[k])),
        }
    }

    /// Whether `self` lies inside `outer` grown by `margin` on every side.
    pub fn within(&self, outer: &Aabb, margin: f64) -> bool {
        (0..3).all(|k| self.min[k] >= outer.min[k] - margin && self.max[k] <= outer.max[k] + margin)
    }

    /// Bounds of the box `[-half, half]` after stretching by `scale`, rotating by `quat` and
    /// moving to `pos`.
    fn of_posed_box(half: [f64; 3], scale: [f64; 3], pos: [f64; 3], quat: [f64; 4]) -> Aabb {
        let m = frames::to_matrix(quat);
        let h = [half[0] * scale[0], half[1] * scale[1], half[2] * scale[2]];
        let extent = [0, 1, 2].map(|i| (0..3).map(|j| m[i][j].abs() * h[j]).sum::<f64>());
        Aabb {
            min: [0, 1, 2].map(|k| pos[k] - extent[k]),
            max: [0, 1, 2].map(|k| pos[k] + extent[k]),
        }
    }
}

impl Collider {
    /// Bounds in the body frame.
    pub fn aabb(&self) -> Aabb {
        let half = match self.shape {
            ColliderShape::Box { half_size } => half_size,
            ColliderShape::Capsule {
                radius,
                half_length,
            } => [radius, radius, half_length + radius],
        };
        Aabb::of_posed_box(half, [1.0; 3], self.pos, self.quat_wxyz)
    }
}

impl VisualPart {
    /// Bounds in the body frame (for round recipes, of their bounding box).
    pub fn aabb(&self) -> Aabb {
        let (half, center) = match &self.recipe {
            Recipe::Box { half } => (*half, [0.0; 3]),
            Recipe::Cylinder {
                radius,
                half_height,
            } => ([*radius, *radius, *half_height], [0.0; 3]),
            Recipe::Capsule {
                radius,
                half_height,
            } => ([*radius, *radius, half_height + radius], [0.0; 3]),
            Recipe::Sphere { radius } => ([*radius; 3], [0.0; 3]),
            Recipe::Lathe { profile, .. } => {
                let r = profile.iter().map(|p| p.0).fold(0.0, f64::max);
                let lo = profile.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
                let hi = profile
                    .iter()
                    .map(|p| p.1)
                    .fold(f64::NEG_INFINITY, f64::max);
                ([r, r, (hi - lo) / 2.0], [0.0, 0.0, (hi + lo) / 2.0])
            }
        };
        let offset = frames::rotate(self.quat_wxyz, [0, 1, 2].map(|k| center[k] * self.scale[k]));
        let pos = [0, 1, 2].map(|k| self.pos[k] + offset[k]);
        Aabb::of_posed_box(half, self.scale, pos, self.quat_wxyz)
    }
}

impl ObjectModel {
    /// Bounds of all colliders of body `body`, in its frame; `None` for a body without any.
    pub fn collision_aabb(&self, body: usize) -> Option<Aabb> {
        let colliders = &self.bodies.get(body)?.colliders;
        colliders
            .iter()
            .map(Collider::aabb)
            .reduce(|a, b| a.union(&b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turned_box_bounds_grow_with_the_turn() {
        let q = frames::about_axis([0.0, 0.0, 1.0], core::f64::consts::FRAC_PI_4);
        let b = Aabb::of_posed_box([1.0, 1.0, 0.5], [1.0; 3], [1.0, 0.0, 0.0], q);
        let r = 2.0_f64.sqrt();
        assert!((b.max[0] - (1.0 + r)).abs() < 1e-12 && (b.min[1] + r).abs() < 1e-12);
        assert!((b.max[2] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn stretched_lathe_bounds_follow_the_profile() {
        let part = VisualPart {
            body: 0,
            recipe: Recipe::Lathe {
                profile: vec![(0.0, 0.1), (0.02, 0.1), (0.02, 0.3), (0.0, 0.3)],
                closed: false,
            },
            pos: [0.0; 3],
            quat_wxyz: [1.0, 0.0, 0.0, 0.0],
            scale: [1.0, 0.5, 1.0],
            rgba: [1.0; 4],
        };
        let b = part.aabb();
        assert!(
            (b.min[2] - 0.1).abs() < 1e-12 && (b.max[2] - 0.3).abs() < 1e-12,
            "{b:?}"
        );
        assert!(
            (b.max[0] - 0.02).abs() < 1e-12 && (b.max[1] - 0.01).abs() < 1e-12,
            "{b:?}"
        );
        let outer = Aabb {
            min: [-0.02, -0.01, 0.1],
            max: [0.02, 0.01, 0.3],
        };
        assert!(
            b.within(&outer, 1e-12)
                && !b.within(
                    &Aabb {
                        max: [0.02, 0.01, 0.29],
                        ..outer
                    },
                    1e-3
                )
        );
    }
}
