//! Drawing primitives shared by every cue family and the signage system.
//!
//! Everything is drawn with tiny-skia into premultiplied RGBA layers (`Pixmap`) and then
//! composited onto the caller's RGB frame by [`composite`]. Glyphs (hands, robots, objects,
//! pictograms) are paths in a unit box mapped to pixels by a `Transform`, so one definition
//! serves every size.

pub mod barcode;
pub mod fiducial;
pub mod geom;
pub mod pool;
pub mod qr;
pub mod round;
pub mod text;

use tiny_skia::{FillRule, Paint, Path, Pixmap, Shader, Stroke, StrokeDash, Transform};

use crate::image::{RgbImage, RgbaImage};

/// Straight-alpha RGBA colour.
pub type Rgba = [u8; 4];

/// Opaque colour from RGB.
pub const fn rgb(c: [u8; 3]) -> Rgba {
    [c[0], c[1], c[2], 255]
}

pub const WHITE: Rgba = [255, 255, 255, 255];
pub const BLACK: Rgba = [0, 0, 0, 255];

fn paint(color: Rgba) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(color[0], color[1], color[2], color[3]);
    paint.anti_alias = true;
    paint
}

/// Fills `path` (non-zero rule).
pub fn fill(pm: &mut Pixmap, path: &Path, color: Rgba, ts: Transform) {
    pm.fill_path(path, &paint(color), FillRule::Winding, ts, None);
}

/// Fills `path` with a shader (gradients).
pub fn fill_shader(pm: &mut Pixmap, path: &Path, shader: Shader<'_>, ts: Transform) {
    let paint = Paint { shader, anti_alias: true, ..Paint::default() };
    pm.fill_path(path, &paint, FillRule::Winding, ts, None);
}

/// Strokes `path` with round joins and caps; `width` is in path units.
pub fn stroke(pm: &mut Pixmap, path: &Path, color: Rgba, width: f32, ts: Transform) {
    let stroke = Stroke {
        width,
        line_cap: tiny_skia::LineCap::Round,
        line_join: tiny_skia::LineJoin::Round,
        ..Stroke::default()
    };
    pm.stroke_path(path, &paint(color), &stroke, ts, None);
}

/// Strokes `path` dashed (`on`, `off` lengths in path units).
pub fn stroke_dashed(pm: &mut Pixmap, path: &Path, color: Rgba, width: f32, on: f32, off: f32, ts: Transform) {
    let stroke = Stroke {
        width,
        line_cap: tiny_skia::LineCap::Round,
        line_join: tiny_skia::LineJoin::Round,
        dash: StrokeDash::new(vec![on, off], 0.0),
        ..Stroke::default()
    };
    pm.stroke_path(path, &paint(color), &stroke, ts, None);
}

/// Fills `path` and draws an outline around it (outline first, so the fill keeps its size
/// inside and the outline shows as a border outside).
pub fn fill_outlined(pm: &mut Pixmap, path: &Path, color: Rgba, outline: Rgba, outline_width: f32, ts: Transform) {
    stroke(pm, path, outline, outline_width * 2.0, ts);
    fill(pm, path, color, ts);
}

/// Blends a premultiplied layer onto an RGB frame with its top-left corner at (x, y), source
/// over. Integer arithmetic, so results are identical on every platform. Most of a cue's layer is
/// transparent: those pixels are skipped eight at a time.
pub fn composite(frame: &mut RgbImage, layer: &Pixmap, x: i32, y: i32) {
    let (fw, fh) = (frame.width as i32, frame.height as i32);
    let (lw, lh) = (layer.width() as i32, layer.height() as i32);
    let x0 = x.max(0);
    let y0 = y.max(0);
    let x1 = (x + lw).min(fw);
    let y1 = (y + lh).min(fh);
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let src = layer.data();
    let span = (x1 - x0) as usize;
    for fy in y0..y1 {
        let ly = (fy - y) as usize;
        let s0 = (ly * lw as usize + (x0 - x) as usize) * 4;
        let d0 = (fy as usize * fw as usize + x0 as usize) * 3;
        let src_row = &src[s0..s0 + span * 4];
        let dst_row = &mut frame.data[d0..d0 + span * 3];
        for (s8, d8) in src_row.chunks(4 * SKIP_PIXELS).zip(dst_row.chunks_mut(3 * SKIP_PIXELS)) {
            if is_clear(s8) {
                continue;
            }
            for (s, d) in s8.chunks_exact(4).zip(d8.chunks_exact_mut(3)) {
                let a = s[3] as u32;
                if a == 0 {
                    continue;
                }
                for c in 0..3 {
                    d[c] = (s[c] as u32 + mul255(d[c] as u32, 255 - a)).min(255) as u8;
                }
            }
        }
    }
}

