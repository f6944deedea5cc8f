//! The vertex stage: an instance's mesh positions to camera space, outcodes and snapped screen
//! positions, eight at a time, kept per distinct position ([`crate::mesh::Points`]) in [`Verts`].
//!
//! Each lane does the IEEE operations of one vertex's transform (`mul_mat3`, then
//! [`ClipSpace::outcode`] and [`View::project`]) in the same order, so the results are the same
//! bits. Dense scanned meshes put tens of thousands of vertices through this stage per frame.

use glam::{Mat3, Vec3};
use wide::f32x8;

use super::clip::{ClipSpace, MUST_CLIP};
use super::view::View;

/// Vertices transformed together.
const LANES: usize = 8;

/// One vertex after the stage: camera-space position, snapped screen position and `1/z` (zero
/// where it must be clipped first), and outcode.
pub(super) type Screen = (Vec3, [i32; 2], f32, u16);

/// Mesh → camera → screen for one instance.
pub(super) struct ToScreen<'a> {
    linear: Mat3,
    trans: Vec3,
    /// The instance lies wholly inside the view: every outcode is 0.
    inside: bool,
    view: &'a View,
}

impl<'a> ToScreen<'a> {
    /// For an instance whose mesh → camera map is `linear · p + trans`.
    pub(super) fn new(linear: Mat3, trans: Vec3, inside: bool, view: &'a View) -> ToScreen<'a> {
        ToScreen { linear, trans, inside, view }
    }

    /// One vertex: what each lane of [`ToScreen::lanes`] computes (the tests' reference).
    #[cfg(test)]
    fn one(&self, p: Vec3) -> Screen {
        let cam = crate::transform::mul_mat3(&self.linear, p) + self.trans;
        let code = if self.inside { 0 } else { self.view.clip.outcode(cam) };
        let (xy, iz) = if code & MUST_CLIP == 0 { self.view.project(cam) } else { ([0, 0], 0.0) };
        (cam, xy, iz, code)
    }

    /// Eight vertices; `out(l, result)` receives lane `l`'s.
    #[inline]
    fn lanes(&self, p: [Vec3; LANES], mut out: impl FnMut(usize, Screen)) {
        let splat = f32x8::splat;
        let (x, y, z) = (f32x8::from(p.map(|v| v.x)), f32x8::from(p.map(|v| v.y)), f32x8::from(p.map(|v| v.z)));
        let m = &self.linear;
        // `mul_mat3` then `+ trans`, row by row.
        let row = |a: Vec3, t: f32| splat(a.x) * x + splat(a.y) * y + splat(a.z) * z + splat(t);
        let cx = row(Vec3::new(m.x_axis.x, m.y_axis.x, m.z_axis.x), self.trans.x);
        let cy = row(Vec3::new(m.x_axis.y, m.y_axis.y, m.z_axis.y), self.trans.y);
        let cz = row(Vec3::new(m.x_axis.z, m.y_axis.z, m.z_axis.z), self.trans.z);
        let codes = if self.inside { [0; LANES] } else { self.view.clip.outcode_lanes(cx, cy, cz) };
        // `View::project`'s arithmetic; lanes that must be clipped first are dropped below.
        let k = &self.view.k;
        let u = (splat(k.fx) * (cx / cz) + splat(k.cx)).to_array();
        let v = (splat(k.fy) * (cy / cz) + splat(k.cy)).to_array();
        let iz = (f32x8::ONE / cz).to_array();
        let (cx, cy, cz) = (cx.to_array(), cy.to_array(), cz.to_array());
        for l in 0..LANES {
            let code = codes[l];
            let (xy, iz) = if code & MUST_CLIP == 0 { ([View::fixed(u[l]), View::fixed(v[l])], iz[l]) } else { ([0, 0], 0.0) };
            out(l, (Vec3::new(cx[l], cy[l], cz[l]), xy, iz, code));
        }
    }

    /// The vertices `ids` of `positions`, eight at a time (a last partial group repeats its
    /// last vertex in the spare lanes, whose results are dropped).
    #[inline]
    pub(super) fn each(&self, ids: &[u32], positions: &[Vec3], mut out: impl FnMut(usize, Screen)) {
        for group in ids.chunks(LANES) {
            let id = |l: usize| group[l.min(group.len() - 1)] as usize;
            self.lanes(std::array::from_fn(|l| positions[id(l)]), |l, s| {
                if l < group.len() {
                    out(id(l), s);
                }
            });
        }
    }
}

impl ClipSpace {
    /// [`ClipSpace::outcode`] of eight points (camera coordinates by lane).
    #[inline]
    pub(super) fn outcode_lanes(&self, x: f32x8, y: f32x8, z: f32x8) -> [u16; LANES] {
        let splat = f32x8::splat;
        let mut codes = f32x8::ZERO;
        for (bit, [a, b, c, d]) in self.planes() {
            let e = splat(a) * x + splat(b) * y + splat(c) * z + splat(d);
            // Outside where the test fails (NaN included): the bit, carried in the lane's bits.
            codes |= e.simd_ge(f32x8::ZERO).select(f32x8::ZERO, splat(f32::from_bits(bit as u32)));
        }
        codes.to_array().map(|c| c.to_bits() as u16)
    }
}

/// Per-position results of one instance, in separate arrays so that the culling loop touches
/// only screen positions and outcodes. A clustered mesh fills only the positions of the clusters
/// it draws; a stamp per position says which are filled for the current instance.
#[derive(Default)]
pub(super) struct Verts {
    pub(super) cam: Vec<Vec3>,
    /// Snapped screen position (fits `i32`: the guard band keeps it below 2^28 sub-pixels).
    pub(super) xy: Vec<[i32; 2]>,
    pub(super) iz: Vec<f32>,
    pub(super) code: Vec<u16>,
    stamps: Vec<u32>,
    current: u32,
    /// The vertices to fill next (reused between instances).
    fresh: Vec<u32>,
}

impl Verts {
    /// Fills every position.
    pub(super) fn fill(&mut self, positions: &[Vec3], to: &ToScreen) {
        let n = positions.len();
        self.hold(n);
        let mut ids = std::mem::take(&mut self.fresh);
        ids.clear();
        ids.extend(0..n as u32);
        to.each(&ids, positions, |v, s| self.put(v, s));
        self.fresh = ids;
    }

