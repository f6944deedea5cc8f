//! Triangle coverage with exact fixed-point edge functions, and screen-space attribute planes.
//!
//! Vertices are snapped to 1/256 pixel. Coverage is tested at pixel centres `(i, j)` (integers,
//! the camera's pixel convention) with integer edge functions, so the test is exact and
//! deterministic, and a tie-breaking rule makes every pixel centre on an edge shared by two
//! triangles belong to exactly one of them (no double blending, no cracks).

/// Sub-pixel steps per pixel. With the clipper's guard band of 2^19 pixels, snapped
/// coordinates stay below 2^28 (`GUARD_FIXED`) and edge functions below 2^59, inside `i64`.
pub(crate) const SUB: i64 = 1 << SUB_BITS;
const SUB_BITS: u32 = 8;

/// Bounding boxes narrower than this many pixels are scanned pixel by pixel rather than walked.
const SCAN_WIDTH: u32 = 12;
/// Columns a scanned row tests at once: two vectors of eight, enough for [`SCAN_WIDTH`].
const SCAN_LANES: u32 = 16;
/// Boxes of more rows than this are scanned eight pixels at a time; in smaller ones (a dense
/// mesh's triangles) the vectors' set-up costs more than it saves.
const LANE_ROWS: u32 = 3;

/// Snaps a screen coordinate (pixels) to the fixed-point grid.
#[inline]
pub(crate) fn snap(x: f32) -> i64 {
    crate::num::round(x as f64 * SUB as f64)
}

/// A screen-linear quantity `a·i + b·j + c`, evaluated as `a·i + (b·j + c)` everywhere so that
/// row-wise and per-pixel evaluation give the same bits.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Plane {
    pub a: f32,
    pub b: f32,
    pub c: f32,
}

impl Plane {
    #[inline]
    pub(crate) fn eval(&self, i: f32, j: f32) -> f32 {
        self.a * i + (self.b * j + self.c)
    }
}

/// A triangle ready for traversal: positive orientation, clipped bounding box, edge functions.
pub(crate) struct Setup {
    /// Inclusive pixel bounds.
    i0: u32,
    i1: u32,
    j0: u32,
    j1: u32,
    /// Biased edge functions at pixel `(i0, j0)`; a pixel is covered when all three are ≥ 0.
    e0: [i64; 3],
    /// Edge function change per pixel step in i and in j.
    di: [i64; 3],
    dj: [i64; 3],
    pub planes: Planes,
}

/// What attribute planes need of a set-up triangle: all a triangle keeps while it waits for
/// its lit corners.
#[derive(Clone, Copy)]
pub(crate) struct Planes {
    /// First vertex in pixels (snapped) and the edge vectors from it divided by twice the
    /// area. In f64: clipped triangles can have vertices far off screen, and the planes must
    /// still be accurate at the on-screen pixels.
    x0: f64,
    y0: f64,
    /// `(y2 − y0, y1 − y0, x1 − x0, x2 − x0) / (2 × area)`.
    k: [f64; 4],
    /// Twice the area in square pixels.
    pub area2: f32,
}

impl Planes {
    /// The plane through the vertex values `a` (one per vertex, in setup order).
    pub(crate) fn plane(&self, a: [f32; 3]) -> Plane {
        let a0 = a[0] as f64;
        let (d1, d2) = (a[1] as f64 - a0, a[2] as f64 - a0);
        let pa = d1 * self.k[0] - d2 * self.k[1];
        let pb = d2 * self.k[2] - d1 * self.k[3];
        Plane { a: pa as f32, b: pb as f32, c: (a0 - pa * self.x0 - pb * self.y0) as f32 }
    }
}

