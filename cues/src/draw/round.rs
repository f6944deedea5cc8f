//! Round strokes drawn from the distance to their centre line: rings (circles stroked) and
//! polylines with round caps and joins.
//!
//! A stroke with round caps and joins is exactly the set of points within half its width of
//! its centre line, so each pixel's coverage follows from one distance: `w/2 + ½ − d`, clamped
//! to [0, 1] (a one-pixel ramp across the edge, as an anti-aliased fill gives). Only the rows'
//! spans that can be covered are visited. On the wrist camera a bullseye's rings or a chevron
//! trail is redrawn every frame, and tiny-skia's stroker and supersampled scan cost 30–40 ns a
//! covered pixel there, which put those cues over the insertion budget.

use tiny_skia::Pixmap;

use super::geom::{V2, v2};
use super::{Rgba, mul255, over};

/// Strokes the circle of radius `r` around `c` with a line `width` wide, source-over onto the
/// premultiplied layer `pm`. Non-finite or non-positive numbers draw nothing.
pub fn ring(pm: &mut Pixmap, c: V2, r: f32, width: f32, color: Rgba) {
    if !(c.x.is_finite() && c.y.is_finite() && r.is_finite() && width.is_finite() && r > 0.0 && width > 0.0) {
        return;
    }
    let reach = width / 2.0 + 0.5;
    let (outer, inner) = (r + reach, r - reach);
    let spans = |y: f32| {
        let dy = y - c.y;
        if dy.abs() >= outer {
            return [None, None];
        }
        let xo = libm::sqrtf(outer * outer - dy * dy);
        if inner > 0.0 && dy.abs() < inner {
            let xi = libm::sqrtf(inner * inner - dy * dy);
            [Some((c.x - xo, c.x - xi)), Some((c.x + xi, c.x + xo))]
        } else {
            [Some((c.x - xo, c.x + xo)), None]
        }
    };
    let distance = |x: f32, y: f32| (v2(x, y).sub(c).len() - r).abs();
    paint(pm, (c.y - outer, c.y + outer), spans, distance, width, color);
}

/// Strokes the open polyline through `points` with a line `width` wide, round caps and joins,
/// source-over onto the premultiplied layer `pm`; overlapping segments are covered once.
/// Meant for short figures (chevrons): a row is visited from its leftmost to its rightmost
/// covered pixel. Non-finite points or width draw nothing.
pub fn polyline(pm: &mut Pixmap, points: &[V2], width: f32, color: Rgba) {
    if points.is_empty() || !(width.is_finite() && width > 0.0) || points.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return;
    }
    let reach = width / 2.0 + 0.5;
    let segments: Vec<(V2, V2)> =
        if points.len() == 1 { vec![(points[0], points[0])] } else { points.windows(2).map(|p| (p[0], p[1])).collect() };
    let spans = |y: f32| {
        let hull = segments.iter().filter_map(|&(a, b)| capsule_span(a, b, reach, y)).reduce(|(l0, r0), (l1, r1)| (l0.min(l1), r0.max(r1)));
        [hull, None]
    };
    let distance = |x: f32, y: f32| segments.iter().map(|&(a, b)| to_segment(v2(x, y), a, b)).fold(f32::INFINITY, f32::min);
    let top = points.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
    let bottom = points.iter().map(|p| p.y).fold(f32::NEG_INFINITY, f32::max);
    paint(pm, (top - reach, bottom + reach), spans, distance, width, color);
}

/// Distance from `p` to the segment `a`–`b`.
fn to_segment(p: V2, a: V2, b: V2) -> f32 {
    let ab = b.sub(a);
    let l2 = ab.x * ab.x + ab.y * ab.y;
    let t = if l2 > 0.0 { ((p.x - a.x) * ab.x + (p.y - a.y) * ab.y) / l2 } else { 0.0 };
    p.sub(a.add(ab.scale(t.clamp(0.0, 1.0)))).len()
}

/// The `x` range where the row at height `y` meets the points within `reach` of segment `a`–`b`
/// (two discs and the rectangle between them; the shape is convex, so one range).
fn capsule_span(a: V2, b: V2, reach: f32, y: f32) -> Option<(f32, f32)> {
    let disc = |c: V2| {
        let dy = y - c.y;
        (dy.abs() < reach).then(|| {
            let dx = libm::sqrtf(reach * reach - dy * dy);
            (c.x - dx, c.x + dx)
        })
    };
    let n = b.sub(a).unit().perp().scale(reach);
    let corners = [a.add(n), b.add(n), b.sub(n), a.sub(n)];
    let mut side = None::<(f32, f32)>;
    for (p, q) in corners.iter().zip(corners.iter().cycle().skip(1)) {
        if (p.y - y) * (q.y - y) <= 0.0 && p.y != q.y {
            let x = p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y);
            side = Some(side.map_or((x, x), |(l, r)| (l.min(x), r.max(x))));
        }
    }
    [disc(a), disc(b), side].into_iter().flatten().reduce(|(l0, r0), (l1, r1)| (l0.min(l1), r0.max(r1)))
}

