//! 2D vectors, transforms and the path shapes cues are made of.
//!
//! Angles go through `libm` (tiny-skia's own `Transform::from_rotate` uses the platform's
//! `sin`/`cos`, which differ between platforms); paths are `None` only for degenerate input.

use tiny_skia::{Path, PathBuilder, Rect, Transform};

/// The identity transform as a constant (tiny-skia's constructor is not `const`).
pub const ID: Transform = Transform { sx: 1.0, kx: 0.0, ky: 0.0, sy: 1.0, tx: 0.0, ty: 0.0 };

/// A point or vector in pixels (x right, y down).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V2 {
    pub x: f32,
    pub y: f32,
}

pub const fn v2(x: f32, y: f32) -> V2 {
    V2 { x, y }
}

// Named methods rather than operator traits: geometry reads as chains such as
// `tip.sub(dir.scale(len)).add(n)`.
#[allow(clippy::should_implement_trait)]
impl V2 {
    pub fn add(self, o: V2) -> V2 {
        v2(self.x + o.x, self.y + o.y)
    }
    pub fn sub(self, o: V2) -> V2 {
        v2(self.x - o.x, self.y - o.y)
    }
    pub fn scale(self, s: f32) -> V2 {
        v2(self.x * s, self.y * s)
    }
    pub fn len(self) -> f32 {
        libm::sqrtf(self.x * self.x + self.y * self.y)
    }
    /// Unit vector; (1, 0) for the zero vector so callers never divide by zero.
    pub fn unit(self) -> V2 {
        let l = self.len();
        if l > 1e-6 { self.scale(1.0 / l) } else { v2(1.0, 0.0) }
    }
    /// Rotated by +90° (clockwise on screen, since y points down).
    pub fn perp(self) -> V2 {
        v2(-self.y, self.x)
    }
    pub fn lerp(self, o: V2, t: f32) -> V2 {
        self.add(o.sub(self).scale(t))
    }
    /// Angle of the vector in radians (screen convention).
    pub fn angle(self) -> f32 {
        libm::atan2f(self.y, self.x)
    }
}

/// Rotation by `angle` radians about the origin, then translation to `at`.
pub fn rotate_translate(angle: f32, at: V2) -> Transform {
    let (s, c) = (libm::sinf(angle), libm::cosf(angle));
    Transform::from_row(c, s, -s, c, at.x, at.y)
}

/// Maps the unit box \[0,1\]² onto the pixel rectangle (x, y, w, h).
pub fn unit_box(x: f32, y: f32, w: f32, h: f32) -> Transform {
    Transform::from_row(w, 0.0, 0.0, h, x, y)
}

pub fn circle(c: V2, r: f32) -> Option<Path> {
    PathBuilder::from_circle(c.x, c.y, r.max(0.01))
}

pub fn ellipse(c: V2, rx: f32, ry: f32) -> Option<Path> {
    PathBuilder::from_oval(Rect::from_xywh(c.x - rx, c.y - ry, (2.0 * rx).max(0.01), (2.0 * ry).max(0.01))?)
}

pub fn rect(x: f32, y: f32, w: f32, h: f32) -> Option<Path> {
    Some(PathBuilder::from_rect(Rect::from_xywh(x, y, w.max(0.01), h.max(0.01))?))
}

/// Rectangle with circular corners of radius `r`.
pub fn rounded_rect(x: f32, y: f32, w: f32, h: f32, r: f32) -> Option<Path> {
    let r = r.min(w / 2.0).min(h / 2.0).max(0.0);
    // Cubic approximation of a quarter circle.
    let k = r * 0.552_284_8;
    let mut pb = PathBuilder::new();
    pb.move_to(x + r, y);
    pb.line_to(x + w - r, y);
    pb.cubic_to(x + w - r + k, y, x + w, y + r - k, x + w, y + r);
    pb.line_to(x + w, y + h - r);
    pb.cubic_to(x + w, y + h - r + k, x + w - r + k, y + h, x + w - r, y + h);
    pb.line_to(x + r, y + h);
    pb.cubic_to(x + r - k, y + h, x, y + h - r + k, x, y + h - r);
    pb.line_to(x, y + r);
    pb.cubic_to(x, y + r - k, x + r - k, y, x + r, y);
    pb.close();
    pb.finish()
}