/// Layer pixels [`composite`] tests for transparency at once.
const SKIP_PIXELS: usize = 8;

/// Whether every byte of `s` is zero (a transparent premultiplied pixel is), a word at a time.
fn is_clear(s: &[u8]) -> bool {
    let (words, rest) = s.as_chunks::<8>();
    words.iter().fold(0, |acc, w| acc | u64::from_ne_bytes(*w)) == 0 && rest.iter().all(|&b| b == 0)
}

/// Draws a premultiplied sprite onto a premultiplied layer at integer position (x, y),
/// source-over, in integer arithmetic. Cheaper than tiny-skia's general `draw_pixmap` (no
/// shader pipeline) for the unscaled, unrotated sprites cues place every frame.
pub fn blit_over(layer: &mut Pixmap, sprite: &Pixmap, x: i32, y: i32) {
    let (lw, lh) = (layer.width() as i32, layer.height() as i32);
    let (sw, sh) = (sprite.width() as i32, sprite.height() as i32);
    let (x0, y0, x1, y1) = (x.max(0), y.max(0), (x + sw).min(lw), (y + sh).min(lh));
    if x0 >= x1 || y0 >= y1 {
        return;
    }
    let span = (x1 - x0) as usize;
    let src = sprite.data();
    let dst = layer.data_mut();
    for ly in y0..y1 {
        let s0 = ((ly - y) as usize * sw as usize + (x0 - x) as usize) * 4;
        let d0 = (ly as usize * lw as usize + x0 as usize) * 4;
        for (s, d) in src[s0..s0 + span * 4].chunks_exact(4).zip(dst[d0..d0 + span * 4].chunks_exact_mut(4)) {
            match s[3] {
                0 => {}
                255 => d.copy_from_slice(s),
                _ => over(d, s),
            }
        }
    }
}

/// The pixels of RGBA bytes with their indices, leaving out the runs of eight whose bytes are
/// all zero (transparent): a ghost's frame-sized image is mostly such runs.
pub fn pixels_not_clear(rgba: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    rgba.chunks(4 * SKIP_PIXELS)
        .enumerate()
        .filter(|(_, run)| !is_clear(run))
        .flat_map(|(k, run)| run.chunks_exact(4).enumerate().map(move |(j, p)| (k * SKIP_PIXELS + j, p)))
}

