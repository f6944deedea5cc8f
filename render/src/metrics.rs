//! Image similarity: PSNR and SSIM between two RGB images of equal size.
//!
//! SSIM follows Wang et al. (2004) exactly: an 11×11 Gaussian window with σ = 1.5,
//! `K1 = 0.01`, `K2 = 0.03`, dynamic range 255, computed on **luminance**
//! (`Y = 0.299 R + 0.587 G + 0.114 B`, BT.601) and averaged over the positions where the window
//! lies fully inside the image ("valid" filtering, as the reference MATLAB code does).

use thiserror::Error;

use crate::frame::RgbImage;

/// Why a metric could not be computed.
#[derive(Debug, Error, PartialEq)]
pub enum MetricError {
    #[error("images differ in size: {0}×{1} vs {2}×{3}")]
    SizeMismatch(u32, u32, u32, u32),
    #[error("image {0}×{1} holds {2} bytes, expected {3}")]
    BadData(u32, u32, usize, usize),
    #[error("SSIM needs images of at least 11×11 pixels, got {0}×{1}")]
    TooSmall(u32, u32),
}

fn check_pair(a: &RgbImage, b: &RgbImage) -> Result<(), MetricError> {
    for img in [a, b] {
        let expected = img.width as usize * img.height as usize * 3;
        if img.data.len() != expected {
            return Err(MetricError::BadData(img.width, img.height, img.data.len(), expected));
        }
    }
    if (a.width, a.height) != (b.width, b.height) {
        return Err(MetricError::SizeMismatch(a.width, a.height, b.width, b.height));
    }
    Ok(())
}

/// Peak signal-to-noise ratio in dB over all three channels (peak 255); infinite for identical
/// images.
pub fn psnr(a: &RgbImage, b: &RgbImage) -> Result<f64, MetricError> {
    check_pair(a, b)?;
    if a.data.is_empty() {
        return Ok(f64::INFINITY);
    }
    let sse: f64 = a.data.iter().zip(&b.data).map(|(&x, &y)| (x as f64 - y as f64).powi(2)).sum();
    let mse = sse / a.data.len() as f64;
    Ok(if mse == 0.0 { f64::INFINITY } else { 10.0 * libm::log10(255.0 * 255.0 / mse) })
}

const WINDOW: usize = 11;
const SIGMA: f64 = 1.5;

/// Mean structural similarity of the luminance channels, in `[-1, 1]` (1 = identical).
pub fn ssim(a: &RgbImage, b: &RgbImage) -> Result<f64, MetricError> {
    check_pair(a, b)?;
    let (w, h) = (a.width as usize, a.height as usize);
    if w < WINDOW || h < WINDOW {
        return Err(MetricError::TooSmall(a.width, a.height));
    }
    let (x, y) = (luminance(a), luminance(b));
    let xx: Vec<f64> = x.iter().map(|v| v * v).collect();
    let yy: Vec<f64> = y.iter().map(|v| v * v).collect();
    let xy: Vec<f64> = x.iter().zip(&y).map(|(p, q)| p * q).collect();
    let kernel = gaussian();
    let f = |img: &[f64]| filter_valid(img, w, h, &kernel);
    let (mx, my, sxx, syy, sxy) = (f(&x), f(&y), f(&xx), f(&yy), f(&xy));
    let c1 = (0.01 * 255.0f64).powi(2);
    let c2 = (0.03 * 255.0f64).powi(2);
    let n = mx.len();
    let total: f64 = (0..n)
        .map(|i| {
            let (ux, uy) = (mx[i], my[i]);
            let vx = sxx[i] - ux * ux;
            let vy = syy[i] - uy * uy;
            let cov = sxy[i] - ux * uy;
            ((2.0 * ux * uy + c1) * (2.0 * cov + c2)) / ((ux * ux + uy * uy + c1) * (vx + vy + c2))
        })
        .sum();
    Ok(total / n as f64)
}

fn luminance(img: &RgbImage) -> Vec<f64> {
    img.data.chunks_exact(3).map(|p| 0.299 * p[0] as f64 + 0.587 * p[1] as f64 + 0.114 * p[2] as f64).collect()
}

/// Normalised 1-D Gaussian; the 2-D window is its outer product.
fn gaussian() -> [f64; WINDOW] {
    let mut k = [0.0; WINDOW];
    let c = (WINDOW / 2) as f64;
    for (i, v) in k.iter_mut().enumerate() {
        let d = i as f64 - c;
        *v = libm::exp(-d * d / (2.0 * SIGMA * SIGMA));
    }
    let s: f64 = k.iter().sum();
    k.map(|v| v / s)
}

/// Separable "valid" filtering: output is `(w − 10) × (h − 10)`.
fn filter_valid(img: &[f64], w: usize, h: usize, k: &[f64; WINDOW]) -> Vec<f64> {
    let ow = w - WINDOW + 1;
    let oh = h - WINDOW + 1;
    let mut horiz = vec![0.0; ow * h];
    for y in 0..h {
        for x in 0..ow {
            horiz[y * ow + x] = (0..WINDOW).map(|t| k[t] * img[y * w + x + t]).sum();
        }
    }
    let mut out = vec![0.0; ow * oh];
    for y in 0..oh {
        for x in 0..ow {
            out[y * ow + x] = (0..WINDOW).map(|t| k[t] * horiz[(y + t) * ow + x]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(w: u32, h: u32, seed: u32) -> RgbImage {
        let mut s = seed;
        let data = (0..w * h * 3)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 24) as u8
            })
            .collect();
        RgbImage { width: w, height: h, data }
    }

    #[test]
    fn identical_images_are_perfect() {
        let a = noise(32, 24, 1);
        assert_eq!(psnr(&a, &a).unwrap(), f64::INFINITY);
        assert!((ssim(&a, &a).unwrap() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn psnr_of_constant_offset() {
        let a = RgbImage::filled(8, 8, [100, 100, 100]);
        let b = RgbImage::filled(8, 8, [110, 110, 110]);
        // MSE = 100 → 10 log10(65025 / 100) = 28.131 dB.
        assert!((psnr(&a, &b).unwrap() - 28.1308).abs() < 1e-3);
    }

    #[test]
    fn ssim_orders_degradations() {
        let a = noise(40, 40, 7);
        let mut slight = a.clone();
        for v in slight.data.iter_mut().step_by(7) {
            *v = v.saturating_add(20);
        }
        let other = noise(40, 40, 99);
        let s1 = ssim(&a, &slight).unwrap();
        let s2 = ssim(&a, &other).unwrap();
        assert!(s1 < 1.0 && s1 > 0.8, "{s1}");
        assert!(s2 < 0.2, "{s2}");
    }

    #[test]
    fn ssim_of_constant_images_follows_luminance_term() {
        // Flat images: SSIM = (2 μx μy + C1) / (μx² + μy² + C1).
        let a = RgbImage::filled(12, 12, [100, 100, 100]);
        let b = RgbImage::filled(12, 12, [120, 120, 120]);
        let c1 = 6.5025;
        let expect = (2.0 * 100.0 * 120.0 + c1) / (100.0f64.powi(2) + 120.0f64.powi(2) + c1);
        assert!((ssim(&a, &b).unwrap() - expect).abs() < 1e-9);
    }

    #[test]
    fn errors_for_mismatched_or_tiny_images() {
        let a = noise(12, 12, 1);
        assert!(matches!(psnr(&a, &noise(12, 13, 1)), Err(MetricError::SizeMismatch(..))));
        assert_eq!(ssim(&noise(10, 30, 1), &noise(10, 30, 2)), Err(MetricError::TooSmall(10, 30)));
    }
}
