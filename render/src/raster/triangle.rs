//! Triangle coverage with exact fixed-point edge functions, and screen-space attribute planes.
//!
//! Vertices are snapped to 1/16 pixel. Coverage is tested at pixel centres `(i, j)` (integers,
//! the camera's pixel convention) with integer edge functions, so the test is exact and
//! deterministic, and a tie-breaking rule makes every pixel centre on an edge shared by two
//! triangles belong to exactly one of them (no double blending, no cracks).

/// Sub-pixel steps per pixel.
pub(crate) const SUB: i64 = 16;

/// Snaps a screen coordinate (pixels) to the fixed-point grid.
#[inline]
pub(crate) fn snap(x: f32) -> i64 {
    (x * SUB as f32).round() as i64
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
    /// Vertex positions in pixels (snapped) and `1 / (2 × area)`, for attribute planes.
    x: [f32; 3],
    y: [f32; 3],
    inv_det: f32,
    /// Twice the area in square pixels.
    pub area2: f32,
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
        let s = 1.0 / SUB as f32;
        let x = [v[0].0 as f32 * s, v[1].0 as f32 * s, v[2].0 as f32 * s];
        let y = [v[0].1 as f32 * s, v[1].1 as f32 * s, v[2].1 as f32 * s];
        let area2 = (area2 as f64 / (SUB * SUB) as f64) as f32;
        Some(Setup {
            i0: i0 as u32,
            i1: i1 as u32,
            j0: j0 as u32,
            j1: j1 as u32,
            e0,
            di,
            dj,
            x,
            y,
            inv_det: 1.0 / area2,
            area2,
        })
    }

    /// The plane through the vertex values `a` (one per vertex, in setup order).
    pub(crate) fn plane(&self, a: [f32; 3]) -> Plane {
        let (x, y) = (&self.x, &self.y);
        let (d1, d2) = (a[1] - a[0], a[2] - a[0]);
        let pa = (d1 * (y[2] - y[0]) - d2 * (y[1] - y[0])) * self.inv_det;
        let pb = (d2 * (x[1] - x[0]) - d1 * (x[2] - x[0])) * self.inv_det;
        Plane { a: pa, b: pb, c: a[0] - pa * x[0] - pb * y[0] }
    }

    /// Calls `f(pixel index, i, j, key)` for every covered pixel, row by row, where `key` is
    /// `plane` evaluated at the pixel centre.
    #[inline]
    pub(crate) fn for_each_pixel(&self, plane: &Plane, width: u32, mut f: impl FnMut(usize, u32, u32, f32)) {
        let mut row = self.e0;
        for j in self.j0..=self.j1 {
            let mut e = row;
            let base = j as usize * width as usize;
            let row_key = plane.b * j as f32 + plane.c;
            let mut entered = false;
            for i in self.i0..=self.i1 {
                if (e[0] | e[1] | e[2]) >= 0 {
                    entered = true;
                    f(base + i as usize, i, j, plane.a * i as f32 + row_key);
                } else if entered {
                    break; // Convex: the row's span has ended.
                }
                e[0] += self.di[0];
                e[1] += self.di[1];
                e[2] += self.di[2];
            }
            row[0] += self.dj[0];
            row[1] += self.dj[1];
            row[2] += self.dj[2];
        }
    }
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
    fn offscreen_and_degenerate_triangles_are_skipped() {
        assert!(Setup::new([px(-5.0, -5.0), px(-1.0, -5.0), px(-5.0, -1.0)], 4, 4).is_none());
        assert!(Setup::new([px(1.0, 1.0), px(2.0, 2.0), px(3.0, 3.0)], 4, 4).is_none());
        // Between pixel centres: covers nothing.
        let v = [px(1.1, 1.1), px(1.9, 1.1), px(1.1, 1.9)];
        let v = if orientation(v) > 0 { v } else { [v[0], v[2], v[1]] };
        assert!(Setup::new(v, 4, 4).is_none());
    }
}
