//! RGBA8 textures with repeat wrapping, nearest or bilinear filtering, and a mip chain.
//!
//! Texture coordinates follow MuJoCo's use of image rows: `v = 0` is the first (top) row of the
//! image, `u = 0` its left column; texel centres sit at `(i + 0.5) / width`.

use glam::Vec2;
use thiserror::Error;

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
        let lv = &self.levels[level.min(self.levels.len() - 1)];
        let (w, h) = (lv.width as i64, lv.height as i64);
        let fetch = |x: i64, y: i64| lv.texels[(y.rem_euclid(h) * w + x.rem_euclid(w)) as usize];
        let x = u * lv.width as f32 - 0.5;
        let y = v * lv.height as f32 - 0.5;
        const S: f32 = 1.0 / 255.0;
        match self.filter {
            Filter::Nearest => {
                let t = fetch(floor(x + 0.5), floor(y + 0.5));
                t.map(|c| c as f32 * S)
            }
            Filter::Bilinear => {
                let (x0, y0) = (floor(x), floor(y));
                let (ax, ay) = (x - x0 as f32, y - y0 as f32);
                // Inside the level (the common case) no wrapping is needed: skip the divisions.
                let (t00, t10, t01, t11) = if x0 >= 0 && y0 >= 0 && x0 + 1 < w && y0 + 1 < h {
                    let i = (y0 * w + x0) as usize;
                    let s = lv.width as usize;
                    (lv.texels[i], lv.texels[i + 1], lv.texels[i + s], lv.texels[i + s + 1])
                } else {
                    (fetch(x0, y0), fetch(x0 + 1, y0), fetch(x0, y0 + 1), fetch(x0 + 1, y0 + 1))
                };
                let mut out = [0.0; 4];
                for (c, o) in out.iter_mut().enumerate() {
                    let top = t00[c] as f32 + (t10[c] as f32 - t00[c] as f32) * ax;
                    let bottom = t01[c] as f32 + (t11[c] as f32 - t01[c] as f32) * ax;
                    *o = (top + (bottom - top) * ay) * S;
                }
                out
            }
        }
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

fn check(width: u32, height: u32, channels: u32, data: &[u8]) -> Result<&[u8], TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::Empty { width, height });
    }
    let expected = width as usize * height as usize * channels as usize;
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