/// Blends `color` at coverage `w/2 + ½ − distance(x, y)` into every pixel whose centre lies in
/// one of the row's `spans`, for the rows whose centres lie in `rows`.
fn paint(
    pm: &mut Pixmap,
    rows: (f32, f32),
    spans: impl Fn(f32) -> [Option<(f32, f32)>; 2],
    distance: impl Fn(f32, f32) -> f32,
    width: f32,
    color: Rgba,
) {
    let (w, h) = (pm.width() as i32, pm.height() as i32);
    // Pixel centres at `i + ½`, as tiny-skia samples them.
    let first = |lo: f32, n: i32| ((lo - 0.5).ceil().max(0.0) as i32).min(n);
    let end = |hi: f32, n: i32| ((hi - 0.5).floor() as i32 + 1).clamp(0, n);
    let edge = width / 2.0 + 0.5;
    let data = pm.data_mut();
    for y in first(rows.0, h)..end(rows.1, h) {
        let yc = y as f32 + 0.5;
        for (lo, hi) in spans(yc).into_iter().flatten() {
            for x in first(lo, w)..end(hi, w) {
                let cover = (edge - distance(x as f32 + 0.5, yc)).clamp(0.0, 1.0);
                let a = (color[3] as f32 * cover + 0.5) as u32;
                if a == 0 {
                    continue;
                }
                let s = [mul255(color[0] as u32, a) as u8, mul255(color[1] as u32, a) as u8, mul255(color[2] as u32, a) as u8, a as u8];
                over(&mut data[(y * w + x) as usize * 4..][..4], &s);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn alpha(pm: &Pixmap, x: u32, y: u32) -> u8 {
        pm.data()[((y * pm.width() + x) * 4 + 3) as usize]
    }

    /// Every pixel's coverage from its own distance, without the spans: what `paint` must give.
    fn brute(w: u32, h: u32, distance: impl Fn(f32, f32) -> f32, width: f32) -> Vec<u8> {
        let mut out = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let cover = (width / 2.0 + 0.5 - distance(x as f32 + 0.5, y as f32 + 0.5)).clamp(0.0, 1.0);
                out.push((255.0 * cover + 0.5) as u8);
            }
        }
        out
    }

    fn alphas(pm: &Pixmap) -> Vec<u8> {
        pm.data().chunks_exact(4).map(|p| p[3]).collect()
    }

    #[test]
    fn rings_cover_what_their_distance_says_and_nothing_else() {
        for (c, r, width) in [(v2(30.0, 25.0), 12.0, 4.0), (v2(31.3, 24.6), 3.0, 7.0), (v2(-5.0, 40.0), 30.0, 2.5), (v2(32.0, 24.0), 200.0, 5.0)] {
            let mut pm = Pixmap::new(64, 48).unwrap();
            ring(&mut pm, c, r, width, [255, 255, 255, 255]);
            let want = brute(64, 48, |x, y| (v2(x, y).sub(c).len() - r).abs(), width);
            assert_eq!(alphas(&pm), want, "ring at {c:?} r {r} width {width}");
        }
        // The drawn ring is where it should be: full on the circle, empty at the centre.
        let mut pm = Pixmap::new(64, 48).unwrap();
        ring(&mut pm, v2(32.0, 24.0), 12.0, 4.0, [255, 0, 0, 255]);
        assert_eq!(alpha(&pm, 32 + 12, 24), 255);
        assert_eq!(alpha(&pm, 32, 24), 0);
        assert!(alphas(&pm).iter().filter(|&&a| a > 0).count() > 300);
    }

    #[test]
    fn polylines_cover_what_their_distance_says_and_nothing_else() {
        let shapes: [&[V2]; 5] = [
            &[v2(10.0, 10.0), v2(40.0, 24.0), v2(10.0, 38.0)],
            &[v2(5.5, 40.2), v2(58.0, 3.7)],
            &[v2(20.0, 20.0), v2(20.0, 30.0)],
            &[v2(33.0, 12.0)],
            &[v2(-10.0, 5.0), v2(80.0, 45.0), v2(30.0, 44.5)],
        ];
        for points in shapes {
            for width in [2.2, 7.0] {
                let mut pm = Pixmap::new(64, 48).unwrap();
                polyline(&mut pm, points, width, [40, 205, 80, 255]);
                let segments: Vec<(V2, V2)> =
                    if points.len() == 1 { vec![(points[0], points[0])] } else { points.windows(2).map(|p| (p[0], p[1])).collect() };
                let want = brute(64, 48, |x, y| segments.iter().map(|&(a, b)| to_segment(v2(x, y), a, b)).fold(f32::INFINITY, f32::min), width);
                assert_eq!(alphas(&pm), want, "{points:?} width {width}");
            }
        }
    }

    #[test]
    fn strokes_blend_over_the_layer_and_ignore_bad_numbers() {
        let mut pm = Pixmap::new(32, 32).unwrap();
        ring(&mut pm, v2(16.0, 16.0), 8.0, 6.0, [20, 20, 20, 255]);
        ring(&mut pm, v2(16.0, 16.0), 8.0, 3.0, [60, 225, 90, 255]);
        // The thin green ring over the wide dark one: green on the circle, dark at its sides.
        let px = |x: u32, y: u32| pm.data()[((y * 32 + x) * 4) as usize..][..4].to_vec();
        assert_eq!(px(24, 16), vec![60, 225, 90, 255]);
        assert!(px(26, 16)[3] >= 250, "{:?}", px(26, 16));
        assert!(px(26, 16)[1] < 100, "{:?}", px(26, 16));
        let before = pm.clone();
        for bad in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
            ring(&mut pm, v2(16.0, 16.0), bad, 3.0, [255; 4]);
            ring(&mut pm, v2(16.0, 16.0), 8.0, bad, [255; 4]);
            polyline(&mut pm, &[v2(1.0, 1.0), v2(20.0, 20.0)], bad, [255; 4]);
        }
        polyline(&mut pm, &[v2(1.0, 1.0), v2(f32::NAN, 20.0)], 3.0, [255; 4]);
        polyline(&mut pm, &[], 3.0, [255; 4]);
        assert_eq!(pm.data(), before.data());
    }
}
