//! Vertex clustering: a coarser copy of a dense mesh for when its triangles are far smaller than
//! a pixel (LIBERO's scanned objects have 10-60 k triangles each; most cover no pixel centre at
//! 256² but each still costs a setup).
//!
//! Vertices are grouped by the cell of a uniform grid their position falls in, by their normal
//! rounded to about 30° (so hard edges stay hard) and, for textured meshes, by the cell of a UV
//! grid (so texture seams stay seams); each group becomes one vertex at the group's mean
//! position, UV and normal. Triangles whose corners collapse are
//! dropped. Deterministic: groups and sums follow vertex order.

use std::collections::BTreeMap;

use glam::{DVec2, DVec3, IVec3, Vec2, Vec3};

use crate::mesh::Mesh;

/// UV cells per unit: a texture chart keeps its shape to 1/64 of the texture.
const UV_CELLS: f32 = 64.0;

impl Mesh {
    /// The mesh with vertices merged per `cell`-sized cube (in the mesh's own units); `None` when
    /// that removes nothing or leaves no triangle.
    pub fn clustered(&self, cell: f32) -> Option<Mesh> {
        if !(cell > 0.0 && cell.is_finite()) {
            return None;
        }
        let uvs = self.uvs();
        let key = |i: usize| {
            let p = (self.positions()[i] / cell).floor();
            let uv = uvs.map_or(Vec2::ZERO, |u| (u[i] * UV_CELLS).floor());
            let n = (self.normals()[i] * 2.0).round();
            (IVec3::new(p.x as i32, p.y as i32, p.z as i32).to_array(), [n.x as i8, n.y as i8, n.z as i8], [uv.x as i32, uv.y as i32])
        };
        let mut groups: BTreeMap<([i32; 3], [i8; 3], [i32; 2]), u32> = BTreeMap::new();
        let mut of_vertex = Vec::with_capacity(self.vertex_count());
        let mut sums: Vec<(DVec3, DVec3, DVec2, f64)> = Vec::new();
        for i in 0..self.vertex_count() {
            let next = sums.len() as u32;
            let g = *groups.entry(key(i)).or_insert(next);
            if g == next {
                sums.push((DVec3::ZERO, DVec3::ZERO, DVec2::ZERO, 0.0));
            }
            let s = &mut sums[g as usize];
            s.0 += self.positions()[i].as_dvec3();
            s.1 += self.normals()[i].as_dvec3();
            s.2 += uvs.map_or(DVec2::ZERO, |u| u[i].as_dvec2());
            s.3 += 1.0;
            of_vertex.push(g);
        }
        if sums.len() == self.vertex_count() {
            return None;
        }
        let triangles: Vec<[u32; 3]> = self
            .triangles()
            .iter()
            .map(|t| t.map(|i| of_vertex[i as usize]))
            .filter(|[a, b, c]| a != b && b != c && a != c)
            .collect();
        if triangles.is_empty() {
            return None;
        }
        let positions = sums.iter().map(|s| (s.0 / s.3).as_vec3()).collect();
        let normals = sums.iter().map(|s| s.1.normalize_or(DVec3::Z).as_vec3()).collect::<Vec<Vec3>>();
        let uvs = uvs.map(|_| sums.iter().map(|s| (s.2 / s.3).as_vec2()).collect());
        Mesh::new(positions, normals, uvs, triangles).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dense_sphere_gets_coarser_and_keeps_its_size() {
        let s = Mesh::sphere(1.0, 64);
        let dense = Mesh::new(s.positions().to_vec(), s.normals().to_vec(), None, s.triangles().to_vec()).unwrap();
        let coarse = dense.clustered(0.2).unwrap();
        assert!(coarse.triangle_count() * 3 < dense.triangle_count(), "{} -> {}", dense.triangle_count(), coarse.triangle_count());
        let r = coarse.bounds().radius;
        assert!((r - 1.0).abs() < 0.1, "{r}");
        assert_eq!(dense.clustered(0.2).unwrap().positions(), coarse.positions());
    }

    #[test]
    fn a_cell_finer_than_the_mesh_changes_nothing() {
        let cube = Mesh::cuboid(Vec3::splat(1.0));
        assert!(cube.clustered(0.01).is_none());
        assert!(cube.clustered(0.0).is_none() && cube.clustered(f32::NAN).is_none());
        // Everything in one cell: each face collapses to a point, no triangle survives.
        assert!(cube.clustered(100.0).is_none());
    }
}
