//! The per-frame view: the camera's intrinsics, clip space and pose as the geometry stage uses
//! them, and the plane a mirror's pass keeps.

use glam::{Mat3, Vec3};

use super::clip::{ClipSpace, GUARD_FIXED, REJECT};
use super::triangle::snap;
use crate::camera::{Camera, Intrinsics};
use crate::transform::{dot, mul_mat3};

/// Per-frame view constants.
pub(super) struct View {
    pub(super) k: Intrinsics,
    pub(super) clip: ClipSpace,
    /// World → camera rotation (rows are the camera's right, down and forward axes).
    pub(super) rot: Mat3,
    pub(super) position: Vec3,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) far: f32,
    /// A mirror's pass: only surfaces on the outer side of this plane are drawn.
    pub(super) keep: Option<Keep>,
}

/// The plane a mirror's pass keeps the outer side of: as a per-pixel test, and in the world.
#[derive(Clone, Copy)]
pub(super) struct Keep {
    pub(super) test: PlaneTest,
    point: Vec3,
    normal: Vec3,
}

/// A world plane as a per-pixel test: `a i + b j + c + d / z` is the signed distance to the
/// plane of the point at pixel `(i, j)` and depth `z`, divided by `z` (so linear in `i`, `j`
/// and `1/z`).
#[derive(Clone, Copy)]
pub(super) struct PlaneTest {
    a: f32,
    b: f32,
    c: f32,
    d: f32,
}

impl PlaneTest {
    /// The plane through `point` with unit normal `normal` (world), seen by `view`.
    pub(super) fn new(view: &View, point: Vec3, normal: Vec3) -> PlaneTest {
        let m = mul_mat3(&view.rot, normal);
        let k = &view.k;
        let (a, b) = (m.x / k.fx, m.y / k.fy);
        PlaneTest { a, b, c: m.z - a * k.cx - b * k.cy, d: dot(normal, view.position - point) }
    }

    /// Distance over depth at pixel `(i, j)` with `1/z = iz`.
    #[inline]
    pub(super) fn at(&self, i: f32, j: f32, iz: f32) -> f32 {
        self.a * i + (self.b * j + self.c) + self.d * iz
    }
}

impl View {
    pub(super) fn new(c: &Camera) -> View {
        let k = c.intrinsics();
        let r = &c.rotation;
        View {
            k,
            clip: ClipSpace::new(&k, c.width, c.height, c.near),
            rot: Mat3::from_cols(r.x_axis, -r.y_axis, -r.z_axis).transpose(),
            position: c.position,
            width: c.width,
            height: c.height,
            far: c.far,
            keep: None,
        }
    }

    /// The view drawing only what lies on the side of the plane through `point` that unit
    /// `normal` points to.
    pub(super) fn keeping(mut self, point: Vec3, normal: Vec3) -> View {
        self.keep = Some(Keep { test: PlaneTest::new(&self, point, normal), point, normal });
        self
    }

    /// Whether an instance's bounding box (corners in world space) lies wholly outside one side
    /// of the view or behind the kept side of its plane: then none of its triangles can show.
    pub(super) fn box_hidden(&self, t: &crate::transform::Transform, centre: Vec3, half: Vec3) -> bool {
        let mut outside = REJECT;
        let mut behind = true;
        for k in 0..8 {
            let sign = |bit: u32| if k & bit == 0 { -1.0 } else { 1.0 };
            let corner = t.transform_point(centre + Vec3::new(sign(1) * half.x, sign(2) * half.y, sign(4) * half.z));
            outside &= self.clip.outcode(mul_mat3(&self.rot, corner - self.position));
            behind &= self.keep.is_some_and(|k| dot(k.normal, corner - k.point) < 0.0);
        }
        outside != 0 || behind
    }

    /// The pixels (inclusive `[x0, y0, x1, y1]`) that a camera-space sphere's projection can
    /// cover, and the `1/z` of its nearest point; `None` unless it lies wholly in front of the eye.
    pub(super) fn sphere_cover(&self, c: Vec3, r: f32) -> Option<([u32; 4], f32)> {
        let (z0, z1) = (c.z - r, c.z + r);
        if !(z0 > 0.0) {
            return None;
        }
        // x/z over the box around the sphere is extreme at its corners; one pixel of margin.
        let (iz0, iz1) = (1.0 / z0, 1.0 / z1);
        let range = |m: f32, f: f32, o: f32, size: u32| {
            let q = [(m - r) * iz0, (m - r) * iz1, (m + r) * iz0, (m + r) * iz1].map(|q| f * q + o);
            let (lo, hi) = (q.iter().fold(f32::INFINITY, |a, &b| a.min(b)), q.iter().fold(f32::NEG_INFINITY, |a, &b| a.max(b)));
            let clamp = |x: f32| (x.max(0.0).min(size as f32 - 1.0)) as u32;
            (clamp(lo - 1.0), clamp(hi + 2.0))
        };
        let (x0, x1) = range(c.x, self.k.fx, self.k.cx, self.width);
        let (y0, y1) = range(c.y, self.k.fy, self.k.cy, self.height);
        Some(([x0, y0, x1, y1], iz0))
    }

    /// The part of this view from pixel `(x0, y0)` to `(x1, y1)` (inclusive), as a view of its own.
    pub(super) fn cropped(mut self, x0: u32, y0: u32, x1: u32, y1: u32, near: f32) -> View {
        self.k.cx -= x0 as f32;
        self.k.cy -= y0 as f32;
        self.width = x1 - x0 + 1;
        self.height = y1 - y0 + 1;
        self.clip = ClipSpace::new(&self.k, self.width, self.height, near);
        self
    }

    /// Screen position (snapped) and `1/z` of a camera-space point in front of the near plane
    /// and inside the guard band; the same arithmetic as [`Camera::project`].
    #[inline]
    pub(super) fn project(&self, c: Vec3) -> ([i32; 2], f32) {
        let u = self.k.fx * (c.x / c.z) + self.k.cx;
        let v = self.k.fy * (c.y / c.z) + self.k.cy;
        ([View::fixed(u), View::fixed(v)], 1.0 / c.z)
    }

    /// A projected coordinate (pixels) snapped to the fixed-point grid. Clipping keeps real
    /// vertices inside the guard band; the clamp only bounds what absurd (but finite) inputs
    /// could produce, so the fixed-point arithmetic cannot overflow.
    #[inline]
    pub(super) fn fixed(x: f32) -> i32 {
        snap(x).clamp(-GUARD_FIXED, GUARD_FIXED) as i32
    }
}
