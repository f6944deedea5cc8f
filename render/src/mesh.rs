//! Triangle meshes: validated vertex data plus a bounding sphere for culling.

use glam::{Vec2, Vec3};
use thiserror::Error;

use crate::cluster::Clusters;
use crate::transform::{cross, dot, mul_mat3, normalize, Transform};

/// Why mesh data was rejected.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    /// Normals or UVs do not have one entry per position.
    #[error("mesh has {positions} positions but {count} {what}")]
    LengthMismatch { what: &'static str, positions: usize, count: usize },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but the mesh has {vertices} vertices")]
    IndexOutOfRange { triangle: usize, index: u32, vertices: usize },
    /// A position, normal or UV is NaN or infinite.
    #[error("{what} {index} is not finite")]
    NonFinite { what: &'static str, index: usize },
}

/// A sphere enclosing all vertices of a mesh, in the mesh's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    pub center: Vec3,
    pub radius: f32,
}

/// An indexed triangle mesh with per-vertex normals and optional texture coordinates.
///
/// Triangles are counter-clockwise seen from the front (OpenGL/MuJoCo convention). Immutable once
/// built, so scenes share meshes through `Arc<Mesh>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Option<Vec<Vec2>>,
    triangles: Vec<[u32; 3]>,
    bounds: BoundingSphere,
    /// Half size of the bounding box centred on `bounds.center`.
    half_extent: Vec3,
    /// Groups of triangles culled as a whole; empty unless [`Mesh::clustered`] made them.
    clusters: Clusters,
    points: Points,
}

/// A mesh's distinct positions (equal in every bit), numbered in the order its vertices first
/// use them, and each vertex's. Vertices that share a position but not a normal or UV (a hard
/// edge, a texture seam: robosuite's faceted Panda parts have about five per position) are then
/// transformed to the screen once.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Points {
    pub list: Vec<Vec3>,
    pub of_vertex: Vec<u32>,
    /// Each triangle's corners as positions.
    pub triangles: Vec<[u32; 3]>,
}

impl Points {
    fn of(positions: &[Vec3], triangles: &[[u32; 3]]) -> Points {
        let mut first: std::collections::HashMap<[u32; 3], u32> = std::collections::HashMap::with_capacity(positions.len());
        let mut list = Vec::new();
        let of_vertex = positions
            .iter()
            .map(|p| {
                *first.entry(p.to_array().map(f32::to_bits)).or_insert_with(|| {
                    list.push(*p);
                    list.len() as u32 - 1
                })
            })
            .collect::<Vec<u32>>();
        let triangles = triangles.iter().map(|t| t.map(|v| of_vertex[v as usize])).collect();
        Points { list, of_vertex, triangles }
    }
}

