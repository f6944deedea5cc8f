//! RGBA8 textures with repeat wrapping, nearest or bilinear filtering, and a mip chain.
//!
//! Texture coordinates follow MuJoCo's use of image rows: `v = 0` is the first (top) row of the
//! image, `u = 0` its left column; texel centres sit at `(i + 0.5) / width`.

use std::ops::{Add, Mul, Sub};

use glam::Vec2;
use thiserror::Error;
use wide::{f32x8, i32x8};

use crate::num::floor;

/// How a texel is chosen between texel centres.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Weighted average of the four surrounding texels.
    #[default]
    Bilinear,
}

/// Why texture data was rejected.
#[derive(Debug, Error, PartialEq)]
pub enum TextureError {
    #[error("texture size {width}×{height} is empty")]
    Empty { width: u32, height: u32 },
    #[error("texture {width}×{height} needs {expected} bytes of {channels}-channel data, got {got}")]
    WrongLength { width: u32, height: u32, channels: u32, expected: usize, got: usize },
}

#[derive(Clone, Debug, PartialEq)]
struct Level {
    width: u32,
    height: u32,
    texels: Vec<[u8; 4]>,
}

/// Texel value → `[0, 1]`.
const UNIT: f32 = 1.0 / 255.0;

/// Points sampled together by [`Texture::sample_level_rgb8`].
const LANES: usize = 8;

impl Level {
    /// `(u, v)` in texel units, texel centres at whole numbers.
    #[inline]
    fn texel_space(&self, u: f32, v: f32) -> (f32, f32) {
        (u * self.width as f32 - 0.5, v * self.height as f32 - 0.5)
    }

    /// The texel at `(x, y)`, wrapped (repeat).
    #[inline]
    fn fetch(&self, x: i64, y: i64) -> [u8; 4] {
        let (w, h) = (self.width as i64, self.height as i64);
        self.texels[(y.rem_euclid(h) * w + x.rem_euclid(w)) as usize]
    }

    /// The four texels around `(x, y)` (texel units), top-left, top-right, bottom-left,
    /// bottom-right, and the blend weights towards the right and the bottom.
    #[inline]
    fn square(&self, x: f32, y: f32) -> ([[u8; 4]; 4], f32, f32) {
        let (w, h) = (self.width as i64, self.height as i64);
        let (x0, y0) = (floor(x), floor(y));
        let (ax, ay) = (x - x0 as f32, y - y0 as f32);
        // Inside the level (the common case) no wrapping is needed: skip the divisions.
        let texels = if x0 >= 0 && y0 >= 0 && x0 + 1 < w && y0 + 1 < h {
            let i = (y0 * w + x0) as usize;
            let s = self.width as usize;
            [self.texels[i], self.texels[i + 1], self.texels[i + s], self.texels[i + s + 1]]
        } else {
            [self.fetch(x0, y0), self.fetch(x0 + 1, y0), self.fetch(x0, y0 + 1), self.fetch(x0 + 1, y0 + 1)]
        };
        (texels, ax, ay)
    }
}

/// An image used to colour surfaces. Immutable; share it with `Arc<Texture>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Level 0 is the full image; each next level halves both sizes (box filtered).
    levels: Vec<Level>,
    filter: Filter,
}

impl Texture {
    /// A texture from tightly packed RGBA8 rows, top row first.
    pub fn from_rgba8(width: u32, height: u32, data: &[u8]) -> Result<Texture, TextureError> {
        let texels = check(width, height, 4, data)?.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect();
        Ok(Texture::from_level(Level { width, height, texels }))
    }

    /// A texture from tightly packed RGB8 rows, top row first (alpha 255).
    pub fn from_rgb8(width: u32, height: u32, data: &[u8]) -> Result<Texture, TextureError> {
        let texels = check(width, height, 3, data)?.chunks_exact(3).map(|c| [c[0], c[1], c[2], 255]).collect();
        Ok(Texture::from_level(Level { width, height, texels }))
    }

    /// A 1×1 texture of one colour.
    pub fn solid(rgba: [u8; 4]) -> Texture {
        Texture::from_level(Level { width: 1, height: 1, texels: vec![rgba] })
    }

    /// The same texture with another filter.
    pub fn with_filter(mut self, filter: Filter) -> Texture {
        self.filter = filter;
        self
    }

