//! The images an openpi LIBERO client sends, made from our upright observation frames.
//!
//! robosuite returns frames bottom-up (OpenGL convention: `raw[r] = upright[H-1-r]`), and
//! openpi's LIBERO client sends `raw[::-1, ::-1]`, which is `upright[r][W-1-c]`: the upright
//! frame **mirrored left–right**, not rotated. It then calls `image_tools.resize_with_pad`
//! (PIL `BILINEAR`, zero padding to keep the aspect ratio). [`openpi_image`] reproduces both
//! steps byte for byte; PIL's resampler is re-implemented below with its fixed-point
//! arithmetic so the bytes match Pillow, not merely look alike.

use vifo_cues::RgbImage;

/// openpi's LIBERO image from an upright frame: mirrored left–right, then
/// [`resize_with_pad`] to `size` × `size`.
pub fn openpi_image(upright: &RgbImage, size: u32) -> RgbImage {
    resize_with_pad(&mirror_left_right(upright), size, size)
}

/// `upright[r][W-1-c]`: what `raw[::-1, ::-1]` of a bottom-up robosuite frame is.
pub fn mirror_left_right(img: &RgbImage) -> RgbImage {
    let mut mirrored = img.clone();
    mirrored.mirror_left_right();
    mirrored
}

/// openpi's `image_tools.resize_with_pad`: scale by the larger of the two ratios with PIL's
/// bilinear filter, then centre on a black `width` × `height` canvas. Same size: unchanged.
pub fn resize_with_pad(img: &RgbImage, height: u32, width: u32) -> RgbImage {
    if img.width == width && img.height == height {
        return img.clone();
    }
    let ratio = f64::max(img.width as f64 / width as f64, img.height as f64 / height as f64);
    // Python's int() truncates; a side never drops to zero here (PIL would raise).
    let rh = ((img.height as f64 / ratio) as u32).clamp(1, height);
    let rw = ((img.width as f64 / ratio) as u32).clamp(1, width);
    let resized = pil_resize_bilinear(img, rw, rh);
    let pad_h = ((height - rh) / 2) as usize;
    let pad_w = ((width - rw) / 2) as usize;
    let mut data = vec![0u8; width as usize * height as usize * 3];
    let row_bytes = rw as usize * 3;
    for (y, src) in resized.data.chunks_exact(row_bytes).enumerate() {
        let start = ((y + pad_h) * width as usize + pad_w) * 3;
        data[start..start + row_bytes].copy_from_slice(src);
    }
    RgbImage { width, height, data }
}

/// Pillow's `PRECISION_BITS` (`Resample.c`): weights are integers scaled by 2^22.
const PRECISION_BITS: u32 = 32 - 8 - 2;

/// Per output pixel: first input index and the integer weights of the taps.
struct Taps {
    first: Vec<usize>,
    weights: Vec<Vec<i32>>,
}

/// Pillow's `precompute_coeffs` + `normalize_coeffs_8bpc` for the bilinear (triangle) filter
/// over the whole input: the filter widens with the scale when shrinking (antialiasing).
fn taps(in_size: u32, out_size: u32) -> Taps {
    let scale = in_size as f64 / out_size as f64;
    let filter_scale = scale.max(1.0);
    let support = filter_scale; // bilinear support 1.0, times the filter scale
    let inv = 1.0 / filter_scale;
    let mut first = Vec::with_capacity(out_size as usize);
    let mut weights = Vec::with_capacity(out_size as usize);
    for xx in 0..out_size {
        let center = (xx as f64 + 0.5) * scale;
        // C's (int) cast truncates towards zero; both values are >= -0.5 + 0.5 here.
        let xmin = ((center - support + 0.5) as i64).max(0) as usize;
        let xmax = ((center + support + 0.5) as i64).min(in_size as i64) as usize;
        let raw: Vec<f64> = (xmin..xmax)
            .map(|x| {
                let t = ((x as f64 - center + 0.5) * inv).abs();
                if t < 1.0 { 1.0 - t } else { 0.0 }
            })
            .collect();
        let total: f64 = raw.iter().sum();
        let fixed = raw
            .iter()
            .map(|&w| {
                let w = if total != 0.0 { w / total } else { w };
                // Bilinear weights are never negative: (int)(0.5 + w * 2^22).
                (0.5 + w * f64::from(1u32 << PRECISION_BITS)) as i32
            })
            .collect();
        first.push(xmin);
        weights.push(fixed);
    }
    Taps { first, weights }
}

/// Pillow's `clip8`: round-half-up already added, shift out the fraction, saturate.
fn clip8(acc: i32) -> u8 {
    if acc >= (1 << PRECISION_BITS << 8) {
        255
    } else if acc <= 0 {
        0
    } else {
        (acc >> PRECISION_BITS) as u8
    }
}