/// Blends a straight-alpha image of the frame's size onto the frame with an extra opacity,
/// optionally pulling its colours towards `tint` by `tint_amount` (0–1). Integer arithmetic.
pub fn composite_rgba(frame: &mut RgbImage, img: &RgbaImage, opacity: f32, tint: Option<([u8; 3], f32)>) {
    let op = (opacity.clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
    let (tint_rgb, t) = tint.map_or(([0; 3], 0), |(c, k)| (c, (k.clamp(0.0, 1.0) * 255.0 + 0.5) as u32));
    for (i, s) in pixels_not_clear(&img.data) {
        let Some(d) = frame.data.get_mut(i * 3..i * 3 + 3) else { break };
        if s[3] == 0 {
            continue;
        }
        let a = mul255(s[3] as u32, op);
        for c in 0..3 {
            let src = mul255(s[c] as u32, 255 - t) + mul255(tint_rgb[c] as u32, t);
            d[c] = (mul255(src, a) + mul255(d[c] as u32, 255 - a)).min(255) as u8;
        }
    }
}

/// Source-over of the premultiplied RGBA pixel `s` onto the premultiplied `d`, in integers.
pub(crate) fn over(d: &mut [u8], s: &[u8]) {
    let ia = 255 - s[3] as u32;
    for c in 0..4 {
        d[c] = (s[c] as u32 + mul255(d[c] as u32, ia)).min(255) as u8;
    }
}

/// `a * b / 255`, rounded.
pub(crate) fn mul255(a: u32, b: u32) -> u32 {
    let t = a * b + 128;
    (t + (t >> 8)) >> 8
}

/// Converts a premultiplied layer to a straight-alpha [`RgbaImage`].
pub fn to_rgba_image(pm: &Pixmap) -> RgbaImage {
    let mut data = Vec::with_capacity(pm.data().len());
    for px in pm.data().chunks_exact(4) {
        let a = px[3] as u32;
        for &c in &px[..3] {
            data.push((c as u32 * 255 + a / 2).checked_div(a).unwrap_or(0).min(255) as u8);
        }
        data.push(px[3]);
    }
    RgbaImage { width: pm.width(), height: pm.height(), data }
}

/// Converts a straight-alpha [`RgbaImage`] to a premultiplied layer; `None` when the image
/// is malformed (wrong buffer length or zero size).
pub fn from_rgba_image(img: &RgbaImage) -> Option<Pixmap> {
    img.validate().ok()?;
    let mut pm = Pixmap::new(img.width, img.height)?;
    for (dst, src) in pm.data_mut().chunks_exact_mut(4).zip(img.data.chunks_exact(4)) {
        let a = src[3] as u32;
        for c in 0..3 {
            dst[c] = mul255(src[c] as u32, a) as u8;
        }
        dst[3] = src[3];
    }
    Some(pm)
}

/// An RGB frame as an opaque layer (used to draw pictures of frames into panels).
pub fn from_rgb_image(img: &RgbImage) -> Option<Pixmap> {
    img.validate().ok()?;
    let mut pm = Pixmap::new(img.width, img.height)?;
    for (dst, src) in pm.data_mut().chunks_exact_mut(4).zip(img.data.chunks_exact(3)) {
        dst[..3].copy_from_slice(src);
        dst[3] = 255;
    }
    Some(pm)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The blend as first written, one pixel at a time with a full opacity factor.
    fn composite_reference(frame: &mut RgbImage, layer: &Pixmap, x: i32, y: i32) {
        let (lw, lh) = (layer.width() as i32, layer.height() as i32);
        for ly in 0..lh {
            for lx in 0..lw {
                let (fx, fy) = (x + lx, y + ly);
                if fx < 0 || fy < 0 || fx >= frame.width as i32 || fy >= frame.height as i32 {
                    continue;
                }
                let s = &layer.data()[(ly * lw + lx) as usize * 4..][..4];
                if s[3] == 0 {
                    continue;
                }
                let d = &mut frame.data[(fy as usize * frame.width as usize + fx as usize) * 3..][..3];
                let a = mul255(s[3] as u32, 255);
                for c in 0..3 {
                    d[c] = (mul255(s[c] as u32, 255) + mul255(d[c] as u32, 255 - a)).min(255) as u8;
                }
            }
        }
    }

    #[test]
    fn composite_gives_the_per_pixel_blend_bit_for_bit() {
        let mut seed = 0x9e37_79b9_u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            seed >> 8
        };
        let mut changed = 0;
        // The last layer lies wholly left of the frame.
        for (w, h, x, y) in [(37, 21, 0, 0), (64, 9, -5, 3), (13, 40, 30, -7), (50, 50, 20, 20), (8, 8, -8, 0)] {
            let mut layer = Pixmap::new(w, h).unwrap();
            for px in layer.data_mut().chunks_exact_mut(4) {
                // Runs of transparency, some opaque and some partial pixels (premultiplied).
                let a = match next() % 4 {
                    0 | 1 => 0,
                    2 => 255,
                    _ => next() % 256,
                };
                for c in &mut px[..3] {
                    *c = (next() % (a + 1)) as u8;
                }
                px[3] = a as u8;
            }
            let base = RgbImage { width: 48, height: 32, data: (0..48 * 32 * 3).map(|_| next() as u8).collect() };
            let (mut fast, mut slow) = (base.clone(), base.clone());
            composite(&mut fast, &layer, x, y);
            composite_reference(&mut slow, &layer, x, y);
            assert_eq!(fast.data, slow.data, "{w}x{h} layer at ({x}, {y})");
            changed += fast.data.iter().zip(&base.data).filter(|(a, b)| a != b).count();
        }
        assert!(changed > 2000, "{changed} bytes of the frames changed");
    }

    /// `composite_rgba` as first written, every pixel visited.
    fn composite_rgba_reference(frame: &mut RgbImage, img: &RgbaImage, opacity: f32, tint: Option<([u8; 3], f32)>) {
        let op = (opacity.clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
        let (tint_rgb, t) = tint.map_or(([0; 3], 0), |(c, k)| (c, (k.clamp(0.0, 1.0) * 255.0 + 0.5) as u32));
        for (d, s) in frame.data.chunks_exact_mut(3).zip(img.data.chunks_exact(4)) {
            if s[3] == 0 {
                continue;
            }
            let a = mul255(s[3] as u32, op);
            for c in 0..3 {
                let src = mul255(s[c] as u32, 255 - t) + mul255(tint_rgb[c] as u32, t);
                d[c] = (mul255(src, a) + mul255(d[c] as u32, 255 - a)).min(255) as u8;
            }
        }
    }

    #[test]
    fn composite_rgba_skips_clear_runs_and_blends_the_rest_as_before() {
        let mut seed = 0x2545_f491_u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            seed >> 8
        };
        // A silhouette in a transparent image (odd width, so runs of eight cross rows), a few
        // transparent pixels with colour left in them, and frames of the image's size or smaller.
        let (w, h) = (37, 29);
        let mut img = RgbaImage::new(w, h).unwrap();
        for (i, px) in img.data.chunks_exact_mut(4).enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            if (8..20).contains(&x) && (5..17).contains(&y) {
                px.copy_from_slice(&[next() as u8, next() as u8, next() as u8, [255, 0, 128][next() as usize % 3]]);
            } else if next() % 50 == 0 {
                px.copy_from_slice(&[next() as u8, next() as u8, next() as u8, 0]);
            }
        }
        for (fw, fh, opacity, tint) in [(w, h, 0.45, None), (w, h, 1.0, Some(([40, 200, 90], 0.35))), (w, 20, 0.7, None)] {
            let base = RgbImage { width: fw, height: fh, data: (0..fw * fh * 3).map(|_| next() as u8).collect() };
            let (mut fast, mut slow) = (base.clone(), base.clone());
            composite_rgba(&mut fast, &img, opacity, tint);
            composite_rgba_reference(&mut slow, &img, opacity, tint);
            assert_eq!(fast.data, slow.data, "{fw}x{fh} opacity {opacity} tint {tint:?}");
            assert!(fast.data != base.data);
        }
        // Every pixel outside the all-zero runs is listed once, in order, with its own bytes.
        let listed: Vec<usize> = pixels_not_clear(&img.data).map(|(i, p)| {
            assert_eq!(p, &img.data[i * 4..i * 4 + 4]);
            i
        }).collect();
        assert!(listed.windows(2).all(|p| p[0] < p[1]));
        for (i, px) in img.data.chunks_exact(4).enumerate() {
            assert!(px == [0; 4] || listed.contains(&i), "pixel {i} left out");
        }
        assert!(listed.len() < img.data.len() / 4 / 2, "{} of {} listed", listed.len(), img.data.len() / 4);
    }
}