    /// Width of the full-resolution image.
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of the full-resolution image.
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// The full-size level: width, height, texels (see [`crate::pack`]).
    pub(crate) fn full_level(&self) -> (u32, u32, &[[u8; 4]]) {
        (self.levels[0].width, self.levels[0].height, &self.levels[0].texels)
    }

    /// The filter used when sampling.
    pub fn filter(&self) -> Filter {
        self.filter
    }

    /// Number of mip levels (1 for a 1×1 texture).
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// RGBA in `[0, 1]` at `uv` from the full-resolution level, wrapping (repeat).
    pub fn sample(&self, uv: Vec2) -> [f32; 4] {
        self.sample_level(uv.x, uv.y, 0)
    }

    /// RGBA in `[0, 1]` at `(u, v)` from mip `level` (clamped to the last level).
    #[inline]
    pub(crate) fn sample_level(&self, u: f32, v: f32, level: usize) -> [f32; 4] {
        let lv = self.level(level);
        let (x, y) = lv.texel_space(u, v);
        self.sample_at(lv, x, y)
    }

    /// RGBA in `[0, 1]` at `(x, y)` in texel units of `lv`.
    #[inline]
    fn sample_at(&self, lv: &Level, x: f32, y: f32) -> [f32; 4] {
        match self.filter {
            Filter::Nearest => lv.fetch(floor(x + 0.5), floor(y + 0.5)).map(|c| c as f32 * UNIT),
            Filter::Bilinear => {
                let (texels, ax, ay) = lv.square(x, y);
                std::array::from_fn(|c| blend(texels.map(|t| t[c] as f32), ax, ay) * UNIT)
            }
        }
    }

    /// Red, green and blue of [`Texture::sample_level`] at eight points: each lane does the
    /// same float operations as one sample alone, so the results are the same bits. Bilinear
    /// samples find their texels (wrapped) and blend them eight wide; a nearest sample, or a
    /// group with a coordinate that is huge or NaN, goes lane by lane.
    #[inline]
    pub(crate) fn sample_level_rgb8(&self, u: f32x8, v: f32x8, level: usize) -> [f32x8; 3] {
        let lv = self.level(level);
        let splat = f32x8::splat;
        let (w, h) = (lv.width as f32, lv.height as f32);
        // `texel_space`.
        let (x, y) = (u * splat(w) - splat(0.5), v * splat(h) - splat(0.5));
        let unit = splat(UNIT);
        const SMALL: f32 = 4_194_304.0;
        let small = splat(SMALL);
        let sizes_small = w < SMALL && h < SMALL;
        if self.filter == Filter::Bilinear && sizes_small && (x.abs().simd_lt(small) & y.abs().simd_lt(small)).all() {
            // With coordinates and sizes below 2^22 these float operations are exact: `floor`
            // (through i64) is the truncation minus one where it rounded up, and `rem_euclid`
            // the remainder after the floored quotient.
            let floor8 = |x: f32x8| {
                let t = x.fast_trunc_int().round_float();
                t.simd_gt(x).select(t - f32x8::ONE, t)
            };
            let (x0, y0) = (floor8(x), floor8(y));
            let (ax, ay) = (x - x0, y - y0);
            // Wrapped columns and rows of the square, as `Level::square` fetches them.
            let wrap = |a: f32x8, size: f32| {
                let size = splat(size);
                let first = a - floor8(a / size) * size;
                let next = first + f32x8::ONE;
                (first.fast_trunc_int().to_array(), next.simd_eq(size).select(f32x8::ZERO, next).fast_trunc_int().to_array())
            };
            let ((xa, xb), (ya, yb)) = (wrap(x0, w), wrap(y0, h));
            let s = lv.width as usize;
            let mut corners = [[0i32; LANES]; 4];
            for l in 0..LANES {
                let (top, bottom) = (ya[l] as usize * s, yb[l] as usize * s);
                let at = [top + xa[l] as usize, top + xb[l] as usize, bottom + xa[l] as usize, bottom + xb[l] as usize];
                for (corner, k) in corners.iter_mut().zip(at) {
                    corner[l] = i32::from_le_bytes(lv.texels[k]);
                }
            }
            let corners = corners.map(i32x8::from);
            return std::array::from_fn(|c| blend(corners.map(|t| ((t >> (8 * c as u32)) & i32x8::splat(0xFF)).round_float()), ax, ay) * unit);
        }
        let (x, y) = (x.to_array(), y.to_array());
        let mut out = [[0.0f32; LANES]; 3];
        for l in 0..LANES {
            let t = self.sample_at(lv, x[l], y[l]);
            for c in 0..3 {
                out[c][l] = t[c];
            }
        }
        out.map(f32x8::from)
    }

