//! Triangle meshes for the catalog's procedural recipes, each built once and shared.
//!
//! Round shapes use a fixed number of segments chosen for 256² cameras: enough that a bowl or
//! can looks round at a hand's length from the wrist camera, few enough that a full LIBERO scene
//! stays at a few thousand triangles. Boxes are split into quads by size, because lighting is
//! per vertex (as in MuJoCo) and a large face lit only at its corners shows no spot-light falloff.

use std::collections::BTreeMap;
use std::sync::Arc;

use vifo_render::Mesh;
use vifo_render::glam::Vec3;

use crate::catalog::Recipe;

/// Segments around turned shapes (lathes, cylinders, capsules, spheres).
pub const ROUND_SEGMENTS: u32 = 16;
/// Box faces get one quad per this many metres of edge (at least one, at most four).
const BOX_QUAD_EDGE: f64 = 0.3;

/// The mesh of one recipe (in the recipe's own frame, before any part scale).
pub fn mesh_of(recipe: &Recipe) -> Mesh {
    let f = |x: f64| x as f32;
    match recipe {
        Recipe::Lathe { profile, closed } => {
            let points: Vec<(f32, f32)> = profile.iter().map(|&(r, z)| (f(r), f(z))).collect();
            if *closed { Mesh::lathe_capped(&points, ROUND_SEGMENTS) } else { Mesh::lathe(&points, ROUND_SEGMENTS) }
        }
        Recipe::Box { half } => {
            let longest = half.iter().fold(0.0f64, |m, &h| m.max(2.0 * h));
            let quads = (longest / BOX_QUAD_EDGE).ceil().clamp(1.0, 4.0) as u32;
            Mesh::cuboid_tessellated(Vec3::new(f(half[0]), f(half[1]), f(half[2])), quads)
        }
        Recipe::Cylinder { radius, half_height } => Mesh::cylinder(f(*radius), f(*half_height), ROUND_SEGMENTS),
        Recipe::Capsule { radius, half_height } => Mesh::capsule(f(*radius), f(*half_height), ROUND_SEGMENTS),
        Recipe::Sphere { radius } => Mesh::sphere(f(*radius), ROUND_SEGMENTS),
    }
}

/// An exact key for a recipe: its variant and the bits of every number, so equal recipes (two
/// bowls of one category, the cabinet's repeated handles) share one mesh.
fn key(recipe: &Recipe) -> Vec<u64> {
    match recipe {
        Recipe::Lathe { profile, closed } => {
            let mut k = vec![0, u64::from(*closed)];
            k.extend(profile.iter().flat_map(|&(r, z)| [r.to_bits(), z.to_bits()]));
            k
        }
        Recipe::Box { half } => vec![1, half[0].to_bits(), half[1].to_bits(), half[2].to_bits()],
        Recipe::Cylinder { radius, half_height } => vec![2, radius.to_bits(), half_height.to_bits()],
        Recipe::Capsule { radius, half_height } => vec![3, radius.to_bits(), half_height.to_bits()],
        Recipe::Sphere { radius } => vec![4, radius.to_bits()],
    }
}

/// Meshes by recipe; cloning an `Arc` is all a repeated recipe costs.
#[derive(Default)]
pub struct MeshCache {
    meshes: BTreeMap<Vec<u64>, Arc<Mesh>>,
}

impl MeshCache {
    pub fn get(&mut self, recipe: &Recipe) -> Arc<Mesh> {
        self.meshes.entry(key(recipe)).or_insert_with(|| Arc::new(mesh_of(recipe))).clone()
    }

    /// Distinct meshes built so far.
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_recipes_share_one_mesh_and_others_do_not() {
        let mut cache = MeshCache::default();
        let a = cache.get(&Recipe::Box { half: [0.1, 0.2, 0.3] });
        let b = cache.get(&Recipe::Box { half: [0.1, 0.2, 0.3] });
        let c = cache.get(&Recipe::Box { half: [0.1, 0.2, 0.30000000000000004] });
        let d = cache.get(&Recipe::Cylinder { radius: 0.1, half_height: 0.2 });
        assert!(Arc::ptr_eq(&a, &b));
        assert!(!Arc::ptr_eq(&a, &c));
        assert_eq!(cache.len(), 3);
        assert!(d.triangle_count() > 0);
    }

    #[test]
    fn large_boxes_are_tessellated_small_ones_are_not() {
        let small = mesh_of(&Recipe::Box { half: [0.02, 0.02, 0.02] });
        let large = mesh_of(&Recipe::Box { half: [0.5, 0.6, 0.025] });
        assert_eq!(small.triangle_count(), 12);
        assert_eq!(large.triangle_count(), 12 * 16);
    }

    #[test]
    fn every_catalog_recipe_gives_a_mesh_within_its_bounds() {
        for model in crate::catalog::all() {
            for part in &model.visuals {
                let mesh = mesh_of(&part.recipe);
                assert!(mesh.triangle_count() > 0, "{}: {:?}", model.category, part.recipe);
                assert!(mesh.bounds().radius < 1.0, "{}: {:?}", model.category, part.recipe);
            }
        }
    }
}