/// `Image.resize((w, h), Image.BILINEAR)` of an RGB image: horizontal pass, then vertical,
/// each rounding to 8 bits, as Pillow does.
pub fn pil_resize_bilinear(img: &RgbImage, out_w: u32, out_h: u32) -> RgbImage {
    let (in_w, in_h) = (img.width as usize, img.height as usize);
    let mut current = img.data.clone();
    let mut width = in_w;
    if out_w as usize != in_w {
        let t = taps(img.width, out_w);
        let ow = out_w as usize;
        let mut out = vec![0u8; ow * in_h * 3];
        for (row, out_row) in current.chunks_exact(in_w * 3).zip(out.chunks_exact_mut(ow * 3)) {
            for ((first, ws), px) in t.first.iter().zip(&t.weights).zip(out_row.chunks_exact_mut(3)) {
                let mut acc = [1i32 << (PRECISION_BITS - 1); 3];
                for (src, w) in row[first * 3..].chunks_exact(3).zip(ws) {
                    for c in 0..3 {
                        acc[c] += i32::from(src[c]) * w;
                    }
                }
                for c in 0..3 {
                    px[c] = clip8(acc[c]);
                }
            }
        }
        current = out;
        width = ow;
    }
    if out_h as usize != in_h {
        let t = taps(img.height, out_h);
        let row_len = width * 3;
        let mut out = vec![0u8; row_len * out_h as usize];
        let mut acc = vec![0i32; row_len];
        for ((first, ws), out_row) in t.first.iter().zip(&t.weights).zip(out.chunks_exact_mut(row_len)) {
            acc.fill(1 << (PRECISION_BITS - 1));
            for (k, w) in ws.iter().enumerate() {
                let src = &current[(first + k) * row_len..(first + k + 1) * row_len];
                for (a, &v) in acc.iter_mut().zip(src) {
                    *a += i32::from(v) * w;
                }
            }
            for (o, &a) in out_row.iter_mut().zip(&acc) {
                *o = clip8(a);
            }
        }
        current = out;
    }
    RgbImage { width: out_w, height: out_h, data: current }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern(w: u32, h: u32) -> RgbImage {
        let data = (0..w * h)
            .flat_map(|i| {
                let (x, y) = (i % w, i / w);
                [(x * 7 + y * 3) as u8, (x ^ y) as u8, (x * y / 5) as u8]
            })
            .collect();
        RgbImage { width: w, height: h, data }
    }

    #[test]
    fn openpi_orientation_is_a_left_right_mirror_of_the_upright_frame() {
        let upright = pattern(5, 3);
        // robosuite's raw frame is the upright one with its rows reversed ...
        let raw: Vec<&[u8]> = upright.data.chunks(15).rev().collect();
        // ... and openpi reverses rows and columns of that.
        let mut expected = Vec::new();
        for row in raw.iter().rev() {
            for px in row.chunks(3).rev() {
                expected.extend_from_slice(px);
            }
        }
        assert_eq!(mirror_left_right(&upright).data, expected);
        assert_eq!(mirror_left_right(&upright).pixel(0, 0), upright.pixel(4, 0));
        assert_eq!(mirror_left_right(&mirror_left_right(&upright)), upright);
    }

    #[test]
    fn resizing_keeps_flat_colours_and_the_size() {
        let flat = RgbImage::filled(256, 256, [12, 200, 255]).unwrap();
        let out = openpi_image(&flat, 224);
        assert_eq!((out.width, out.height), (224, 224));
        assert!(out.data.chunks(3).all(|p| p == [12, 200, 255]));
        // Same size: untouched (openpi returns the input as is).
        let p = pattern(224, 224);
        assert_eq!(resize_with_pad(&p, 224, 224), p);
    }

    #[test]
    fn a_wide_frame_is_padded_top_and_bottom() {
        let wide = RgbImage::filled(320, 160, [255, 255, 255]).unwrap();
        let out = resize_with_pad(&wide, 224, 224);
        // 320x160 -> 224x112, centred: rows 56..168 white, the rest black.
        assert_eq!(out.pixel(100, 55), Some([0, 0, 0]));
        assert_eq!(out.pixel(100, 56), Some([255, 255, 255]));
        assert_eq!(out.pixel(100, 167), Some([255, 255, 255]));
        assert_eq!(out.pixel(100, 168), Some([0, 0, 0]));
    }

    #[test]
    fn weights_sum_to_one_in_fixed_point() {
        for (i, o) in [(256, 224), (128, 224), (640, 224), (7, 3)] {
            let t = taps(i, o);
            for ws in &t.weights {
                let s: i32 = ws.iter().sum();
                assert!((s - (1 << PRECISION_BITS)).abs() <= ws.len() as i32, "{i}->{o}: {s}");
            }
        }
    }
}