    fn level(&self, level: usize) -> &Level {
        &self.levels[level.min(self.levels.len() - 1)]
    }

    /// The mip level whose texels are about one pixel in size, given how many level-0 texels
    /// fall on one pixel (by area).
    pub(crate) fn level_for_density(&self, texels_per_pixel: f32) -> usize {
        if !(texels_per_pixel > 1.0) {
            return 0;
        }
        let last = self.levels.len() as i64 - 1;
        // For x = 2^e · (1 + f), 0 < f < 1, the rounding below gives ⌊(e + 1) / 2⌋. That is read
        // off the exponent bits (one log per textured triangle showed in profiles) wherever f is
        // far enough from 0 and 1 that the logarithm's rounding cannot matter; elsewhere (and
        // for infinity) the logarithm decides, so the result is the same either way.
        let bits = texels_per_pixel.to_bits();
        let (e, f) = ((bits >> 23) as i64 - 127, bits & 0x7F_FFFF);
        const MARGIN: u32 = 1 << 13;
        if e < 128 && f > MARGIN && f < 0x7F_FFFF - MARGIN {
            return ((e + 1) / 2).min(last) as usize;
        }
        // log4 of the area ratio = log2 of the linear ratio; round to the nearest level.
        let lod = 0.5 * libm::log2f(texels_per_pixel);
        floor(lod + 0.5).clamp(0, last) as usize
    }

    fn from_level(level: Level) -> Texture {
        let mut levels = vec![level];
        loop {
            let last = &levels[levels.len() - 1];
            if last.width == 1 && last.height == 1 {
                break;
            }
            let next = downsample(last);
            levels.push(next);
        }
        Texture { levels, filter: Filter::default() }
    }
}

/// The bilinear blend of the texels of a square (top-left, top-right, bottom-left,
/// bottom-right) with weights `ax` towards the right and `ay` towards the bottom; one sample, or
/// eight in lanes, with the same operations.
#[inline]
fn blend<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>>([t00, t10, t01, t11]: [T; 4], ax: T, ay: T) -> T {
    let top = t00 + (t10 - t00) * ax;
    let bottom = t01 + (t11 - t01) * ax;
    top + (bottom - top) * ay
}

fn check(width: u32, height: u32, channels: u32, data: &[u8]) -> Result<&[u8], TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::Empty { width, height });
    }
    // Saturated where the size does not fit: no slice is that long, so it is refused as well.
    let expected = (width as usize).saturating_mul(height as usize).saturating_mul(channels as usize);
    if data.len() != expected {
        return Err(TextureError::WrongLength { width, height, channels, expected, got: data.len() });
    }
    Ok(data)
}

