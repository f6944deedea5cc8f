//! F7 visual highlight / lighting (scene-anchored): light cones, glows, dimming and washes
//! that sit on the anchored objects. Light is drawn as translucent layers with radial or
//! linear gradients, so the object under it stays visible.

use tiny_skia::{BlendMode, Color, FillRule, GradientStop, LinearGradient, Paint, Point, RadialGradient, SpreadMode, Transform};

use crate::draw::geom::{self, V2, v2};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::insert::{Ctx, Placed, Which};

use crate::draw::geom::ID;

fn rgba(c: Rgba, alpha: u8) -> Color {
    Color::from_rgba8(c[0], c[1], c[2], alpha)
}

/// A soft radial pool of light: `alphas` at fractions `stops` of radius `r`.
fn pool(pm: &mut tiny_skia::Pixmap, at: V2, r: f32, color: Rgba, stops: &[(f32, u8)]) {
    let stops: Vec<GradientStop> = stops.iter().map(|&(t, a)| GradientStop::new(t, rgba(color, a))).collect();
    if let (Some(shader), Some(path)) = (
        RadialGradient::new(Point::from_xy(at.x, at.y), 0.0, Point::from_xy(at.x, at.y), r, stops, SpreadMode::Pad, ID),
        geom::circle(at, r),
    ) {
        draw::fill_shader(pm, &path, shader, ID);
    }
}

fn radius(p: &Placed, s: f32) -> f32 {
    p.radius.max(10.0 * s)
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
        geom::polygon(&[v2(top.x - half_top, top.y), v2(top.x + half_top, top.y), v2(src.at.x + r, src.at.y), v2(src.at.x - r, src.at.y)]),
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
    let stops = vec![GradientStop::new(0.0, rgba(color, 150)), GradientStop::new(0.7, rgba(color, 110)), GradientStop::new(1.0, rgba(color, 0))];
    if let (Some(shader), Some(path)) = (
        RadialGradient::new(Point::from_xy(src.at.x, src.at.y), 0.0, Point::from_xy(src.at.x, src.at.y), r * 1.15, stops, SpreadMode::Pad, ID),
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
    pool(ctx.layer(), src.at, r * 2.3, color, &[(0.0, 40), (0.38, 70), (0.5, 190), (0.62, 120), (1.0, 0)]);
    Ok(())
}

pub fn dim_surround(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let s = ctx.scale();
    let src = ctx.place(Which::Source, draw::WHITE);
    let tgt = if ctx.spec.target.is_some() { ctx.place(Which::Target, draw::WHITE) } else { None };
    if src.is_none() && tgt.is_none() {
        return Ok(());
    }
    let (w, h) = ctx.size();
    let pm = ctx.layer();
    if let Some(p) = geom::rect(0.0, 0.0, w as f32, h as f32) {
        draw::fill(pm, &p, [0, 0, 0, 165], ID);
    }
    // Cut soft holes with destination-out.
    for p in [src, tgt].into_iter().flatten() {
        let r = radius(&p, s) * 1.8;
        let stops = vec![GradientStop::new(0.0, Color::BLACK), GradientStop::new(0.65, Color::BLACK), GradientStop::new(1.0, Color::TRANSPARENT)];
        if let (Some(shader), Some(path)) = (
            RadialGradient::new(Point::from_xy(p.at.x, p.at.y), 0.0, Point::from_xy(p.at.x, p.at.y), r, stops, SpreadMode::Pad, ID),
            geom::circle(p.at, r),
        ) {
            let paint = Paint { shader, anti_alias: true, blend_mode: BlendMode::DestinationOut, ..Paint::default() };
            pm.fill_path(&path, &paint, FillRule::Winding, ID, None);
        }
    }
    Ok(())
}

pub fn color_wash(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([40, 255, 110]);
    let s = ctx.scale();
    let Some(goal) = ctx.place_goal(color) else { return Ok(()) };
    let r = radius(&goal, s) * 1.9;
    pool(ctx.layer(), goal.at, r, color, &[(0.0, 120), (0.6, 100), (1.0, 0)]);
    Ok(())
}

pub fn rim_light(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let glow = ctx.color([110, 215, 255]);
    let s = ctx.scale();
    let Some(src) = ctx.place(Which::Source, glow) else { return Ok(()) };
    let pm = ctx.layer();
    let r = radius(&src, s) * 1.2;
    if let Some(p) = geom::circle(src.at, r) {
        draw::stroke(pm, &p, [glow[0], glow[1], glow[2], 70], 11.0 * s, ID);
        draw::stroke(pm, &p, [glow[0], glow[1], glow[2], 140], 5.0 * s, ID);
        draw::stroke(pm, &p, [255, 255, 255, 235], 2.0 * s, ID);
    }
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
            pool(ctx.layer(), p.at, r, c, &[(0.0, 150), (0.55, 120), (1.0, 0)]);
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
    if let Some(p) = geom::line(a.at, b.at) {
        draw::stroke(pm, &p, [color[0], color[1], color[2], 60], 16.0 * s, ID);
        draw::stroke(pm, &p, [color[0], color[1], color[2], 130], 7.0 * s, ID);
        draw::stroke(pm, &p, [255, 255, 255, 230], 2.2 * s, ID);
    }
    for p in [a, b] {
        pool(pm, p.at, radius(&p, s) * 1.4, color, &[(0.0, 130), (1.0, 0)]);
    }
    Ok(())
}