impl Setup {
    /// Sets up the triangle with snapped vertices `(x, y)` in the order given. Returns `None`
    /// when it has zero area or covers no pixel centre of a `width × height` image. The vertex
    /// order must give positive orientation (`orientation(..) > 0`).
    pub(crate) fn new(v: [(i64, i64); 3], width: u32, height: u32) -> Option<Setup> {
        let area2 = orientation(v);
        if area2 <= 0 || width == 0 || height == 0 {
            return None;
        }
        let (min_x, max_x) = (v[0].0.min(v[1].0).min(v[2].0), v[0].0.max(v[1].0).max(v[2].0));
        let (min_y, max_y) = (v[0].1.min(v[1].1).min(v[2].1), v[0].1.max(v[1].1).max(v[2].1));
        let ceil_px = |a: i64| -((-a).div_euclid(SUB));
        let i0 = ceil_px(min_x).max(0);
        let i1 = max_x.div_euclid(SUB).min(width as i64 - 1);
        let j0 = ceil_px(min_y).max(0);
        let j1 = max_y.div_euclid(SUB).min(height as i64 - 1);
        if i0 > i1 || j0 > j1 {
            return None;
        }
        let (px, py) = (i0 * SUB, j0 * SUB);
        let mut e0 = [0i64; 3];
        let mut di = [0i64; 3];
        let mut dj = [0i64; 3];
        // Edge k runs between the two vertices other than k; it is ≥ 0 on vertex k's side.
        for k in 0..3 {
            let (a, b) = (v[(k + 1) % 3], v[(k + 2) % 3]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let owns_ties = dy > 0 || (dy == 0 && dx < 0);
            e0[k] = dx * (py - a.1) - dy * (px - a.0) - if owns_ties { 0 } else { 1 };
            di[k] = -dy * SUB;
            dj[k] = dx * SUB;
        }
        let s = 1.0 / SUB as f64;
        let x = [v[0].0 as f64 * s, v[1].0 as f64 * s, v[2].0 as f64 * s];
        let y = [v[0].1 as f64 * s, v[1].1 as f64 * s, v[2].1 as f64 * s];
        let area2 = area2 as f64 * s * s;
        let inv = 1.0 / area2;
        Some(Setup {
            i0: i0 as u32,
            i1: i1 as u32,
            j0: j0 as u32,
            j1: j1 as u32,
            e0,
            di,
            dj,
            planes: Planes {
                x0: x[0],
                y0: y[0],
                k: [(y[2] - y[0]) * inv, (y[1] - y[0]) * inv, (x[1] - x[0]) * inv, (x[2] - x[0]) * inv],
                area2: area2 as f32,
            },
        })
    }

    /// Inclusive pixel bounds `[i0, j0, i1, j1]` (inside the image).
    pub(crate) fn bounds(&self) -> [u32; 4] {
        [self.i0, self.j0, self.i1, self.j1]
    }

    /// The plane through the vertex values `a` (one per vertex, in setup order).
    pub(crate) fn plane(&self, a: [f32; 3]) -> Plane {
        self.planes.plane(a)
    }

    /// Calls `f(j, first, last)` with the covered pixels `first..=last` of every row `j` that
    /// has any. Narrow triangles test each pixel of their bounding box; wider ones track each
    /// edge's crossing from row to row with exact integer steps, so they never visit pixels
    /// outside the triangle. Both give exactly the pixels whose centres pass the edge tests.
    #[inline]
    pub(crate) fn for_each_span(&self, f: impl FnMut(u32, u32, u32)) {
        if self.i1 - self.i0 < SCAN_WIDTH {
            self.scan_spans(f);
        } else {
            self.walk_spans(f);
        }
    }

    /// Spans by testing every pixel of the bounding box (cheap for small boxes: no division).
    fn scan_spans(&self, f: impl FnMut(u32, u32, u32)) {
        if self.j1 - self.j0 >= LANE_ROWS && self.fits_lanes() {
            self.scan_spans_lanes(f);
        } else {
            self.scan_spans_one_by_one(f);
        }
    }

    /// [`Setup::scan_spans`] one pixel at a time, in `i64`.
    fn scan_spans_one_by_one(&self, mut f: impl FnMut(u32, u32, u32)) {
        let mut row = self.e0;
        for j in self.j0..=self.j1 {
            let mut e = row;
            let mut first = None;
            for i in self.i0..=self.i1 {
                if (e[0] | e[1] | e[2]) >= 0 {
                    first.get_or_insert(i);
                } else if let Some(start) = first {
                    f(j, start, i - 1); // Convex: the span has ended.
                    first = None;
                    break;
                }
                e = [e[0] + self.di[0], e[1] + self.di[1], e[2] + self.di[2]];
            }
            if let Some(start) = first {
                f(j, start, self.i1);
            }
            row = [row[0] + self.dj[0], row[1] + self.dj[1], row[2] + self.dj[2]];
        }
    }

    /// Whether every edge value of the bounding box, widened to [`SCAN_LANES`] columns, fits in
    /// an `i32` (a triangle whose vertices lie far off screen can exceed it). The values are
    /// linear in the pixel, so the box's corners bound them.
    fn fits_lanes(&self) -> bool {
        let fits = |x: i64| x == x as i32 as i64;
        let (last_i, last_j) = (SCAN_LANES as i64 - 1, (self.j1 - self.j0) as i64);
        (0..3).all(|k| {
            let (e, di, dj) = (self.e0[k], self.di[k], self.dj[k]);
            fits(last_i * di) && fits(dj) && [0, last_i].iter().all(|&i| [0, last_j].iter().all(|&j| fits(e + i * di + j * dj)))
        })
    }

    /// [`Setup::scan_spans`] for a box whose edge values fit in `i32`: a row's pixels are tested
    /// eight at a time, and its span is read off the mask of covered pixels (the pixels are the
    /// same: a row's covered pixels are contiguous, as the triangle is convex).
    fn scan_spans_lanes(&self, mut f: impl FnMut(u32, u32, u32)) {
        use wide::i32x8;
        let width = self.i1 - self.i0 + 1;
        let in_box = (1u32 << width) - 1;
        let offsets = |first: i32| self.di.map(|d| i32x8::from(std::array::from_fn::<i32, 8, _>(|l| (first + l as i32) * d as i32)));
        // The second eight columns only where the box reaches them.
        let (left, right) = (offsets(0), (width > 8).then(|| offsets(8)));
        let mut row = self.e0.map(|e| e as i32);
        let negative = |row: &[i32; 3], off: &[i32x8; 3]| ((i32x8::splat(row[0]) + off[0]) | (i32x8::splat(row[1]) + off[1]) | (i32x8::splat(row[2]) + off[2])).to_bitmask();
        for j in self.j0..=self.j1 {
            let outside = negative(&row, &left) | right.as_ref().map_or(0, |right| negative(&row, right) << 8);
            let covered = !outside & in_box;
            if covered != 0 {
                f(j, self.i0 + covered.trailing_zeros(), self.i0 + (u32::BITS - 1 - covered.leading_zeros()));
            }
            // After the last row the sum may leave `i32`; it is not used.
            row = std::array::from_fn(|k| row[k].wrapping_add(self.dj[k] as i32));
        }
    }

    /// Spans from edge walkers (no per-pixel work outside the triangle).
    fn walk_spans(&self, mut f: impl FnMut(u32, u32, u32)) {
        let last = (self.i1 - self.i0) as i64;
        let mut walkers: [EdgeWalker; 3] = std::array::from_fn(|k| EdgeWalker::new(self.e0[k], self.di[k], self.dj[k]));
        for j in self.j0..=self.j1 {
            let (mut lo, mut hi) = (0i64, last);
            for w in &walkers {
                match *w {
                    EdgeWalker::Enter { t, .. } => lo = lo.max(t),
                    EdgeWalker::Leave { t, .. } => hi = hi.min(t),
                    EdgeWalker::Flat { e, .. } if e < 0 => hi = -1,
                    EdgeWalker::Flat { .. } => {}
                }
            }
            if lo <= hi {
                f(j, self.i0 + lo as u32, self.i0 + hi as u32);
            }
            for w in &mut walkers {
                w.next_row();
            }
        }
    }

    /// Calls `f(pixel index, i, j, key)` for every covered pixel, row by row, where `key` is
    /// `plane` evaluated at the pixel centre.
    #[inline]
    pub(crate) fn for_each_pixel(&self, plane: &Plane, width: u32, mut f: impl FnMut(usize, u32, u32, f32)) {
        self.for_each_span(|j, first, last| {
            let base = j as usize * width as usize;
            let row_key = plane.b * j as f32 + plane.c;
            for i in first..=last {
                f(base + i as usize, i, j, plane.a * i as f32 + row_key);
            }
        });
    }
}

/// Where one edge starts or ends a row's span, as a pixel offset `t` from the bounding box's
/// left column, kept exact from row to row by a remainder (Bresenham style).
#[derive(Clone, Copy)]
enum EdgeWalker {
    /// The edge function grows along the row (`e + d·t`, `d > 0`): covered from `t` on.
    /// `f = e + d·t ∈ [0, d)`; each row adds `dj = −(q·d + rem)` to `e`.
    Enter { t: i64, f: i64, d: i64, q: i64, rem: i64 },
    /// It shrinks (`e − a·t`, `a > 0`): covered up to `t`. `g = e − a·t ∈ [0, a)`; each row
    /// adds `dj = q·a + rem`.
    Leave { t: i64, g: i64, a: i64, q: i64, rem: i64 },
    /// Constant along the row: covered where `e ≥ 0`.
    Flat { e: i64, dj: i64 },
}

impl EdgeWalker {
    /// From the (biased) edge value `e` at the bounding box's left column and its changes per
    /// pixel (`di`) and per row (`dj`).
    fn new(e: i64, di: i64, dj: i64) -> EdgeWalker {
        if di > 0 {
            let (t, f) = floor_divmod(e, di);
            let (q, rem) = floor_divmod(-dj, di);
            EdgeWalker::Enter { t: -t, f, d: di, q, rem }
        } else if di < 0 {
            let a = -di;
            let (t, g) = floor_divmod(e, a);
            let (q, rem) = floor_divmod(dj, a);
            EdgeWalker::Leave { t, g, a, q, rem }
        } else {
            EdgeWalker::Flat { e, dj }
        }
    }

