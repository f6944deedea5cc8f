//! The farthest surface per 8 × 8 tile of the visibility buffer, so that a cluster or an
//! instance hidden behind what is already drawn is skipped before its vertices are transformed,
//! and a large triangle before its pixels are tested (instances are drawn front to back, and in
//! LIBERO's scenes most triangles that reach the depth test lose it everywhere: table legs, the
//! robot's inner links, the floor under the table).
//!
//! Tiles are refreshed lazily: a depth write marks its tiles stale, a query recomputes the stale
//! tiles it reads. The test is conservative, so skipping changes no pixel.

/// Tiles are `1 << SHIFT` pixels square.
const SHIFT: u32 = 3;

/// How much farther than everything in a tile a surface must be to count as hidden there, as a
/// fraction of `1/z`: far more than the rounding of the per-pixel `1/z` planes.
const MARGIN: f32 = 1e-3;

#[derive(Default)]
pub(super) struct HiZ {
    tiles_wide: usize,
    /// Per tile, the smallest `1/z` of its pixels (0 where any pixel is empty).
    far: Vec<f32>,
    stale: Vec<bool>,
}

impl HiZ {
    /// Starts a frame of `width × height` empty pixels.
    pub(super) fn reset(&mut self, width: u32, height: u32) {
        self.tiles_wide = tiles(width);
        let n = self.tiles_wide * tiles(height);
        self.far.clear();
        self.far.resize(n, 0.0);
        self.stale.clear();
        self.stale.resize(n, false);
    }

    /// Becomes a copy of `other`, reusing its own memory.
    pub(super) fn copy_from(&mut self, other: &HiZ) {
        self.tiles_wide = other.tiles_wide;
        self.far.clone_from(&other.far);
        self.stale.clone_from(&other.stale);
    }

    /// Notes that any pixel may have been written.
    pub(super) fn mark_all(&mut self) {
        self.stale.fill(true);
    }

    /// Notes that pixels `first..=last` of row `j` were written.
    #[inline]
    pub(super) fn mark(&mut self, j: u32, first: u32, last: u32) {
        let row = (j >> SHIFT) as usize * self.tiles_wide;
        self.stale[row + (first >> SHIFT) as usize..=row + (last >> SHIFT) as usize].fill(true);
    }

    /// Whether every pixel of `rect` (inclusive `[x0, y0, x1, y1]`, inside the image) holds a
    /// surface clearly nearer than `1/z = nearest`, given the visibility buffer `depth` of an
    /// image `width` wide: then nothing at `nearest` or beyond can win a depth test there.
    pub(super) fn hidden(&mut self, depth: &[f32], width: u32, rect: [u32; 4], nearest: f32) -> bool {
        let bound = nearest * (1.0 + MARGIN);
        let w = width as usize;
        let height = depth.len() / w.max(1);
        for ty in (rect[1] >> SHIFT) as usize..=(rect[3] >> SHIFT) as usize {
            for tx in (rect[0] >> SHIFT) as usize..=(rect[2] >> SHIFT) as usize {
                let k = ty * self.tiles_wide + tx;
                if self.stale[k] {
                    self.far[k] = tile_min(depth, w, height, tx << SHIFT, ty << SHIFT);
                    self.stale[k] = false;
                }
                if !(self.far[k] > bound) {
                    return false;
                }
            }
        }
        true
    }
}

/// The smallest `1/z` of the tile whose top left pixel is `(x0, y0)`. A whole tile is read a row
/// of eight at a time: the buffer never holds NaN (a depth test writes only where `1/z` is
/// greater), so the lanes' minimum is the scalar one.
#[inline]
fn tile_min(depth: &[f32], w: usize, height: usize, x0: usize, y0: usize) -> f32 {
    const SIDE: usize = 1 << SHIFT;
    let (x1, y1) = ((x0 + SIDE).min(w), (y0 + SIDE).min(height));
    if x1 - x0 == SIDE && y1 - y0 == SIDE {
        let row = |y: usize| wide::f32x8::from(<[f32; SIDE]>::try_from(&depth[y * w + x0..y * w + x1]).expect("a whole tile's row"));
        let m = (y0 + 1..y1).fold(row(y0), |m, y| m.fast_min(row(y)));
        return m.to_array().into_iter().fold(f32::INFINITY, f32::min);
    }
    (y0..y1).flat_map(|y| &depth[y * w + x0..y * w + x1]).fold(f32::INFINITY, |m, &d| m.min(d))
}

fn tiles(pixels: u32) -> usize {
    pixels.div_ceil(1 << SHIFT) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_minimum_is_the_smallest_depth_of_whole_and_partial_tiles() {
        let (w, h) = (20usize, 12usize);
        let mut seed = 5u32;
        let depth: Vec<f32> = (0..w * h)
            .map(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                if seed >> 29 == 0 { 0.0 } else { (seed >> 8) as f32 / (1u32 << 24) as f32 }
            })
            .collect();
        for ty in 0..tiles(h as u32) {
            for tx in 0..tiles(w as u32) {
                let (x0, y0) = (tx << SHIFT, ty << SHIFT);
                let want = (y0..(y0 + 8).min(h)).flat_map(|y| (x0..(x0 + 8).min(w)).map(move |x| (x, y))).map(|(x, y)| depth[y * w + x]).fold(f32::INFINITY, f32::min);
                assert_eq!(tile_min(&depth, w, h, x0, y0), want, "tile ({tx}, {ty})");
            }
        }
    }

    #[test]
    fn a_rect_is_hidden_only_where_every_pixel_is_clearly_nearer() {
        let (w, h) = (20u32, 12u32);
        let mut depth = vec![0.0f32; (w * h) as usize];
        let mut hiz = HiZ::default();
        hiz.reset(w, h);
        assert!(!hiz.hidden(&depth, w, [0, 0, 19, 11], 0.5), "empty pixels hide nothing");
        depth.fill(2.0);
        for j in 0..h {
            hiz.mark(j, 0, w - 1);
        }
        assert!(hiz.hidden(&depth, w, [0, 0, 19, 11], 1.0));
        assert!(!hiz.hidden(&depth, w, [0, 0, 19, 11], 2.0), "equal depth is not hidden");
        // One nearer-than-the-query pixel in the last, partial tile is enough to show.
        depth[(11 * w + 19) as usize] = 0.9;
        hiz.mark(11, 19, 19);
        assert!(!hiz.hidden(&depth, w, [17, 9, 19, 11], 1.0));
        assert!(hiz.hidden(&depth, w, [0, 0, 15, 7], 1.0));
    }
}