    #[inline]
    fn put(&mut self, v: usize, (cam, xy, iz, code): Screen) {
        (self.cam[v], self.xy[v], self.iz[v], self.code[v]) = (cam, xy, iz, code);
    }

    /// Snapped screen position of point `i` (a distinct position of the mesh).
    #[inline]
    pub(super) fn screen(&self, i: usize) -> (i64, i64) {
        (self.xy[i][0] as i64, self.xy[i][1] as i64)
    }

    /// Starts an instance whose positions are filled on demand by [`Verts::ensure`].
    pub(super) fn begin(&mut self, points: usize) {
        if self.stamps.len() < points {
            self.stamps.resize(points, 0);
        }
        self.hold(points);
        self.current = self.current.wrapping_add(1);
        if self.current == 0 {
            self.stamps.fill(0);
            self.current = 1;
        }
    }

    /// Room for `points` positions. The arrays only grow: shrinking them for a small mesh
    /// would have the next large one write its whole length again before filling it.
    fn hold(&mut self, points: usize) {
        if self.cam.len() < points {
            self.cam.resize(points, Vec3::ZERO);
            self.xy.resize(points, [0; 2]);
            self.iz.resize(points, 0.0);
            self.code.resize(points, 0);
        }
    }

    /// Fills the positions `used` that this instance has not filled yet.
    #[inline]
    pub(super) fn ensure(&mut self, used: &[u32], positions: &[Vec3], to: &ToScreen) {
        let mut fresh = std::mem::take(&mut self.fresh);
        fresh.clear();
        for &v in used {
            if self.stamps[v as usize] != self.current {
                self.stamps[v as usize] = self.current;
                fresh.push(v);
            }
        }
        to.each(&fresh, positions, |v, s| self.put(v, s));
        self.fresh = fresh;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::next_unit;
    use crate::camera::Camera;

    #[test]
    fn eight_lanes_give_what_one_vertex_at_a_time_gives() {
        let mut seed = 11u64;
        let mut rnd = |scale: f32| (next_unit(&mut seed) - 0.5) * scale;
        let camera = Camera::look_at(Vec3::new(0.4, -0.7, 1.3), Vec3::new(0.0, 0.1, 0.8), Vec3::Z, 60.0, 256, 192);
        let view = View::new(&camera);
        let skewed = (Mat3::from_cols(Vec3::new(0.9, 0.2, -0.1), Vec3::new(-0.3, 1.1, 0.05), Vec3::new(0.1, 0.0, 0.8)), Vec3::new(0.2, -0.1, 1.5));
        let specials = [
            Vec3::ZERO,
            // On the near plane: kept in front of it (`≥`), under the identity.
            Vec3::new(0.0, 0.0, camera.near),
            Vec3::new(0.01, -0.02, camera.near),
            Vec3::new(f32::NAN, 0.0, 1.0),
            Vec3::new(0.0, f32::INFINITY, 1.0),
            Vec3::new(-0.0, 0.0, -0.0),
            Vec3::new(1e6, -1e6, 3.0),
            Vec3::new(0.0, 0.0, -1.5),
        ];
        let mut positions: Vec<Vec3> = specials.to_vec();
        positions.extend((0..4000).map(|n| {
            let s = if n % 3 == 0 { 50.0 } else { 3.0 };
            Vec3::new(rnd(s), rnd(s), rnd(s))
        }));
        // Every vertex, and a scattered subset whose last group is partial.
        let all: Vec<u32> = (0..positions.len() as u32).collect();
        let some: Vec<u32> = all.iter().copied().filter(|i| i % 7 != 3).rev().take(1003).collect();
        let bits = |s: Screen| (s.0.to_array().map(f32::to_bits), s.1, s.2.to_bits(), s.3);
        let (mut clipped, mut drawn) = (0, 0);
        for ((linear, trans), inside) in [skewed, (Mat3::IDENTITY, Vec3::ZERO)].into_iter().flat_map(|m| [(m, false), (m, true)]) {
            let to = ToScreen::new(linear, trans, inside, &view);
            for ids in [&all, &some] {
                let mut seen = vec![false; positions.len()];
                to.each(ids, &positions, |i, s| {
                    assert_eq!(bits(s), bits(to.one(positions[i])), "vertex {i}: {}", positions[i]);
                    if s.3 & MUST_CLIP != 0 {
                        clipped += 1;
                    } else {
                        drawn += 1;
                    }
                    seen[i] = true;
                });
                assert!(ids.iter().all(|&i| seen[i as usize]));
                assert_eq!(seen.iter().filter(|&&s| s).count(), ids.len());
            }
        }
        // Both kinds of vertex were compared.
        assert!(clipped > 100 && drawn > 100, "{clipped} {drawn}");
    }
}