    #[inline]
    fn next_row(&mut self) {
        match self {
            EdgeWalker::Enter { t, f, d, q, rem } => {
                if *rem > *f {
                    *t += *q + 1;
                    *f += *d - *rem;
                } else {
                    *t += *q;
                    *f -= *rem;
                }
            }
            EdgeWalker::Leave { t, g, a, q, rem } => {
                if *g + *rem >= *a {
                    *t += *q + 1;
                    *g += *rem - *a;
                } else {
                    *t += *q;
                    *g += *rem;
                }
            }
            EdgeWalker::Flat { e, dj } => *e += *dj,
        }
    }
}

/// `(⌊a / b⌋, a mod b)` for `b > 0`, from one hardware division.
#[inline]
fn floor_divmod(a: i64, b: i64) -> (i64, i64) {
    let (q, r) = (a / b, a % b);
    if r < 0 { (q - 1, r + b) } else { (q, r) }
}

/// Whether the bounding box of three snapped points holds a pixel centre. Most triangles of a
/// dense mesh seen from afar hold none; this rejects them before any other setup work, and
/// [`Setup::new`] would reject them too (it also clips the box to the image).
#[inline]
pub(crate) fn box_holds_centre(v: [[i32; 2]; 3]) -> bool {
    // ⌈lo / SUB⌉ ≤ ⌊hi / SUB⌋ per axis, with arithmetic shifts (coordinates stay far below 2^30).
    let holds = |k: usize| {
        let (lo, hi) = (v[0][k].min(v[1][k]).min(v[2][k]), v[0][k].max(v[1][k]).max(v[2][k]));
        (lo + (SUB as i32 - 1)) >> SUB_BITS <= hi >> SUB_BITS
    };
    holds(0) && holds(1)
}

/// Twice the signed area in fixed-point units². [`Setup`] needs it positive. Because screen y
/// points down, counter-clockwise front faces come out negative.
#[inline]
pub(crate) fn orientation(v: [(i64, i64); 3]) -> i64 {
    (v[1].0 - v[0].0) * (v[2].1 - v[0].1) - (v[2].0 - v[0].0) * (v[1].1 - v[0].1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::next_unit;

    fn px(x: f32, y: f32) -> (i64, i64) {
        (snap(x), snap(y))
    }

    fn covered(v: [(i64, i64); 3], w: u32, h: u32) -> Vec<u32> {
        let mut hits = vec![0u32; (w * h) as usize];
        if let Some(s) = Setup::new(v, w, h) {
            s.for_each_pixel(&Plane::default(), w, |idx, _, _, _| hits[idx] += 1);
        }
        hits
    }

    #[test]
    fn samples_exactly_at_integer_pixel_centres() {
        // A triangle covering centres (1,1), (2,1), (1,2) but not (2,2).
        let v = [px(0.5, 0.5), px(2.5, 0.5), px(0.5, 2.5)];
        assert!(orientation(v) > 0);
        let hits = covered(v, 4, 4);
        let on: Vec<usize> = hits.iter().enumerate().filter(|&(_, &h)| h > 0).map(|(i, _)| i).collect();
        assert_eq!(on, vec![5, 6, 9]);
    }

    #[test]
    fn shared_edges_cover_each_pixel_once() {
        // A square split along its diagonal, with the diagonal through pixel centres, in both
        // split directions; plus a fan around a vertex that sits exactly on a pixel centre.
        let (w, h) = (12, 12);
        let quads = [
            [px(1.0, 1.0), px(9.0, 1.0), px(9.0, 9.0), px(1.0, 9.0)],
            [px(0.3, 2.0), px(10.0, 0.7), px(11.0, 11.0), px(2.0, 10.2)],
        ];
        for q in quads {
            for split in 0..2 {
                let (a, b, c, d) = if split == 0 { (q[0], q[1], q[2], q[3]) } else { (q[1], q[2], q[3], q[0]) };
                let mut total = vec![0u32; (w * h) as usize];
                for t in [[a, b, c], [a, c, d]] {
                    for (k, n) in covered(t, w, h).into_iter().enumerate() {
                        total[k] += n;
                    }
                }
                assert!(total.iter().all(|&n| n <= 1), "a pixel was covered twice");
                // Interior pixel centres of the quad are all covered.
                assert_eq!(total[5 * w as usize + 5], 1);
            }
        }
        let centre = px(6.0, 6.0);
        let ring = [px(2.0, 6.0), px(6.0, 2.0), px(10.0, 6.0), px(6.0, 10.0)];
        let mut total = vec![0u32; (w * h) as usize];
        for k in 0..4 {
            let t = [centre, ring[k], ring[(k + 1) % 4]];
            let t = if orientation(t) > 0 { t } else { [t[0], t[2], t[1]] };
            for (idx, n) in covered(t, w, h).into_iter().enumerate() {
                total[idx] += n;
            }
        }
        assert_eq!(total[6 * w as usize + 6], 1, "the shared vertex is drawn exactly once");
        assert!(total.iter().all(|&n| n <= 1));
    }

    #[test]
    fn spans_match_brute_force_edge_tests() {
        // Random triangles, including thin, huge and off-screen ones, against a direct
        // evaluation of the tie-broken edge functions at every pixel centre.
        let (w, h) = (40u32, 30u32);
        let mut seed = 12345u64;
        let mut rnd = |range: f32| (next_unit(&mut seed) - 0.25) * range;
        for n in 0..2000 {
            let range = if n % 3 == 0 { 400.0 } else { 60.0 };
            let mut v = [(snap(rnd(range)), snap(rnd(range))), (snap(rnd(range)), snap(rnd(range))), (snap(rnd(range)), snap(rnd(range)))];
            if orientation(v) < 0 {
                v.swap(1, 2);
            }
            let mut want = vec![0u32; (w * h) as usize];
            if orientation(v) > 0 {
                for j in 0..h as i64 {
                    for i in 0..w as i64 {
                        let (px, py) = (i * SUB, j * SUB);
                        let inside = (0..3).all(|k| {
                            let (a, b) = (v[(k + 1) % 3], v[(k + 2) % 3]);
                            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                            let e = dx * (py - a.1) - dy * (px - a.0);
                            e > 0 || (e == 0 && (dy > 0 || (dy == 0 && dx < 0)))
                        });
                        want[(j * w as i64 + i) as usize] = inside as u32;
                    }
                }
            }
            assert_eq!(covered(v, w, h), want, "triangle {n}: {v:?}");
        }
    }

    #[test]
    fn scanning_eight_pixels_at_a_time_gives_the_same_spans() {
        // Narrow boxes of every width the scan takes, short and tall, some with a vertex far
        // off screen (edge values beyond `i32`, which the vector scan must refuse).
        let mut seed = 4242u64;
        let mut rnd = |range: f32| next_unit(&mut seed) * range;
        let (mut vector, mut refused) = (0, 0);
        for n in 0..20_000 {
            let (x, y) = (rnd(200.0), rnd(200.0));
            let (w, h) = (rnd(SCAN_WIDTH as f32), rnd(if n % 2 == 0 { 6.0 } else { 120.0 }));
            let far = if n % 7 == 0 { 300_000.0 } else { 0.0 };
            let mut v = [px(x, y), px(x + w, y + rnd(h)), px(x + rnd(w), y + h + far)];
            if orientation(v) < 0 {
                v.swap(1, 2);
            }
            let Some(s) = Setup::new(v, 256, 256) else { continue };
            if s.i1 - s.i0 >= SCAN_WIDTH {
                continue;
            }
            fn spans(scan: impl FnOnce(&mut dyn FnMut(u32, u32, u32))) -> Vec<(u32, u32, u32)> {
                let mut out = Vec::new();
                scan(&mut |j, a, b| out.push((j, a, b)));
                out
            }
            let want = spans(|f| s.scan_spans_one_by_one(f));
            if s.fits_lanes() {
                vector += 1;
                assert_eq!(spans(|f| s.scan_spans_lanes(f)), want, "triangle {n}: {v:?}");
            } else {
                refused += 1;
            }
            assert_eq!(spans(|f| s.scan_spans(f)), want, "triangle {n}: {v:?}");
        }
        assert!(vector > 1000 && refused > 100, "{vector} scanned by vectors, {refused} refused");
    }

    #[test]
    fn planes_interpolate_vertex_values() {
        let v = [px(0.0, 0.0), px(8.0, 0.0), px(0.0, 8.0)];
        // Flip to positive orientation.
        let v = if orientation(v) > 0 { v } else { [v[0], v[2], v[1]] };
        let s = Setup::new(v, 10, 10).unwrap();
        let vals = v.map(|(x, y)| (x + 2 * y) as f32 / SUB as f32);
        let p = s.plane(vals);
        assert!((p.eval(3.0, 2.0) - 7.0).abs() < 1e-5);
    }

    #[test]
    fn box_test_rejects_exactly_the_triangles_between_pixel_centres() {
        let mut seed = 99u64;
        let mut rnd = |range: f32| (next_unit(&mut seed) - 0.25) * range;
        for n in 0..5000 {
            let range = if n % 2 == 0 { 3.0 } else { 40.0 };
            let mut v = [px(rnd(range), rnd(range)), px(rnd(range), rnd(range)), px(rnd(range), rnd(range))];
            if orientation(v) < 0 {
                v.swap(1, 2);
            }
            let small = v.map(|(x, y)| [x as i32, y as i32]);
            // A box with no pixel centre never yields a set-up triangle, on any image size.
            if !box_holds_centre(small) {
                assert!(Setup::new(v, 1 << 12, 1 << 12).is_none(), "{v:?}");
            }
            let (xs, ys) = (v.map(|p| p.0), v.map(|p| p.1));
            let centre_in = |lo: i64, hi: i64| (lo..=hi).any(|c| c.rem_euclid(SUB) == 0);
            let want = centre_in(*xs.iter().min().unwrap(), *xs.iter().max().unwrap()) && centre_in(*ys.iter().min().unwrap(), *ys.iter().max().unwrap());
            assert_eq!(box_holds_centre(small), want, "{v:?}");
        }
    }

    #[test]
    fn offscreen_and_degenerate_triangles_are_skipped() {
        assert!(Setup::new([px(-5.0, -5.0), px(-1.0, -5.0), px(-5.0, -1.0)], 4, 4).is_none());
        assert!(Setup::new([px(1.0, 1.0), px(2.0, 2.0), px(3.0, 3.0)], 4, 4).is_none());
        // Between pixel centres: covers nothing.
        let v = [px(1.1, 1.1), px(1.9, 1.1), px(1.1, 1.9)];
        let v = if orientation(v) > 0 { v } else { [v[0], v[2], v[1]] };
        assert!(Setup::new(v, 4, 4).is_none());
    }
}