/// Closed polygon through `points`.
pub fn polygon(points: &[V2]) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let (first, rest) = points.split_first()?;
    pb.move_to(first.x, first.y);
    for p in rest {
        pb.line_to(p.x, p.y);
    }
    pb.close();
    pb.finish()
}

/// Open polyline through `points`.
pub fn polyline(points: &[V2]) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let (first, rest) = points.split_first()?;
    pb.move_to(first.x, first.y);
    for p in rest {
        pb.line_to(p.x, p.y);
    }
    pb.finish()
}

/// Regular polygon with `n` corners, the first at angle `start` (radians).
pub fn regular_polygon(c: V2, r: f32, n: usize, start: f32) -> Option<Path> {
    let points: Vec<V2> = (0..n)
        .map(|i| {
            let a = start + i as f32 * core::f32::consts::TAU / n as f32;
            v2(c.x + r * libm::cosf(a), c.y + r * libm::sinf(a))
        })
        .collect();
    polygon(&points)
}

/// Straight segment.
pub fn line(a: V2, b: V2) -> Option<Path> {
    polyline(&[a, b])
}

/// Quadratic Bézier from `a` via control `c` to `b`.
pub fn quad(a: V2, c: V2, b: V2) -> Option<Path> {
    let mut pb = PathBuilder::new();
    pb.move_to(a.x, a.y);
    pb.quad_to(c.x, c.y, b.x, b.y);
    pb.finish()
}

/// Circular arc around `c` from angle `a0` to `a1` (radians), as a polyline.
pub fn arc(c: V2, r: f32, a0: f32, a1: f32) -> Option<Path> {
    let n = 24;
    let points: Vec<V2> = (0..=n)
        .map(|i| {
            let a = a0 + (a1 - a0) * i as f32 / n as f32;
            v2(c.x + r * libm::cosf(a), c.y + r * libm::sinf(a))
        })
        .collect();
    polyline(&points)
}

/// Filled triangular arrow head with its tip at `tip`, pointing along `dir`.
pub fn arrow_head(tip: V2, dir: V2, length: f32, width: f32) -> Option<Path> {
    let d = dir.unit();
    let base = tip.sub(d.scale(length));
    let n = d.perp().scale(width / 2.0);
    polygon(&[tip, base.add(n), base.sub(n)])
}

/// A straight arrow from `a` to `b` as one closed outline (shaft plus head), so it can be
/// filled and bordered in one go. The head shrinks for very short arrows.
pub fn block_arrow(a: V2, b: V2, shaft: f32, head_len: f32, head_w: f32) -> Option<Path> {
    let d = b.sub(a);
    let len = d.len();
    if len < 1.0 {
        return None;
    }
    let u = d.unit();
    let n = u.perp();
    let hl = head_len.min(len * 0.6);
    let neck = b.sub(u.scale(hl));
    let s = shaft / 2.0;
    let h = head_w / 2.0;
    polygon(&[
        a.add(n.scale(s)),
        neck.add(n.scale(s)),
        neck.add(n.scale(h)),
        b,
        neck.sub(n.scale(h)),
        neck.sub(n.scale(s)),
        a.sub(n.scale(s)),
    ])
}

/// A chevron ("›") centred at `c`, pointing along `dir`.
pub fn chevron(c: V2, dir: V2, size: f32) -> Option<Path> {
    polyline(&chevron_points(c, dir, size))
}

/// The three points of [`chevron`]'s polyline: one arm's end, the tip, the other arm's end.
pub fn chevron_points(c: V2, dir: V2, size: f32) -> [V2; 3] {
    let u = dir.unit();
    let n = u.perp();
    let tip = c.add(u.scale(size * 0.5));
    let back = c.sub(u.scale(size * 0.5));
    [back.add(n.scale(size * 0.6)), tip, back.sub(n.scale(size * 0.6))]
}
