//! Procedural meshes, so that every LIBERO object can be drawn without asset files.
//!
//! Builders never fail: non-finite or negative sizes are treated as zero or their absolute
//! value, and segment counts are clamped to a sensible minimum. Texture coordinates put `v = 0`
//! at the top of the texture image.
//!
//! Lighting is computed per vertex (as in MuJoCo's fixed-function renderer), so large flat faces
//! lit by spot lights need tessellation: use [`Mesh::cuboid_tessellated`] / [`Mesh::grid`] for
//! tables, floors and walls (MuJoCo itself draws every box face as 4×4 quads and planes as grids).

use glam::{Vec2, Vec3};

use crate::mesh::Mesh;

/// Adjacent profile segments whose normals differ by more than this (cosine) get a hard edge.
/// MuJoCo uses the same 0.8 threshold when it draws meshes.
const CREASE_COS: f32 = 0.8;

/// `|x|` for finite `x`, else 0.
fn size(x: f32) -> f32 {
    if x.is_finite() { x.abs() } else { 0.0 }
}

/// Accumulates vertices and triangles, then validates into a [`Mesh`].
#[derive(Default)]
struct Builder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    triangles: Vec<[u32; 3]>,
}

impl Builder {
    fn vertex(&mut self, p: Vec3, n: Vec3, uv: Vec2) -> u32 {
        self.positions.push(p);
        self.normals.push(n);
        self.uvs.push(uv);
        (self.positions.len() - 1) as u32
    }

    fn finish(self) -> Mesh {
        Mesh::new(self.positions, self.normals, Some(self.uvs), self.triangles)
            .expect("procedural builders only produce finite, in-range data")
    }
}

impl Mesh {
    /// A box centred at the origin with the given half-extents (MuJoCo `type="box"` `size`),
    /// one quad per face (12 triangles). Each face maps the whole texture, upright on the sides.
    pub fn cuboid(half_extents: Vec3) -> Mesh {
        Mesh::cuboid_tessellated(half_extents, 1)
    }

    /// Like [`Mesh::cuboid`] but each face is split into `n × n` quads, for smooth per-vertex
    /// lighting on large faces. MuJoCo draws boxes with `n = 4`.
    pub fn cuboid_tessellated(half_extents: Vec3, n: u32) -> Mesh {
        let n = n.clamp(1, 256);
        Mesh::cuboid_split(half_extents, |_| n)
    }

    /// Like [`Mesh::cuboid`] but each face is split into quads at most `edge` on a side (at most
    /// 256 along an edge), so long thin faces are not split across their width.
    pub fn cuboid_with_quads_at_most(half_extents: Vec3, edge: f32) -> Mesh {
        Mesh::cuboid_split(half_extents, |half| ((2.0 * half / edge).ceil() as u32).clamp(1, 256))
    }

