//! Camera-space clipping: the near plane, a guard band, and trivial rejection.
//!
//! Triangles are cut in camera space (before the perspective divide), interpolating lit colours
//! and UVs linearly, as OpenGL clips. Only the near plane is needed for correctness; the guard
//! band (far outside the image) keeps fixed-point screen coordinates small.

use glam::{Vec2, Vec3, Vec4};

use super::lighting::Lit;
use crate::camera::Intrinsics;

/// Screen coordinates beyond ±this many pixels are clipped away before rasterization.
const GUARD_PX: f32 = (1 << 19) as f32;
/// The guard band in fixed-point units (with a little slack for rounding at its edge); the
/// rasterizer's integer arithmetic is sized for coordinates up to this.
pub(crate) const GUARD_FIXED: i64 = 2 << (19 + 8);

/// Outcode bits: a vertex outside the plane sets the bit.
pub(crate) const NEAR: u16 = 1;
const GUARD_SHIFT: u16 = 1; // bits 1..=4
const VIEW_SHIFT: u16 = 5; // bits 5..=8
/// Bits that require clipping (near plane and guard band).
pub(crate) const MUST_CLIP: u16 = NEAR | (0b1111 << GUARD_SHIFT);
/// Bits that allow rejecting a triangle when all three vertices share one.
pub(crate) const REJECT: u16 = NEAR | (0b1111 << VIEW_SHIFT);

/// Half-space `a x + b y + c z + d ≥ 0` in camera coordinates.
#[derive(Clone, Copy, Debug)]
struct HalfSpace([f32; 4]);

impl HalfSpace {
    #[inline]
    fn eval(&self, p: Vec3) -> f32 {
        let [a, b, c, d] = self.0;
        a * p.x + b * p.y + c * p.z + d
    }
}

/// A bounding sphere against the view volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SphereClass {
    /// Nothing of it can be seen.
    Outside,
    /// Partly inside: vertices need outcodes.
    Straddles,
    /// Wholly in front of the near plane and within the image (with its one-pixel margin):
    /// every vertex has outcode 0.
    Inside,
}

/// Four half-spaces evaluated at once, one per lane: the same IEEE operations in the same order
/// as [`HalfSpace::eval`], so the same results (outcodes run for every vertex in view).
#[derive(Clone, Copy, Debug)]
struct Lanes {
    a: Vec4,
    b: Vec4,
    c: Vec4,
    d: Vec4,
}

impl Lanes {
    fn new(h: &[HalfSpace; 4]) -> Lanes {
        let col = |k: usize| Vec4::from_array(h.map(|h| h.0[k]));
        Lanes { a: col(0), b: col(1), c: col(2), d: col(3) }
    }

    /// Bit `i` set where `p` is outside half-space `i` (or the test is NaN).
    #[inline]
    fn outside(&self, p: Vec3) -> u16 {
        let e = self.a * p.x + self.b * p.y + self.c * p.z + self.d;
        (!e.cmpge(Vec4::ZERO).bitmask() & 0b1111) as u16
    }
}

/// The clip planes of one view.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ClipSpace {
    near: HalfSpace,
    guard: [HalfSpace; 4],
    view: [HalfSpace; 4],
    guard_lanes: Lanes,
    view_lanes: Lanes,
}

impl ClipSpace {
    pub(crate) fn new(k: &Intrinsics, width: u32, height: u32, near: f32) -> ClipSpace {
        // sx = fx x / z + cx ≥ lo  ⇔  fx x + (cx − lo) z ≥ 0;  sx ≤ hi  ⇔  −fx x + (hi − cx) z ≥ 0.
        let sides = |lo_x: f32, hi_x: f32, lo_y: f32, hi_y: f32| {
            [
                HalfSpace([k.fx, 0.0, k.cx - lo_x, 0.0]),
                HalfSpace([-k.fx, 0.0, hi_x - k.cx, 0.0]),
                HalfSpace([0.0, k.fy, k.cy - lo_y, 0.0]),
                HalfSpace([0.0, -k.fy, hi_y - k.cy, 0.0]),
            ]
        };
        let (w, h) = (width as f32, height as f32);
        let guard = sides(-GUARD_PX, GUARD_PX, -GUARD_PX, GUARD_PX);
        // One pixel of margin: a triangle entirely beyond it cannot cover a pixel centre.
        let view = sides(-1.0, w, -1.0, h);
        ClipSpace { near: HalfSpace([0.0, 0.0, 1.0, -near]), guard, view, guard_lanes: Lanes::new(&guard), view_lanes: Lanes::new(&view) }
    }

