//! Triangle clusters: a dense mesh's triangles regrouped into small compact patches, each with a
//! bounding sphere and a cone around its faces' normals. The renderer skips a whole patch that
//! lies outside the view or faces away from the camera without transforming its vertices or
//! looking at its triangles (LIBERO's meshes put tens of thousands of triangles in view, about
//! half of them facing away).
//!
//! meshoptimizer builds the patches (its meshlets, grown for coherent normals) and their cones.
//! Regrouping only reorders the triangles, each keeping its vertices and winding, so a mesh draws
//! the same surfaces; only where two of its triangles overlap at equal depth can the order
//! change which one shows. The vertices are renumbered in the order the patches first use them,
//! so that a patch's vertex data lies together in memory; that changes no value.

use std::borrow::Cow;

use glam::Vec3;
use meshoptimizer_rs::{build_meshlets, compute_cluster_bounds, MeshletSettings, Positions, Workspace};

use crate::mesh::{bounding_sphere, Mesh};

/// Limits per patch: meshoptimizer's defaults, sized so a patch covers a few pixels to a few
/// dozen at 256².
const SETTINGS: MeshletSettings = MeshletSettings { max_vertices: 64, max_triangles: 124 };
/// How much meshoptimizer favours coherent normals over compactness when growing a patch.
const CONE_WEIGHT: f32 = 0.5;

/// One patch of a clustered mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cluster {
    /// Its triangles: `first..first + count` of the mesh's triangles.
    pub first: u32,
    pub count: u32,
    /// The positions its vertices use: `first_point..first_point + point_count` of
    /// [`Clusters::points`].
    pub first_point: u32,
    pub point_count: u32,
    /// Encloses its vertices (mesh frame).
    pub centre: Vec3,
    pub radius: f32,
    /// Every triangle faces away from an eye at `e` when
    /// `dot(normalize(apex − e), axis) ≥ cutoff` (meshoptimizer's cone test).
    pub cone_apex: Vec3,
    pub cone_axis: Vec3,
    pub cone_cutoff: f32,
}

/// The patches of a mesh, in triangle order, and the positions ([`crate::mesh::Points`]) each
/// uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Clusters {
    pub list: Vec<Cluster>,
    pub points: Vec<u32>,
    /// The index each vertex had before clustering renumbered the vertices.
    pub loaded_order: Vec<u32>,
}

impl Mesh {
    /// The same mesh with its triangles regrouped into clusters the renderer can cull as a
    /// whole. Meshes too small to gain, or that meshoptimizer cannot split, come back unchanged.
    pub fn clustered(self) -> Mesh {
        if self.triangle_count() <= SETTINGS.max_triangles {
            return self;
        }
        let positions: Vec<[f32; 3]> = self.positions().iter().map(|p| p.to_array()).collect();
        let indices: Vec<u32> = self.triangles().iter().flatten().copied().collect();
        let mut workspace = Workspace::default();
        let Ok(meshlets) = build_meshlets(&indices, Positions::from_packed(&positions), SETTINGS, CONE_WEIGHT, &mut workspace) else {
            return self;
        };
        let mut triangles = Vec::with_capacity(self.triangle_count());
        let mut clusters = Clusters::default();
        // Each cluster's vertices, in `first_point..` ranges until [`Clusters::vertices_to_points`].
        let mut vertices = Vec::new();
        for m in &meshlets.meshlets {
            let local = &meshlets.vertices[m.vertex_offset as usize..(m.vertex_offset + m.vertex_count) as usize];
            let bytes = &meshlets.triangles[m.triangle_offset as usize..(m.triangle_offset + 3 * m.triangle_count) as usize];
            let first = triangles.len() as u32;
            triangles.extend(bytes.chunks_exact(3).map(|t| [local[t[0] as usize], local[t[1] as usize], local[t[2] as usize]]));
            // Bounds from the cluster's own vertices (meshoptimizer scans every position given).
            let points: Vec<Vec3> = local.iter().map(|&v| self.positions()[v as usize]).collect();
            let packed: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
            let own: Vec<u32> = bytes.iter().map(|&b| b as u32).collect();
            let Ok(cone) = compute_cluster_bounds(&own, Positions::from_packed(&packed), &mut workspace) else {
                return self;
            };
            let (sphere, _) = bounding_sphere(&points);
            clusters.list.push(Cluster {
                first,
                count: m.triangle_count,
                first_point: vertices.len() as u32,
                point_count: m.vertex_count,
                centre: sphere.center,
                radius: sphere.radius,
                cone_apex: Vec3::from_array(cone.cone_apex),
                cone_axis: Vec3::from_array(cone.cone_axis),
                cone_cutoff: cone.cone_cutoff,
            });
            vertices.extend_from_slice(local);
        }
        // Every triangle must be in exactly one cluster; anything else leaves the mesh as it was.
        if triangles.len() != self.triangle_count() {
            return self;
        }
        // Vertices in the order the clusters first use them (meshoptimizer's vertex fetch
        // order): a cluster's vertices then lie close together in memory.
        let mut new_index = vec![u32::MAX; self.vertex_count()];
        let mut order = Vec::with_capacity(self.vertex_count());
        for v in vertices.iter().copied().chain(0..self.vertex_count() as u32) {
            if new_index[v as usize] == u32::MAX {
                new_index[v as usize] = order.len() as u32;
                order.push(v);
            }
        }
        let renumber = |v: &mut u32| *v = new_index[*v as usize];
        triangles.iter_mut().flatten().for_each(renumber);
        vertices.iter_mut().for_each(renumber);
        clusters.points = vertices;
        clusters.loaded_order = order;
        self.with_clusters(triangles, clusters)
    }