    /// A box whose faces are grids of `quads(half-length)` quads along each of their edges.
    fn cuboid_split(half_extents: Vec3, quads: impl Fn(f32) -> u32) -> Mesh {
        let h = Vec3::new(size(half_extents.x), size(half_extents.y), size(half_extents.z));
        // (normal, s, t) with s × t = normal, so quads in (s, t) order are counter-clockwise
        // from outside; side faces have t = +z so textures stand upright.
        let faces = [
            (Vec3::X, Vec3::Y, Vec3::Z),
            (Vec3::NEG_X, Vec3::NEG_Y, Vec3::Z),
            (Vec3::Y, Vec3::NEG_X, Vec3::Z),
            (Vec3::NEG_Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (Vec3::NEG_Z, Vec3::X, Vec3::NEG_Y),
        ];
        let along = |axis: Vec3| (axis.abs() * h).element_sum();
        let mut b = Builder::default();
        for (normal, s, t) in faces {
            let (ns, nt) = (quads(along(s)), quads(along(t)));
            let base = b.positions.len() as u32;
            for j in 0..=nt {
                for i in 0..=ns {
                    let a = 2.0 * i as f32 / ns as f32 - 1.0;
                    let c = 2.0 * j as f32 / nt as f32 - 1.0;
                    let p = (normal + s * a + t * c) * h;
                    b.vertex(p, normal, Vec2::new(0.5 * (a + 1.0), 0.5 * (1.0 - c)));
                }
            }
            grid_triangles(&mut b.triangles, base, ns, nt);
        }
        b.finish()
    }

    /// A rectangle in the local xy-plane facing +z (MuJoCo `type="plane"` `size[0..2]`), as one
    /// quad. UVs run over `[0, 1]` once across the plane; set the material's `uv_scale` to tile
    /// a texture (MuJoCo's `texrepeat`).
    pub fn plane(half_x: f32, half_y: f32) -> Mesh {
        Mesh::grid(half_x, half_y, 1, 1)
    }

    /// Like [`Mesh::plane`] but split into `nx × ny` quads, for per-vertex lighting on floors
    /// and walls (MuJoCo draws its floor as a grid too).
    pub fn grid(half_x: f32, half_y: f32, nx: u32, ny: u32) -> Mesh {
        let (hx, hy) = (size(half_x), size(half_y));
        let (nx, ny) = (nx.clamp(1, 1024), ny.clamp(1, 1024));
        let mut b = Builder::default();
        for j in 0..=ny {
            for i in 0..=nx {
                let (u, v) = (i as f32 / nx as f32, j as f32 / ny as f32);
                let p = Vec3::new(hx * (2.0 * u - 1.0), hy * (2.0 * v - 1.0), 0.0);
                b.vertex(p, Vec3::Z, Vec2::new(u, 1.0 - v));
            }
        }
        grid_triangles(&mut b.triangles, 0, nx, ny);
        b.finish()
    }

    /// A closed cylinder about z from `-half_height` to `+half_height` (MuJoCo `type="cylinder"`
    /// `size="radius half_height"`), smooth sides and flat caps.
    pub fn cylinder(radius: f32, half_height: f32, segments: u32) -> Mesh {
        let (r, h) = (size(radius), size(half_height));
        Mesh::lathe_capped(&[(r, -h), (r, h)], segments)
    }

    /// A sphere about the origin with `segments` divisions around and `segments / 2` from pole
    /// to pole.
    pub fn sphere(radius: f32, segments: u32) -> Mesh {
        let stacks = (segments / 2).max(2);
        let profile = arc(size(radius), 0.0, -std::f32::consts::FRAC_PI_2, std::f32::consts::FRAC_PI_2, stacks);
        Mesh::lathe(&profile, segments)
    }

    /// A capsule about z: a cylinder of half-length `half_height` with hemispherical ends
    /// (MuJoCo `type="capsule"` `size="radius half_height"`).
    pub fn capsule(radius: f32, half_height: f32, segments: u32) -> Mesh {
        let (r, h) = (size(radius), size(half_height));
        let stacks = (segments / 4).max(1);
        let half_pi = std::f32::consts::FRAC_PI_2;
        let mut profile = arc(r, -h, -half_pi, 0.0, stacks);
        profile.extend(arc(r, h, 0.0, half_pi, stacks));
        Mesh::lathe(&profile, segments)
    }

    /// A surface of revolution about z through the profile points `(radius, z)`.
    ///
    /// The front side is to the right of the direction of travel in the (radius, z) half-plane:
    /// a profile going up along the outside faces outwards, one coming back down the inside of a
    /// bowl faces inwards, so bowls, plates, mugs and bottles are one profile each. Normals are
    /// smooth except where adjacent segments meet at more than ~37° (hard edge). Points on the
    /// axis (radius 0) close the surface. Non-finite points and repeated points are dropped.
    pub fn lathe(profile: &[(f32, f32)], segments: u32) -> Mesh {
        let points = clean_profile(profile);
        let segments = segments.clamp(3, 4096);
        let mut b = Builder::default();
        if points.len() < 2 {
            return b.finish();
        }
        let rings = profile_rings(&points);
        let total = rings.last().map_or(1.0, |r| r.arc).max(f32::MIN_POSITIVE);
        let angles: Vec<(f32, f32)> = (0..=segments)
            .map(|k| {
                let a = 2.0 * std::f32::consts::PI * k as f32 / segments as f32;
                (libm::cosf(a), libm::sinf(a))
            })
            .collect();
        let ring = |b: &mut Builder, at: &ProfileRing, normal: Vec2| -> u32 {
            let base = b.positions.len() as u32;
            for (k, &(c, s)) in angles.iter().enumerate() {
                let p = Vec3::new(at.point.x * c, at.point.x * s, at.point.y);
                let n = Vec3::new(normal.x * c, normal.x * s, normal.y);
                let uv = Vec2::new(k as f32 / segments as f32, 1.0 - at.arc / total);
                b.vertex(p, n, uv);
            }
            base
        };
        // One ring of vertices per profile point, two where the profile has a hard edge; each
        // segment of the profile becomes a band of quads between consecutive rings.
        let mut lower: Option<u32> = None;
        for (i, at) in rings.iter().enumerate() {
            let before = (i > 0).then(|| ring(&mut b, at, at.normal_before));
            let after = match before {
                _ if i + 1 == rings.len() => None,
                Some(base) if at.normal_before == at.normal_after => Some(base),
                _ => Some(ring(&mut b, at, at.normal_after)),
            };
            if let (Some(a), Some(c)) = (lower, before) {
                let lo = &rings[i - 1];
                for k in 0..segments {
                    let (a0, a1, c0, c1) = (a + k, a + k + 1, c + k, c + k + 1);
                    if lo.point.x > 0.0 {
                        b.triangles.push([a0, a1, c1]);
                    }
                    if at.point.x > 0.0 {
                        b.triangles.push([a0, c1, c0]);
                    }
                }
            }
            lower = after;
        }
        b.finish()
    }

    /// [`Mesh::lathe`] closed by flat disks at the first and last profile points (facing −z
    /// and +z respectively), for solid objects like cans and pucks.
    pub fn lathe_capped(profile: &[(f32, f32)], segments: u32) -> Mesh {
        let points = clean_profile(profile);
        let (Some(first), Some(last)) = (points.first().copied(), points.last().copied()) else {
            return Mesh::lathe(&[], segments);
        };
        let mut closed = Vec::with_capacity(points.len() + 2);
        closed.push((0.0, first.y));
        closed.extend(points.iter().map(|p| (p.x, p.y)));
        closed.push((0.0, last.y));
        Mesh::lathe(&closed, segments)
    }
}

/// Two triangles per cell of a `(nx+1) × (ny+1)` vertex grid laid out row by row.
fn grid_triangles(out: &mut Vec<[u32; 3]>, base: u32, nx: u32, ny: u32) {
    let row = nx + 1;
    for j in 0..ny {
        for i in 0..nx {
            let v00 = base + j * row + i;
            let (v10, v01, v11) = (v00 + 1, v00 + row, v00 + row + 1);
            out.push([v00, v10, v11]);
            out.push([v00, v11, v01]);
        }
    }
}

/// Points `(r cos a, z0 + r sin a)` for `a` from `a0` to `a1` in `steps` steps.
fn arc(r: f32, z0: f32, a0: f32, a1: f32, steps: u32) -> Vec<(f32, f32)> {
    (0..=steps)
        .map(|i| {
            let a = a0 + (a1 - a0) * i as f32 / steps as f32;
            ((r * libm::cosf(a)).max(0.0), z0 + r * libm::sinf(a))
        })
        .collect()
}

/// Finite points with non-negative radius, without consecutive duplicates.
fn clean_profile(profile: &[(f32, f32)]) -> Vec<Vec2> {
    let mut out: Vec<Vec2> = Vec::with_capacity(profile.len());
    for &(r, z) in profile {
        if !(r.is_finite() && z.is_finite()) {
            continue;
        }
        let p = Vec2::new(r.abs(), z);
        if out.last() != Some(&p) {
            out.push(p);
        }
    }
    out
}

/// One profile point with the (radius, z) normals used by the bands before and after it.
struct ProfileRing {
    point: Vec2,
    normal_before: Vec2,
    normal_after: Vec2,
    /// Arc length from the first point, for the v texture coordinate.
    arc: f32,
}

fn profile_rings(points: &[Vec2]) -> Vec<ProfileRing> {
    // Segment normal: the travel direction turned clockwise, (dz, -dr).
    let seg_normals: Vec<Vec2> = points
        .windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            Vec2::new(d.y, -d.x) / d.length()
        })
        .collect();
    let mut arc = 0.0;
    points
        .iter()
        .enumerate()
        .map(|(i, &point)| {
            if i > 0 {
                arc += (point - points[i - 1]).length();
            }
            let before = if i > 0 { Some(seg_normals[i - 1]) } else { None };
            let after = seg_normals.get(i).copied();
            let (mut nb, mut na) = match (before, after) {
                (Some(b), Some(a)) if b.dot(a) >= CREASE_COS => {
                    let m = (a + b).normalize_or_zero();
                    (m, m)
                }
                (Some(b), Some(a)) => (b, a),
                (Some(b), None) => (b, b),
                (None, Some(a)) => (a, a),
                (None, None) => (Vec2::Y, Vec2::Y),
            };
            // On the axis a smooth surface's normal is along the axis.
            if point.x == 0.0 {
                nb = Vec2::new(0.0, if nb.y < 0.0 { -1.0 } else { 1.0 });
                na = Vec2::new(0.0, if na.y < 0.0 { -1.0 } else { 1.0 });
            }
            ProfileRing { point, normal_before: nb, normal_after: na, arc }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transform::{cross, dot};

    /// Every triangle's geometric normal agrees with its vertex normals (consistent winding),
    /// and no triangle is degenerate.
    fn assert_outward_consistent(m: &Mesh) {
        let p = m.positions();
        let n = m.normals();
        for (t, tri) in m.triangles().iter().enumerate() {
            let [a, b, c] = tri.map(|i| i as usize);
            let face = cross(p[b] - p[a], p[c] - p[a]);
            assert!(face.length() > 0.0, "triangle {t} is degenerate");
            let avg = n[a] + n[b] + n[c];
            assert!(dot(face, avg) > 0.0, "triangle {t} winds against its normals");
        }
    }

    /// Sum over triangles of the signed volume of (origin, triangle): the enclosed volume of a
    /// closed, outward-wound mesh.
    fn volume(m: &Mesh) -> f32 {
        let p = m.positions();
        m.triangles()
            .iter()
            .map(|&[a, b, c]| dot(p[a as usize], cross(p[b as usize], p[c as usize])) / 6.0)
            .sum()
    }

    #[test]
    fn cuboid_is_closed_and_outward() {
        let m = Mesh::cuboid(Vec3::new(0.5, 0.6, 0.025));
        assert_eq!(m.triangle_count(), 12);
        assert_outward_consistent(&m);
        assert!((volume(&m) - 1.0 * 1.2 * 0.05).abs() < 1e-6);
        let t = Mesh::cuboid_tessellated(Vec3::ONE, 4);
        assert_eq!(t.triangle_count(), 6 * 16 * 2);
        assert!((volume(&t) - 8.0).abs() < 1e-4);
    }

    #[test]
    fn cylinder_volume_and_normals() {
        let m = Mesh::cylinder(0.05, 0.1, 64);
        assert_outward_consistent(&m);
        let exact = std::f32::consts::PI * 0.05 * 0.05 * 0.2;
        assert!((volume(&m) - exact).abs() / exact < 0.01);
        // Side normals are horizontal, cap normals vertical (hard edge at the rim).
        for (p, n) in m.positions().iter().zip(m.normals()) {
            if p.z.abs() < 0.1 - 1e-6 {
                assert!(n.z.abs() < 1e-6);
            }
        }
        assert!(m.normals().iter().any(|n| (*n - Vec3::Z).length() < 1e-6));
        assert!(m.normals().iter().any(|n| (*n + Vec3::Z).length() < 1e-6));
    }

    #[test]
    fn sphere_and_capsule_are_closed_with_radial_normals() {
        let s = Mesh::sphere(0.3, 32);
        assert_outward_consistent(&s);
        // Smooth profiles share one ring of vertices between neighbouring bands.
        assert_eq!(s.vertex_count(), 17 * 33);
        let exact = 4.0 / 3.0 * std::f32::consts::PI * 0.027;
        assert!((volume(&s) - exact).abs() / exact < 0.03);
        for (p, n) in s.positions().iter().zip(s.normals()) {
            assert!((p.normalize() - *n).length() < 0.05);
        }
        let c = Mesh::capsule(0.1, 0.2, 24);
        assert_outward_consistent(&c);
        let exact = std::f32::consts::PI * 0.01 * 0.4 + 4.0 / 3.0 * std::f32::consts::PI * 0.001;
        assert!((volume(&c) - exact).abs() / exact < 0.03);
    }

    #[test]
    fn lathe_bowl_inside_faces_up() {
        // Outside from the bottom centre up to the rim, then the inside back down.
        let bowl = [(0.0, 0.0), (0.04, 0.0), (0.05, 0.04), (0.045, 0.04), (0.035, 0.005), (0.0, 0.005)];
        let m = Mesh::lathe(&bowl, 24);
        assert_outward_consistent(&m);
        // The inner bottom (z = 0.005, r < 0.035) faces up; the outer bottom faces down.
        let up = m.positions().iter().zip(m.normals()).any(|(p, n)| p.z == 0.005 && n.z > 0.99);
        let down = m.positions().iter().zip(m.normals()).any(|(p, n)| p.z == 0.0 && n.z < -0.99);
        assert!(up && down);
    }

    #[test]
    fn bad_sizes_do_not_panic() {
        let m = Mesh::lathe(&[(f32::NAN, 0.0), (1.0, 0.0)], 0);
        assert_eq!(m.triangle_count(), 0);
        let m = Mesh::cylinder(-1.0, f32::INFINITY, 1);
        assert!(m.positions().iter().all(|p| p.is_finite()));
        assert_eq!(Mesh::lathe_capped(&[], 8).triangle_count(), 0);
    }

    #[test]
    fn plane_uvs_span_the_unit_square() {
        let m = Mesh::grid(2.0, 1.0, 4, 2);
        assert_eq!(m.triangle_count(), 16);
        assert_outward_consistent(&m);
        let uv = m.uvs().unwrap();
        assert_eq!(uv.first(), Some(&Vec2::new(0.0, 1.0)));
        assert_eq!(uv.last(), Some(&Vec2::new(1.0, 0.0)));
    }
}