    /// Which planes `p` is outside of.
    #[inline]
    pub(crate) fn outcode(&self, p: Vec3) -> u16 {
        let near = (!(self.near.eval(p) >= 0.0)) as u16;
        near | self.guard_lanes.outside(p) << GUARD_SHIFT | self.view_lanes.outside(p) << VIEW_SHIFT
    }

    /// Each plane of the outcode with its bit, as `(bit, [a, b, c, d])`.
    pub(crate) fn planes(&self) -> impl Iterator<Item = (u16, [f32; 4])> + '_ {
        let guard = self.guard.iter().enumerate().map(|(i, h)| (1 << (GUARD_SHIFT + i as u16), h.0));
        let view = self.view.iter().enumerate().map(|(i, h)| (1 << (VIEW_SHIFT + i as u16), h.0));
        std::iter::once((NEAR, self.near.0)).chain(guard).chain(view)
    }

    /// Where a bounding sphere (camera coordinates) lies relative to the near plane, the far
    /// distance and the image's side planes.
    pub(crate) fn classify_sphere(&self, c: Vec3, r: f32, far: f32) -> SphereClass {
        let mut inside = true;
        for h in std::iter::once(&self.near).chain(self.view.iter()) {
            let [a, b, cc, _] = h.0;
            let distance = h.eval(c) / (a * a + b * b + cc * cc).sqrt();
            if !(distance >= -r) {
                return SphereClass::Outside; // Entirely behind this plane (or NaN).
            }
            inside &= distance >= r;
        }
        if !(c.z - r <= far) {
            SphereClass::Outside
        } else if inside {
            SphereClass::Inside
        } else {
            SphereClass::Straddles
        }
    }

    /// Clips the triangle `tri` against every plane in `planes` (outcode bits) into `out`,
    /// returning the polygon's vertex count (0 if nothing is left).
    pub(crate) fn clip(&self, tri: [ClipVert; 3], planes: u16, out: &mut Polygon) -> usize {
        out.len = 3;
        out.verts[..3].copy_from_slice(&tri);
        if planes & NEAR != 0 {
            out.clip_against(self.near);
        }
        for (i, h) in self.guard.iter().enumerate() {
            if planes & (1 << (GUARD_SHIFT + i as u16)) != 0 {
                out.clip_against(*h);
            }
        }
        out.len
    }
}

/// A vertex carried through clipping.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ClipVert {
    /// Camera coordinates.
    pub p: Vec3,
    pub lit: Lit,
    pub uv: Vec2,
}

impl ClipVert {
    fn lerp(&self, other: &ClipVert, t: f32) -> ClipVert {
        let mix = |a: f32, b: f32| a + (b - a) * t;
        ClipVert {
            p: self.p + (other.p - self.p) * t,
            lit: Lit {
                base: std::array::from_fn(|i| mix(self.lit.base[i], other.lit.base[i])),
                shadowed: std::array::from_fn(|i| mix(self.lit.shadowed[i], other.lit.shadowed[i])),
            },
            uv: self.uv + (other.uv - self.uv) * t,
        }
    }
}

/// A convex polygon with room for a triangle clipped by all five clipping planes.
#[derive(Default)]
pub(crate) struct Polygon {
    pub verts: [ClipVert; 9],
    pub len: usize,
    scratch: [ClipVert; 9],
}

