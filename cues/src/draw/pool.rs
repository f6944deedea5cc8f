//! Soft radial pools of light, drawn by hand.
//!
//! F7's spotlights, halos and washes are discs whose opacity falls off with the distance from
//! their centre. On the wrist camera a close object gets pools of 65–85 px radius, redrawn every
//! frame; tiny-skia's gradient pipeline spent about 20 ns on each of their pixels, which put
//! those cues over the insertion budget. Here the falloff is tabulated once per pool over the
//! squared distance, so a pixel costs a multiply, a table read and the blend.

use tiny_skia::Pixmap;

use super::geom::V2;
use super::{Rgba, mul255, over};

/// Entries of the falloff table over `(distance / r)²` in [0, 1).
const TABLE: usize = 1024;

/// Draws a disc of radius `r` around `at`, source-over onto the premultiplied layer `pm`:
/// colour `color` at the opacity given by `stops` (fraction of `r`, alpha), linear between stops
/// and constant beyond the first and last. Pixels are sampled at their centres, as tiny-skia
/// does; the disc ends at `r`, so its rim is sharp unless the last stop's alpha is 0.
/// A non-finite or non-positive centre or radius draws nothing.
pub fn radial_pool(pm: &mut Pixmap, at: V2, r: f32, color: Rgba, stops: &[(f32, u8)]) {
    if !(at.x.is_finite() && at.y.is_finite() && r.is_finite() && r > 0.0) || stops.is_empty() {
        return;
    }
    let table = falloff(color, stops);
    let (w, h) = (pm.width() as i32, pm.height() as i32);
    let span = |c: f32, n: i32| (((c - r).floor() as i32).clamp(0, n), ((c + r).ceil() as i32).clamp(0, n));
    let ((x0, x1), (y0, y1)) = (span(at.x, w), span(at.y, h));
    let inv_r2 = 1.0 / (r * r);
    let data = pm.data_mut();
    for y in y0..y1 {
        let dy = y as f32 + 0.5 - at.y;
        let dy2 = dy * dy * inv_r2;
        if dy2 >= 1.0 {
            continue;
        }
        let row = &mut data[(y * w + x0) as usize * 4..(y * w + x1) as usize * 4];
        for (x, d) in (x0..x1).zip(row.as_chunks_mut::<4>().0) {
            let dx = x as f32 + 0.5 - at.x;
            let q = dx * dx * inv_r2 + dy2;
            if q >= 1.0 {
                continue;
            }
            let s = table[((q * TABLE as f32) as usize).min(TABLE - 1)];
            if *d == [0; 4] {
                // Over a transparent pixel (most of a pool) source-over gives the source.
                *d = s;
                continue;
            }
            over(d, &s);
        }
    }
}

/// The premultiplied colour at the middle of each table entry's range of `(distance / r)²`.
fn falloff(color: Rgba, stops: &[(f32, u8)]) -> [[u8; 4]; TABLE] {
    let mut table = [[0; 4]; TABLE];
    for (k, e) in table.iter_mut().enumerate() {
        let t = libm::sqrtf((k as f32 + 0.5) / TABLE as f32);
        let a = (alpha_at(stops, t) + 0.5) as u32;
        *e = [mul255(color[0] as u32, a) as u8, mul255(color[1] as u32, a) as u8, mul255(color[2] as u32, a) as u8, a as u8];
    }
    table
}

/// The stops' opacity at `t`, linear between them (`stops` ordered by `t`, not empty).
fn alpha_at(stops: &[(f32, u8)], t: f32) -> f32 {
    let after = stops.iter().position(|&(st, _)| st > t).unwrap_or(stops.len());
    match (after.checked_sub(1).map(|i| stops[i]), stops.get(after)) {
        (Some((t0, a0)), Some(&(t1, a1))) => a0 as f32 + (a1 as f32 - a0 as f32) * (t - t0) / (t1 - t0),
        (Some((_, a)), None) | (None, Some(&(_, a))) => a as f32,
        (None, None) => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::draw::geom::v2;

    fn pixel(pm: &Pixmap, x: u32, y: u32) -> [u8; 4] {
        pm.data()[((y * pm.width() + x) * 4) as usize..][..4].try_into().unwrap()
    }

    #[test]
    fn alpha_follows_the_stops() {
        let stops = [(0.0, 40), (0.5, 190), (1.0, 0)];
        assert_eq!(alpha_at(&stops, 0.0), 40.0);
        assert_eq!(alpha_at(&stops, 0.25), 115.0);
        assert_eq!(alpha_at(&stops, 0.5), 190.0);
        assert_eq!(alpha_at(&stops, 0.75), 95.0);
        assert_eq!(alpha_at(&stops, 2.0), 0.0);
        assert_eq!(alpha_at(&[(0.2, 7)], 0.0), 7.0);
    }

    #[test]
    fn a_pool_is_round_falls_off_and_blends_over_what_is_there() {
        let mut pm = Pixmap::new(64, 48).unwrap();
        let color = [255, 70, 220, 255];
        radial_pool(&mut pm, v2(30.0, 20.0), 15.0, color, &[(0.0, 150), (0.55, 120), (1.0, 0)]);
        // The centre pixels hold about the first stop's alpha, premultiplied.
        let c = pixel(&pm, 29, 19);
        assert!((146..=150).contains(&c[3]), "{c:?}");
        assert_eq!(c[0] as u32, mul255(255, c[3] as u32));
        // Opacity falls with the distance and is the same at equal distances.
        let along: Vec<u8> = (29..44).map(|x| pixel(&pm, x, 19)[3]).collect();
        assert!(along.windows(2).all(|p| p[0] >= p[1]), "{along:?}");
        assert_eq!(pixel(&pm, 29 + 8, 19), pixel(&pm, 29, 19 + 8));
        assert_eq!(pixel(&pm, 29 - 7, 19), pixel(&pm, 30 + 7, 19));
        // Nothing beyond the radius.
        assert_eq!(pixel(&pm, 30 + 16, 19), [0; 4]);
        assert_eq!(pixel(&pm, 5, 5), [0; 4]);
        // A second pool over the first adds to it, source-over.
        let before = pixel(&pm, 29, 19);
        radial_pool(&mut pm, v2(30.0, 20.0), 15.0, [60, 230, 255, 255], &[(0.0, 100), (1.0, 0)]);
        let after = pixel(&pm, 29, 19);
        assert!(after[3] > before[3] && after[1] > before[1], "{before:?} -> {after:?}");
    }

    #[test]
    fn pools_off_the_layer_or_with_bad_numbers_draw_nothing() {
        let stops = [(0.0, 150), (1.0, 0)];
        for (at, r) in [
            (v2(-40.0, 10.0), 20.0),
            (v2(10.0, 500.0), 20.0),
            (v2(f32::NAN, 10.0), 20.0),
            (v2(10.0, 10.0), f32::INFINITY),
            (v2(10.0, 10.0), -3.0),
            (v2(10.0, 10.0), 0.0),
        ] {
            let mut pm = Pixmap::new(32, 32).unwrap();
            radial_pool(&mut pm, at, r, [255; 4], &stops);
            assert!(pm.data().iter().all(|&b| b == 0), "{at:?} r {r}");
        }
        // A pool much larger than the layer covers it all.
        let mut pm = Pixmap::new(32, 32).unwrap();
        radial_pool(&mut pm, v2(16.0, 16.0), 1e6, [255; 4], &stops);
        assert!(pm.data().chunks_exact(4).all(|p| p[3] >= 145), "huge pool");
    }
}
