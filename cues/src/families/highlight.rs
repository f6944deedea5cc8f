//! F7 visual highlight / lighting (scene-anchored): light cones, glows, dimming and washes
//! that sit on the anchored objects. Light is drawn as translucent layers with radial or
//! linear gradients, so the object under it stays visible.

use tiny_skia::{Color, FillRule, GradientStop, LinearGradient, Paint, Point, RadialGradient, SpreadMode, Transform};

use crate::draw::geom::{self, V2, v2};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::image::RgbImage;
use crate::insert::{Ctx, Placed, Which};

use crate::draw::geom::ID;

fn rgba(c: Rgba, alpha: u8) -> Color {
    Color::from_rgba8(c[0], c[1], c[2], alpha)
}

/// The highlight's radius: the anchor's, at least 10 px, and at most 36 px (at 256²) so that
/// an object filling the wrist camera gets a spot, not a frame-wide wash (and the pools stay
/// within the insertion budget).
fn radius(p: &Placed, s: f32) -> f32 {
    p.radius.clamp(10.0 * s, 36.0 * s)
}

pub fn spotlight_cone(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([255, 246, 200]);
    let s = ctx.scale();
    let Some(src) = ctx.place(Which::Source, color) else { return Ok(()) };
    let pm = ctx.layer();
    let r = radius(&src, s) * 1.5;
    let ry = r * 0.45;
    let top = v2(src.at.x, -4.0 * s);
    let half_top = 5.0 * s;
    if let (Some(path), Some(shader)) = (
        geom::polygon(&[
            v2(top.x - half_top, top.y),
            v2(top.x + half_top, top.y),
            v2(src.at.x + r, src.at.y),
            v2(src.at.x - r, src.at.y),
        ]),
        LinearGradient::new(
            Point::from_xy(top.x, top.y),
            Point::from_xy(src.at.x, src.at.y),
            vec![GradientStop::new(0.0, rgba(color, 40)), GradientStop::new(1.0, rgba(color, 120))],
            SpreadMode::Pad,
            ID,
        ),
    ) {
        draw::fill_shader(pm, &path, shader, ID);
    }
    if let Some(p) = geom::circle(top, 6.0 * s) {
        draw::fill(pm, &p, [255, 255, 240, 255], ID);
    }
    // The lit pool on the object: an ellipse (a scaled circle gradient).
    let squash = Transform::from_row(1.0, 0.0, 0.0, ry / r, 0.0, src.at.y * (1.0 - ry / r));
    let stops = vec![
        GradientStop::new(0.0, rgba(color, 150)),
        GradientStop::new(0.7, rgba(color, 110)),
        GradientStop::new(1.0, rgba(color, 0)),
    ];
    if let (Some(shader), Some(path)) = (
        RadialGradient::new(
            Point::from_xy(src.at.x, src.at.y),
            0.0,
            Point::from_xy(src.at.x, src.at.y),
            r * 1.15,
            stops,
            SpreadMode::Pad,
            ID,
        ),
        geom::circle(src.at, r * 1.15),
    ) {
        let paint = Paint { shader, anti_alias: true, ..Paint::default() };
        pm.fill_path(&path, &paint, FillRule::Winding, squash, None);
    }
    Ok(())
}

pub fn glow_halo(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([255, 228, 70]);
    let s = ctx.scale();
    let Some(src) = ctx.place(Which::Source, color) else { return Ok(()) };
    let r = radius(&src, s);
    draw::pool::radial_pool(ctx.layer(), src.at, r * 2.3, color, &[(0.0, 40), (0.38, 70), (0.5, 190), (0.62, 120), (1.0, 0)]);
    Ok(())
}

/// Darkens the frame outside soft circles on the source and target. Done per pixel on the
/// frame (smoothstep on squared distance, so no square roots), which is several times faster
/// than painting and punching a full-frame layer.
pub fn dim_surround(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let s = ctx.scale();
    let src = ctx.place(Which::Source, draw::WHITE);
    let tgt = ctx.place(Which::Target, draw::WHITE);
    let holes: Vec<(V2, f32)> = [src, tgt].into_iter().flatten().map(|p| (p.at, radius(&p, s) * 1.8)).collect();
    if !holes.is_empty() {
        dim_outside(ctx.frame_mut(), &holes);
    }
    Ok(())
}

/// Brightness kept outside every hole, out of 255.
const KEEP: u32 = 90;

/// Scales the frame by [`KEEP`]/255 outside the holes (centre, radius R); inside, by a
/// smoothstep of the squared distance from 0.65 R (no dimming) to R (full dimming). Per row, only
/// the columns of the holes' squares that the row crosses need the per-pixel test.
fn dim_outside(frame: &mut RgbImage, holes: &[(V2, f32)]) {
    let w = frame.width as usize;
    for (y, row) in frame.data.chunks_exact_mut(w * 3).enumerate() {
        let py = y as f32 + 0.5;
        let crossing = holes.iter().filter(|(c, r)| (py - c.y).abs() < *r);
        // Columns whose centres can lie within a square: |x + 0.5 − c.x| < r, widened by one.
        let (lo, hi) = crossing.fold((w, 0), |(lo, hi), (c, r)| {
            let first = (c.x - r - 1.5).floor().clamp(0.0, w as f32) as usize;
            let last = (c.x + r + 1.5).ceil().clamp(0.0, w as f32) as usize;
            (lo.min(first), hi.max(last))
        });
        if lo >= hi {
            dim(row, KEEP);
            continue;
        }
        let (left, rest) = row.split_at_mut(lo * 3);
        let (middle, right) = rest.split_at_mut((hi - lo) * 3);
        dim(left, KEEP);
        dim(right, KEEP);
        for (x, px) in (lo..hi).zip(middle.chunks_exact_mut(3)) {
            dim(px, keep_at(holes, x as f32 + 0.5, py));
        }
    }
}