impl Polygon {
    /// Sutherland–Hodgman against one half-space.
    fn clip_against(&mut self, h: HalfSpace) {
        let n = self.len;
        let mut m = 0;
        for i in 0..n {
            let a = self.verts[i];
            let b = self.verts[(i + 1) % n];
            let (da, db) = (h.eval(a.p), h.eval(b.p));
            if da >= 0.0 {
                self.scratch[m] = a;
                m += 1;
            }
            if (da >= 0.0) != (db >= 0.0) {
                // Always interpolate from the inside vertex, so the two triangles sharing this
                // edge compute the same cut point bit for bit (no cracks).
                self.scratch[m] = if da >= 0.0 { a.lerp(&b, da / (da - db)) } else { b.lerp(&a, db / (db - da)) };
                m += 1;
            }
        }
        self.verts[..m].copy_from_slice(&self.scratch[..m]);
        self.len = m;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::next_unit;

    fn cv(x: f32, y: f32, z: f32, c: f32) -> ClipVert {
        ClipVert { p: Vec3::new(x, y, z), lit: Lit { base: [c; 4], shadowed: [0.0; 3] }, uv: Vec2::splat(c) }
    }

    fn space() -> ClipSpace {
        ClipSpace::new(&Intrinsics { fx: 100.0, fy: 100.0, cx: 49.5, cy: 49.5 }, 100, 100, 0.1)
    }

    #[test]
    fn near_plane_cuts_triangle_into_quad_with_interpolated_attributes() {
        let s = space();
        let tri = [cv(0.0, 0.0, -1.0, 0.0), cv(1.0, 0.0, 1.0, 1.0), cv(0.0, 1.0, 1.0, 1.0)];
        let code = s.outcode(tri[0].p);
        assert_ne!(code & NEAR, 0);
        let mut poly = Polygon::default();
        assert_eq!(s.clip(tri, NEAR, &mut poly), 4);
        for v in &poly.verts[..4] {
            assert!(v.p.z >= 0.1 - 1e-6);
        }
        // The cut point on the edge z: -1 → 1 at z = 0.1 is 55 % of the way: colour 0.55.
        let cut = poly.verts[..4].iter().find(|v| v.p.x > 0.0 && v.p.z < 0.2).unwrap();
        assert!((cut.lit.base[0] - 0.55).abs() < 1e-6 && (cut.uv.x - 0.55).abs() < 1e-6);
    }

    #[test]
    fn spheres_are_classified_against_the_view() {
        let s = space();
        assert_eq!(s.classify_sphere(Vec3::new(0.0, 0.0, 5.0), 0.1, 100.0), SphereClass::Inside);
        assert_eq!(s.classify_sphere(Vec3::new(0.0, 0.0, 0.1), 0.5, 100.0), SphereClass::Straddles);
        assert_eq!(s.classify_sphere(Vec3::new(0.0, 0.0, -5.0), 1.0, 100.0), SphereClass::Outside);
        assert_eq!(s.classify_sphere(Vec3::new(50.0, 0.0, 5.0), 1.0, 100.0), SphereClass::Outside);
        assert_eq!(s.classify_sphere(Vec3::new(0.0, 0.0, 500.0), 1.0, 100.0), SphereClass::Outside);
        assert_eq!(s.classify_sphere(Vec3::new(f32::NAN, 0.0, 5.0), 1.0, 100.0), SphereClass::Outside);
    }

    #[test]
    fn outcodes_flag_sides_of_the_view() {
        let s = space();
        assert_eq!(s.outcode(Vec3::new(0.0, 0.0, 1.0)), 0);
        let left = s.outcode(Vec3::new(-10.0, 0.0, 1.0));
        assert_ne!(left & REJECT, 0);
        assert_eq!(left & MUST_CLIP, 0);
        assert_ne!(s.outcode(Vec3::new(-1e5, 0.0, 1.0)) & MUST_CLIP, 0);
        assert_ne!(s.outcode(Vec3::new(f32::NAN, 0.0, 1.0)) & REJECT, 0);
    }

    #[test]
    fn four_lane_outcodes_equal_one_plane_at_a_time() {
        let s = space();
        let one_at_a_time = |p: Vec3| s.planes().filter(|&(_, h)| !(HalfSpace(h).eval(p) >= 0.0)).fold(0, |code, (bit, _)| code | bit);
        let mut seed = 7u64;
        let mut rnd = || (next_unit(&mut seed) - 0.5) * 4.0;
        let specials = [Vec3::new(0.5, 0.5, 0.0), Vec3::new(-0.0, 0.0, 0.1), Vec3::new(f32::INFINITY, 0.0, 1.0), Vec3::new(0.0, f32::NAN, 1.0)];
        for p in specials.into_iter().chain((0..5000).map(|_| Vec3::new(rnd(), rnd(), rnd()))) {
            assert_eq!(s.outcode(p), one_at_a_time(p), "{p}");
        }
    }
}
