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
    /// Its vertices: `first_vertex..first_vertex + vertex_count` of [`Clusters::vertices`].
    pub first_vertex: u32,
    pub vertex_count: u32,
    /// Encloses its vertices (mesh frame).
    pub centre: Vec3,
    pub radius: f32,
    /// Every triangle faces away from an eye at `e` when
    /// `dot(normalize(apex − e), axis) ≥ cutoff` (meshoptimizer's cone test).
    pub cone_apex: Vec3,
    pub cone_axis: Vec3,
    pub cone_cutoff: f32,
}

/// The patches of a mesh, in triangle order, and the vertices each uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Clusters {
    pub list: Vec<Cluster>,
    pub vertices: Vec<u32>,
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
                first_vertex: clusters.vertices.len() as u32,
                vertex_count: m.vertex_count,
                centre: sphere.center,
                radius: sphere.radius,
                cone_apex: Vec3::from_array(cone.cone_apex),
                cone_axis: Vec3::from_array(cone.cone_axis),
                cone_cutoff: cone.cone_cutoff,
            });
            clusters.vertices.extend_from_slice(local);
        }
        // Every triangle must be in exactly one cluster; anything else leaves the mesh as it was.
        if triangles.len() != self.triangle_count() {
            return self;
        }
        // Vertices in the order the clusters first use them (meshoptimizer's vertex fetch
        // order): a cluster's vertices then lie close together in memory.
        let mut new_index = vec![u32::MAX; self.vertex_count()];
        let mut order = Vec::with_capacity(self.vertex_count());
        for v in clusters.vertices.iter().copied().chain(0..self.vertex_count() as u32) {
            if new_index[v as usize] == u32::MAX {
                new_index[v as usize] = order.len() as u32;
                order.push(v);
            }
        }
        let renumber = |v: &mut u32| *v = new_index[*v as usize];
        triangles.iter_mut().flatten().for_each(renumber);
        clusters.vertices.iter_mut().for_each(renumber);
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
            let used = &clusters.vertices[k.first_vertex as usize..(k.first_vertex + k.vertex_count) as usize];
            for t in &c.triangles()[k.first as usize..(k.first + k.count) as usize] {
                for v in t {
                    assert!(used.contains(v));
                    assert!((c.positions()[*v as usize] - k.centre).length() <= k.radius * (1.0 + 1e-6));
                }
            }
        }
        assert_eq!(next as usize, c.triangle_count());
    }

    #[test]
    fn vertices_are_numbered_in_order_of_first_use_by_the_clusters() {
        let c = Mesh::sphere(1.0, 32).clustered();
        let mut next = 0;
        for &v in &c.clusters().vertices {
            assert!(v <= next);
            next = next.max(v + 1);
        }
        assert!(next > 0 && next as usize <= c.vertex_count());
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
