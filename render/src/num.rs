//! Float → integer conversions that compile to plain instructions.
//!
//! x86_64's baseline (SSE2) has no rounding instruction, so `f32::floor` and `f64::round` become
//! library calls, which showed up in profiles of the per-pixel and per-vertex loops. These give
//! the same results for the finite, moderately sized values the renderer uses (NaN → 0, values
//! beyond the integer range saturate).

/// `⌊x⌋`.
#[inline]
pub(crate) fn floor(x: f32) -> i64 {
    let t = x as i64;
    if (t as f32) > x { t - 1 } else { t }
}

/// `x` rounded to the nearest integer, halves away from zero (like `f64::round`).
#[inline]
pub(crate) fn round(x: f64) -> i64 {
    (if x >= 0.0 { x + 0.5 } else { x - 0.5 }) as i64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_std() {
        for &x in &[-2.5f32, -1.0, -0.75, -0.0, 0.0, 0.25, 0.5, 1.0, 3.999, 1e6 + 0.5] {
            assert_eq!(floor(x), x.floor() as i64, "{x}");
        }
        for &x in &[-2.5f64, -1.49, -0.5, 0.0, 0.49, 0.5, 2.5, 123456.75] {
            assert_eq!(round(x), x.round() as i64, "{x}");
        }
        assert_eq!(floor(f32::NAN), 0);
    }
}