    /// The same triangles with the vertices numbered as before [`Mesh::clustered`] renumbered
    /// them: the simplifier's choices depend on the numbering, and coarser copies must come out
    /// as they did from the loaded order.
    pub(crate) fn in_loaded_order(&self) -> Cow<'_, Mesh> {
        let order = &self.clusters().loaded_order;
        if order.is_empty() {
            return Cow::Borrowed(self);
        }
        let mut back = vec![0; order.len()];
        for (new, &old) in order.iter().enumerate() {
            back[old as usize] = new;
        }
        let pick = |v: &[Vec3]| back.iter().map(|&i| v[i]).collect();
        let uvs = self.uvs().map(|u| back.iter().map(|&i| u[i]).collect());
        let triangles = self.triangles().iter().map(|t| t.map(|v| order[v as usize])).collect();
        Cow::Owned(Mesh::new(pick(self.positions()), pick(self.normals()), uvs, triangles).expect("renumbering keeps a valid mesh valid"))
    }
}

impl Clusters {
    /// Turns each cluster's list of vertices (held in [`Clusters::points`] while the clusters
    /// are built) into the list of the distinct positions they use.
    pub(crate) fn vertices_to_points(&mut self, of_vertex: &[u32]) {
        let vertices = std::mem::take(&mut self.points);
        let mut seen = vec![u32::MAX; of_vertex.len()];
        for (k, c) in self.list.iter_mut().enumerate() {
            let first = self.points.len() as u32;
            for &v in &vertices[c.first_point as usize..(c.first_point + c.point_count) as usize] {
                let p = of_vertex[v as usize];
                if seen[p as usize] != k as u32 {
                    seen[p as usize] = k as u32;
                    self.points.push(p);
                }
            }
            (c.first_point, c.point_count) = (first, self.points.len() as u32 - first);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn clustering_keeps_every_triangle_and_bounds_every_vertex() {
        let sphere = Mesh::sphere(1.0, 32);
        let c = sphere.clone().clustered();
        let clusters = c.clusters();
        assert!(clusters.list.len() > 4);
        let mut original: Vec<[u32; 3]> = sphere.triangles().to_vec();
        let loaded = c.in_loaded_order();
        assert_eq!((loaded.positions(), loaded.normals(), loaded.uvs()), (sphere.positions(), sphere.normals(), sphere.uvs()));
        let mut regrouped: Vec<[u32; 3]> = loaded.triangles().to_vec();
        // Same triangles with the same winding (meshoptimizer may rotate a triangle's corners).
        let canonical = |t: &mut [u32; 3]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            t.rotate_left(k);
        };
        original.iter_mut().for_each(canonical);
        regrouped.iter_mut().for_each(canonical);
        original.sort_unstable();
        regrouped.sort_unstable();
        assert_eq!(original, regrouped);
        let mut next = 0;
        for k in &clusters.list {
            assert_eq!(k.first, next);
            next += k.count;
            let used = &clusters.points[k.first_point as usize..(k.first_point + k.point_count) as usize];
            let mut distinct = used.to_vec();
            distinct.sort_unstable();
            distinct.dedup();
            assert_eq!(distinct.len(), used.len(), "a cluster lists a position twice");
            for t in &c.triangles()[k.first as usize..(k.first + k.count) as usize] {
                for v in t {
                    assert!(used.contains(&c.points().of_vertex[*v as usize]));
                    assert!((c.positions()[*v as usize] - k.centre).length() <= k.radius * (1.0 + 1e-6));
                }
            }
        }
        assert_eq!(next as usize, c.triangle_count());
    }

    #[test]
    fn positions_are_numbered_in_order_of_first_use_by_the_clusters() {
        let c = Mesh::sphere(1.0, 32).clustered();
        let mut next = 0;
        for &p in &c.clusters().points {
            assert!(p <= next);
            next = next.max(p + 1);
        }
        // The sphere's seam and poles repeat positions with other UVs.
        let points = c.points();
        assert!(next as usize == points.list.len() && points.list.len() < c.vertex_count());
        for (v, &p) in points.of_vertex.iter().enumerate() {
            assert_eq!(points.list[p as usize], c.positions()[v]);
        }
        for (t, corners) in c.triangles().iter().zip(&points.triangles) {
            assert_eq!(t.map(|v| points.of_vertex[v as usize]), *corners);
        }
    }

    #[test]
    fn zero_uvs_keep_the_triangles_and_clusters() {
        let c = Mesh::sphere(1.0, 32).clustered();
        let flat = c.with_zero_uvs();
        assert_eq!(flat.triangles(), c.triangles());
        assert_eq!(flat.clusters(), c.clusters());
        assert_eq!(flat.uvs(), Some(&vec![Vec2::ZERO; c.vertex_count()][..]));
    }

    #[test]
    fn a_cone_culls_only_clusters_that_face_away() {
        let c = Mesh::sphere(1.0, 32).clustered();
        let eye = Vec3::new(0.0, 0.0, 5.0);
        let mut culled = 0;
        for k in &c.clusters().list {
            if (k.cone_apex - eye).normalize().dot(k.cone_axis) >= k.cone_cutoff {
                culled += 1;
                for t in &c.triangles()[k.first as usize..(k.first + k.count) as usize] {
                    let [a, b, d] = t.map(|v| c.positions()[v as usize]);
                    assert!((b - a).cross(d - a).dot(a - eye) >= 0.0, "a culled triangle faces the eye");
                }
            }
        }
        assert!(culled > 0);
    }

    #[test]
    fn small_meshes_stay_unclustered() {
        let cube = Mesh::cuboid(Vec3::ONE);
        assert!(cube.clone().clustered().clusters().list.is_empty());
        assert_eq!(cube.clone().clustered(), cube);
    }
}