impl Mesh {
    /// Builds a mesh after checking lengths, indices and finiteness.
    ///
    /// UV `v = 0` is the first (top) row of a texture image, as MuJoCo uses texture rows.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        Mesh::check(&positions, &normals, uvs.as_deref(), &triangles)?;
        let (bounds, half_extent) = bounding_sphere(&positions);
        let points = Points::of(&positions, &triangles);
        Ok(Mesh { positions, normals, uvs, triangles, bounds, half_extent, clusters: Clusters::default(), points })
    }

    /// What [`Mesh::new`] checks: one normal and UV per position, finite values, indices in range.
    pub(crate) fn check(positions: &[Vec3], normals: &[Vec3], uvs: Option<&[Vec2]>, triangles: &[[u32; 3]]) -> Result<(), MeshError> {
        let n = positions.len();
        if normals.len() != n {
            return Err(MeshError::LengthMismatch { what: "normals", positions: n, count: normals.len() });
        }
        if let Some(uv) = uvs {
            if uv.len() != n {
                return Err(MeshError::LengthMismatch { what: "UVs", positions: n, count: uv.len() });
            }
            if let Some(i) = uv.iter().position(|t| !t.is_finite()) {
                return Err(MeshError::NonFinite { what: "UV", index: i });
            }
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { what: "position", index: i });
        }
        if let Some(i) = normals.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { what: "normal", index: i });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshError::IndexOutOfRange { triangle: t, index, vertices: n });
            }
        }
        Ok(())
    }

    /// A mesh from fields already checked together (see [`crate::pack`]). The bounds do not
    /// depend on the vertices' order, so they are the same bits as the packed mesh's.
    pub(crate) fn from_parts(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
        clusters: Clusters,
        points: Points,
    ) -> Mesh {
        let (bounds, half_extent) = bounding_sphere(&positions);
        Mesh { positions, normals, uvs, triangles, bounds, half_extent, clusters, points }
    }

    /// Builds a mesh whose normals are the area-weighted average of the adjacent face normals
    /// (smooth shading across shared vertices).
    pub fn with_smooth_normals(
        positions: Vec<Vec3>,
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        let mut normals = vec![Vec3::ZERO; positions.len()];
        for tri in &triangles {
            let [a, b, c] = tri.map(|i| positions.get(i as usize).copied());
            if let (Some(a), Some(b), Some(c)) = (a, b, c) {
                // The cross product's length is twice the area: area weighting for free.
                let fnorm = cross(b - a, c - a);
                for &i in tri {
                    normals[i as usize] += fnorm;
                }
            }
        }
        for n in &mut normals {
            *n = normalize(*n);
        }
        Mesh::new(positions, normals, uvs, triangles)
    }

    /// Builds a mesh shaded the way MuJoCo draws loaded meshes: vertex normals from the file
    /// (or area-weighted smooth normals when it has none), except that for meshes without UVs a
    /// corner whose vertex normal is more than ~37° (cosine 0.8) off its face normal uses the
    /// face normal instead, which keeps hard edges hard. Equal vertices are shared
    /// ([`Mesh::welded`]).
    pub fn with_mujoco_normals(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, MeshError> {
        let smooth = match normals {
            Some(n) => Mesh::new(positions, n, uvs, triangles)?,
            None => Mesh::with_smooth_normals(positions, uvs, triangles)?,
        };
        if smooth.uvs.is_some() {
            return Ok(smooth.welded());
        }
        let mut positions = Vec::with_capacity(smooth.triangles.len() * 3);
        let mut normals = Vec::with_capacity(smooth.triangles.len() * 3);
        for tri in &smooth.triangles {
            let [a, b, c] = tri.map(|i| smooth.positions[i as usize]);
            let face = normalize(cross(b - a, c - a));
            for &i in tri {
                let n = normalize(smooth.normals[i as usize]);
                positions.push(smooth.positions[i as usize]);
                normals.push(if dot(n, face) < 0.8 { face } else { n });
            }
        }
        let triangles = (0..smooth.triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        Ok(Mesh::new(positions, normals, None, triangles)?.welded())
    }

    /// The same mesh with vertices that are equal in every bit (position, normal, UV) shared:
    /// it draws the same pixels, with fewer vertices to transform and light. Mesh files often
    /// store three vertices per triangle; the simplifier needs them shared to collapse edges.
    pub fn welded(self) -> Mesh {
        let key = |i: usize| {
            let uv = self.uvs.as_ref().map_or([0; 2], |u| u[i].to_array().map(f32::to_bits));
            (self.positions[i].to_array().map(f32::to_bits), self.normals[i].to_array().map(f32::to_bits), uv)
        };
        let mut first: std::collections::HashMap<_, u32> = std::collections::HashMap::with_capacity(self.positions.len());
        let mut kept = Vec::new();
        let remap: Vec<u32> = (0..self.positions.len())
            .map(|i| {
                *first.entry(key(i)).or_insert_with(|| {
                    kept.push(i);
                    kept.len() as u32 - 1
                })
            })
            .collect();
        if kept.len() == self.positions.len() {
            return self;
        }
        let pick = |v: &[Vec3]| kept.iter().map(|&i| v[i]).collect();
        let uvs = self.uvs.as_ref().map(|u| kept.iter().map(|&i| u[i]).collect());
        let triangles = self.triangles.iter().map(|t| t.map(|i| remap[i as usize])).collect();
        Mesh::new(pick(&self.positions), pick(&self.normals), uvs, triangles).expect("sharing equal vertices keeps a valid mesh valid")
    }

    /// This mesh with its vertices in `clusters.loaded_order` (the old index of each), and
    /// `triangles` (the same ones, regrouped and renumbered) in `clusters`, whose point lists
    /// still hold each cluster's (renumbered) vertices.
    pub(crate) fn with_clusters(self, triangles: Vec<[u32; 3]>, mut clusters: Clusters) -> Mesh {
        let order = &clusters.loaded_order;
        let pick = |v: &[Vec3]| order.iter().map(|&i| v[i as usize]).collect();
        let uvs = self.uvs.as_ref().map(|u| order.iter().map(|&i| u[i as usize]).collect());
        let (positions, normals): (Vec<Vec3>, _) = (pick(&self.positions), pick(&self.normals));
        let points = Points::of(&positions, &triangles);
        clusters.vertices_to_points(&points.of_vertex);
        Mesh { positions, normals, uvs, triangles, clusters, points, ..self }
    }

    /// The distinct positions and each vertex's.
    pub(crate) fn points(&self) -> &Points {
        &self.points
    }

    /// The triangle clusters (empty for meshes drawn triangle by triangle).
    pub(crate) fn clusters(&self) -> &Clusters {
        &self.clusters
    }

    /// Vertex positions in the local frame.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Per-vertex normals (not necessarily unit length; the renderer normalises).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// The same mesh (triangles and clusters in their order) with texture coordinate zero at
    /// every vertex, as MuJoCo samples a texture on a mesh that has no coordinates of its own.
    pub fn with_zero_uvs(&self) -> Mesh {
        Mesh { uvs: Some(vec![Vec2::ZERO; self.positions.len()]), ..self.clone() }
    }

    /// Per-vertex texture coordinates, if any.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// The same mesh without texture coordinates.
    pub fn without_uvs(&self) -> Mesh {
        Mesh { uvs: None, ..self.clone() }
    }

    /// Triangles as vertex index triples, counter-clockwise from the front.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Enclosing sphere in the local frame.
    pub fn bounds(&self) -> BoundingSphere {
        self.bounds
    }

    /// Half size of the local bounding box, which is centred on `bounds().center`.
    pub fn half_extent(&self) -> Vec3 {
        self.half_extent
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// A copy with every vertex moved by `t` (normals by its inverse transpose).
    pub fn transformed(&self, t: &Transform) -> Mesh {
        Mesh::merge(&[(self.clone(), *t)])
    }

    /// A copy with triangle winding and normals reversed (the inside becomes the front).
    pub fn flipped(&self) -> Mesh {
        let triangles = self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let normals = self.normals.iter().map(|&n| -n).collect();
        Mesh::new(self.positions.clone(), normals, self.uvs.clone(), triangles)
            .expect("flipping keeps a valid mesh valid")
    }

    /// Concatenates meshes, each placed by its transform, into one.
    ///
    /// The result has UVs if any part has them; parts without UVs get `(0, 0)`.
    pub fn merge(parts: &[(Mesh, Transform)]) -> Mesh {
        let any_uv = parts.iter().any(|(m, _)| m.uvs.is_some());
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut triangles = Vec::new();
        for (mesh, t) in parts {
            let base = positions.len() as u32;
            let nm = t.normal_matrix();
            positions.extend(mesh.positions.iter().map(|&p| t.transform_point(p)));
            normals.extend(mesh.normals.iter().map(|&n| normalize(mul_mat3(&nm, n))));
            if any_uv {
                match &mesh.uvs {
                    Some(u) => uvs.extend_from_slice(u),
                    None => uvs.extend(std::iter::repeat_n(Vec2::ZERO, mesh.positions.len())),
                }
            }
            triangles.extend(mesh.triangles.iter().map(|tri| tri.map(|i| i + base)));
        }
        Mesh::new(positions, normals, any_uv.then_some(uvs), triangles)
            .expect("merging valid meshes with finite transforms gives a valid mesh")
    }
}

/// Centre of the bounding box, radius to the farthest vertex: deterministic and tight enough;
/// and the box's half size.
pub(crate) fn bounding_sphere(points: &[Vec3]) -> (BoundingSphere, Vec3) {
    if points.is_empty() {
        return (BoundingSphere { center: Vec3::ZERO, radius: 0.0 }, Vec3::ZERO);
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for &p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let center = (lo + hi) * 0.5;
    let r2 = points.iter().map(|&p| dot(p - center, p - center)).fold(0.0f32, f32::max);
    (BoundingSphere { center, radius: r2.sqrt() }, (hi - lo) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> Mesh {
        Mesh::with_smooth_normals(vec![Vec3::ZERO, Vec3::X, Vec3::Y], None, vec![[0, 1, 2]]).unwrap()
    }

    #[test]
    fn rejects_bad_indices_and_lengths() {
        let e = Mesh::new(vec![Vec3::ZERO], vec![Vec3::Z], None, vec![[0, 0, 3]]).unwrap_err();
        assert_eq!(e, MeshError::IndexOutOfRange { triangle: 0, index: 3, vertices: 1 });
        let e = Mesh::new(vec![Vec3::ZERO], vec![], None, vec![]).unwrap_err();
        assert!(matches!(e, MeshError::LengthMismatch { what: "normals", .. }));
        let e = Mesh::new(vec![Vec3::new(f32::NAN, 0.0, 0.0)], vec![Vec3::Z], None, vec![]).unwrap_err();
        assert_eq!(e, MeshError::NonFinite { what: "position", index: 0 });
    }

    #[test]
    fn smooth_normals_follow_winding() {
        let m = triangle();
        assert!(m.normals().iter().all(|&n| (n - Vec3::Z).length() < 1e-6));
        let f = m.flipped();
        assert!(f.normals().iter().all(|&n| (n + Vec3::Z).length() < 1e-6));
        assert_eq!(f.triangles()[0], [0, 2, 1]);
    }

    #[test]
    fn bounds_enclose_all_vertices() {
        let m = triangle();
        let b = m.bounds();
        for &p in m.positions() {
            assert!((p - b.center).length() <= b.radius + 1e-6);
        }
    }

    #[test]
    fn vertices_at_one_position_share_a_point() {
        // Three normals per corner of a box; -0.0 and 0.0 differ in their bits, so they stay apart.
        let cube = Mesh::cuboid(Vec3::ONE);
        let points = cube.points();
        assert_eq!((cube.vertex_count(), points.list.len()), (24, 8));
        for (v, &p) in points.of_vertex.iter().enumerate() {
            assert_eq!(points.list[p as usize], cube.positions()[v]);
        }
        let corners: Vec<[u32; 3]> = cube.triangles().iter().map(|t| t.map(|v| points.of_vertex[v as usize])).collect();
        assert_eq!(points.triangles, corners);
        let signed = Mesh::new(vec![Vec3::ZERO, Vec3::new(-0.0, 0.0, 0.0), Vec3::X, Vec3::ZERO], vec![Vec3::Z; 4], None, vec![[0, 2, 1], [3, 2, 1]]).unwrap();
        assert_eq!(signed.points().of_vertex, [0, 1, 2, 0]);
    }

    #[test]
    fn mujoco_normals_keep_hard_edges() {
        // Two triangles folded 90° along the x axis, sharing their edge vertices.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let m = Mesh::with_mujoco_normals(p, None, None, vec![[0, 1, 2], [0, 3, 1]]).unwrap();
        assert_eq!(m.vertex_count(), 6);
        // Smooth normals at the shared edge are 45° off each face: the face normals win.
        assert!(m.normals()[..3].iter().all(|&n| (n - Vec3::Z).length() < 1e-6));
        assert!(m.normals()[3..].iter().all(|&n| (n - Vec3::Y).length() < 1e-6));
    }

    #[test]
    fn mujoco_normals_share_the_vertices_of_a_smooth_surface() {
        // A flat quad: the corners on the diagonal are equal in both triangles.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let m = Mesh::with_mujoco_normals(p, None, None, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        assert_eq!((m.vertex_count(), m.triangles()), (4, &[[0, 1, 2], [0, 2, 3]][..]));
    }

    #[test]
    fn merge_offsets_indices_and_transforms() {
        let t = Transform::from_translation(Vec3::new(0.0, 0.0, 2.0));
        let m = Mesh::merge(&[(triangle(), Transform::IDENTITY), (triangle(), t)]);
        assert_eq!(m.vertex_count(), 6);
        assert_eq!(m.triangles()[1], [3, 4, 5]);
        assert_eq!(m.positions()[3], Vec3::new(0.0, 0.0, 2.0));
        assert!(m.uvs().is_none());
    }
}