/// Scales each byte by `keep`/255, rounded.
fn dim(bytes: &mut [u8], keep: u32) {
    for c in bytes {
        *c = ((*c as u32 * keep + 127) / 255) as u8;
    }
}

/// The brightness kept at pixel centre `(x, y)`, out of 255.
fn keep_at(holes: &[(V2, f32)], x: f32, y: f32) -> u32 {
    let mut m: f32 = 1.0;
    for (c, r) in holes {
        let (dx, dy) = (x - c.x, y - c.y);
        if dx.abs() < *r && dy.abs() < *r {
            let inner = 0.4225 * r * r;
            let t = ((dx * dx + dy * dy - inner) / (r * r - inner)).clamp(0.0, 1.0);
            m = m.min(t * t * (3.0 - 2.0 * t));
        }
    }
    if m >= 1.0 { KEEP } else { (255.0 - (255 - KEEP) as f32 * m + 0.5) as u32 }
}

pub fn color_wash(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([40, 255, 110]);
    let s = ctx.scale();
    let Some(goal) = ctx.place_goal(color) else { return Ok(()) };
    let r = radius(&goal, s) * 1.9;
    draw::pool::radial_pool(ctx.layer(), goal.at, r, color, &[(0.0, 120), (0.6, 100), (1.0, 0)]);
    Ok(())
}

pub fn rim_light(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let glow = ctx.color([110, 215, 255]);
    let s = ctx.scale();
    let Some(src) = ctx.place(Which::Source, glow) else { return Ok(()) };
    let pm = ctx.layer();
    let r = radius(&src, s) * 1.2;
    draw::round::ring(pm, src.at, r, 11.0 * s, [glow[0], glow[1], glow[2], 70]);
    draw::round::ring(pm, src.at, r, 5.0 * s, [glow[0], glow[1], glow[2], 140]);
    draw::round::ring(pm, src.at, r, 2.0 * s, [255, 255, 255, 235]);
    Ok(())
}

pub fn dual_spotlights(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let first = ctx.color([60, 230, 255]);
    let second: Rgba = [255, 70, 220, 255];
    let s = ctx.scale();
    let src = ctx.place(Which::Source, first);
    let tgt = ctx.place(Which::Target, second);
    for (p, c) in [(src, first), (tgt, second)] {
        if let Some(p) = p {
            let r = radius(&p, s) * 1.8;
            draw::pool::radial_pool(ctx.layer(), p.at, r, c, &[(0.0, 150), (0.55, 120), (1.0, 0)]);
        }
    }
    Ok(())
}

pub fn light_path(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([120, 200, 255]);
    let s = ctx.scale();
    let src = ctx.place(Which::Source, color);
    let tgt = ctx.place(Which::Target, color);
    let Some((a, b)) = src.zip(tgt) else { return Ok(()) };
    let pm = ctx.layer();
    let line = [a.at, b.at];
    draw::round::polyline(pm, &line, 16.0 * s, [color[0], color[1], color[2], 60]);
    draw::round::polyline(pm, &line, 7.0 * s, [color[0], color[1], color[2], 130]);
    draw::round::polyline(pm, &line, 2.2 * s, [255, 255, 255, 230]);
    for p in [a, b] {
        draw::pool::radial_pool(pm, p.at, radius(&p, s) * 1.4, color, &[(0.0, 130), (1.0, 0)]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dimming_row_by_row_gives_every_pixel_its_own_test() {
        let holes_of = [
            vec![(v2(70.3, 160.2), 28.8)],
            vec![(v2(70.3, 160.2), 28.8), (v2(185.0, 110.7), 64.8)],
            vec![(v2(-20.0, 5.0), 40.0), (v2(250.0, 251.5), 18.0)],
            vec![(v2(128.0, 128.0), 64.8), (v2(140.5, 120.25), 30.0)],
            vec![(v2(f32::NAN, 30.0), 20.0)],
        ];
        let base = RgbImage { width: 256, height: 256, data: (0..256 * 256 * 3).map(|i| (i * 31 % 256) as u8).collect() };
        let mut dimmed_everywhere = base.clone();
        dim(&mut dimmed_everywhere.data, KEEP);
        for holes in holes_of {
            let mut fast = base.clone();
            dim_outside(&mut fast, &holes);
            let mut slow = base.clone();
            for (k, px) in slow.data.chunks_exact_mut(3).enumerate() {
                dim(px, keep_at(&holes, (k % 256) as f32 + 0.5, (k / 256) as f32 + 0.5));
            }
            assert_eq!(fast.data, slow.data, "holes {holes:?}");
            // A hole with a NaN centre lights nothing; the others light something.
            let nan = holes[0].0.x.is_nan();
            assert_eq!(fast.data == dimmed_everywhere.data, nan, "holes {holes:?}");
        }
    }
}