/// Half-size level: each texel is the rounded mean of (up to) a 2×2 block.
fn downsample(src: &Level) -> Level {
    let width = (src.width / 2).max(1);
    let height = (src.height / 2).max(1);
    let mut texels = Vec::with_capacity(width as usize * height as usize);
    for y in 0..height {
        for x in 0..width {
            let xs = [2 * x, (2 * x + 1).min(src.width - 1)];
            let ys = [2 * y, (2 * y + 1).min(src.height - 1)];
            let mut sum = [0u32; 4];
            for &yy in &ys {
                for &xx in &xs {
                    let t = src.texels[(yy * src.width + xx) as usize];
                    for c in 0..4 {
                        sum[c] += t[c] as u32;
                    }
                }
            }
            texels.push(sum.map(|s| ((s + 2) / 4) as u8));
        }
    }
    Level { width, height, texels }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        // 2×2: black, white / white, black.
        let d = [0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255];
        Texture::from_rgba8(2, 2, &d).unwrap()
    }

    #[test]
    fn rejects_wrong_sizes() {
        assert!(matches!(Texture::from_rgba8(2, 2, &[0; 15]), Err(TextureError::WrongLength { .. })));
        // A size whose byte count does not fit a `usize` (found by the look-cache fuzz target).
        assert!(matches!(Texture::from_rgba8(u32::MAX, u32::MAX, &[0; 4]), Err(TextureError::WrongLength { .. })));
        assert!(matches!(Texture::from_rgb8(0, 2, &[]), Err(TextureError::Empty { .. })));
    }

    #[test]
    fn nearest_picks_texels_with_top_row_at_v0() {
        let t = checker().with_filter(Filter::Nearest);
        assert_eq!(t.sample(Vec2::new(0.25, 0.25))[0], 0.0);
        assert_eq!(t.sample(Vec2::new(0.75, 0.25))[0], 1.0);
        assert_eq!(t.sample(Vec2::new(0.25, 0.75))[0], 1.0);
        // Repeat wrapping, including negative coordinates.
        assert_eq!(t.sample(Vec2::new(-0.75, 2.25))[0], 0.0);
    }

    #[test]
    fn bilinear_blends_between_texel_centres() {
        let t = checker();
        let mid = t.sample(Vec2::new(0.5, 0.25))[0];
        assert!((mid - 0.5).abs() < 1e-6);
        assert_eq!(t.sample(Vec2::new(0.25, 0.25))[0], 0.0);
    }

    #[test]
    fn eight_lanes_sample_what_one_point_at_a_time_samples() {
        // A 7×5 texture (its levels are 3×2 and 1×1), both filters, points inside and outside
        // the unit square (wrapping), on texel centres and edges, NaN, and groups within level 0.
        let data: Vec<u8> = (0..7 * 5 * 4).map(|i| ((i * 53 + 7) % 256) as u8).collect();
        let mut seed = 5u64;
        let mut points: Vec<f32> = vec![0.0, -0.0, 0.5 / 7.0, 1.0, -1.0, 0.9999, f32::NAN, 1e7, -3.25];
        points.extend((0..800).map(|_| (crate::raster::next_unit(&mut seed) - 0.4) * 3.0));
        // Then groups of eight whose squares all lie inside level 0 (the eight-wide path there).
        points.extend((0..800).map(|_| 0.15 + 0.7 * crate::raster::next_unit(&mut seed)));
        for filter in [Filter::Bilinear, Filter::Nearest] {
            let t = Texture::from_rgba8(7, 5, &data).unwrap().with_filter(filter);
            for level in 0..4 {
                for (n, group) in points.chunks_exact(2 * LANES).enumerate() {
                    let (u, v): (Vec<f32>, Vec<f32>) = group.chunks_exact(2).map(|p| (p[0], p[1 - n % 2])).unzip();
                    let (u, v) = (<[f32; LANES]>::try_from(u).unwrap(), <[f32; LANES]>::try_from(v).unwrap());
                    let lanes = t.sample_level_rgb8(f32x8::from(u), f32x8::from(v), level).map(|c| c.to_array());
                    for l in 0..LANES {
                        let one = t.sample_level(u[l], v[l], level);
                        for c in 0..3 {
                            assert_eq!(lanes[c][l].to_bits(), one[c].to_bits(), "{filter:?} level {level} ({}, {}) channel {c}", u[l], v[l]);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn mip_chain_averages_down_to_one_texel() {
        let t = checker();
        assert_eq!(t.level_count(), 2);
        assert_eq!(t.sample_level(0.3, 0.8, 1), [128.0 / 255.0, 128.0 / 255.0, 128.0 / 255.0, 1.0]);
        assert_eq!(t.level_for_density(0.5), 0);
        assert_eq!(t.level_for_density(4.0), 1);
        assert_eq!(t.level_for_density(1e9), 1);
    }

    #[test]
    fn mip_level_from_exponent_bits_equals_rounded_logarithm() {
        let big = Texture::from_rgba8(1 << 12, 1, &vec![0; 4 << 12]).unwrap();
        let by_log = |x: f32| (floor(0.5 * libm::log2f(x) + 0.5).clamp(0, big.level_count() as i64 - 1)) as usize;
        let mut x = 1.0f32;
        while x < 1e30 {
            for y in [x, f32::from_bits(x.to_bits() + 1), f32::from_bits(x.to_bits() - 1), x * 1.37, x * 1.9999] {
                if y > 1.0 {
                    assert_eq!(big.level_for_density(y), by_log(y), "{y}");
                }
            }
            x *= 2.0;
        }
        assert_eq!(big.level_for_density(f32::INFINITY), big.level_count() - 1);
    }
}
