//! F2 geometric symbols (scene-anchored): arrows and paths from source to target, and marks
//! on one object. Arrows start at the source anchor and end with their tip on the target
//! anchor.

use super::tag;
use crate::draw::geom::{self, V2, v2};
use crate::draw::text::{Face, centered_line};
use crate::draw::{self, Rgba, WHITE};
use crate::error::CueError;
use crate::insert::{Ctx, Placed, Which};

use crate::draw::geom::ID;
const DARK: Rgba = [20, 20, 20, 255];

/// Both anchors, or `None` when either is skipped (the arrow then is not drawn).
fn ends(ctx: &mut Ctx<'_>, color: Rgba) -> Option<(Placed, Placed)> {
    let s = ctx.place(Which::Source, color);
    let t = ctx.place(Which::Target, color);
    s.zip(t)
}

/// Control point of an arc from `a` to `b` bulging upwards by `bend` × distance.
fn bulge(a: V2, b: V2, bend: f32) -> V2 {
    let mid = a.lerp(b, 0.5);
    let mut n = b.sub(a).perp().unit();
    if n.y > 0.0 {
        n = n.scale(-1.0);
    }
    mid.add(n.scale(b.sub(a).len() * bend))
}

pub fn straight_arrow(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([232, 36, 36]);
    let s = ctx.scale();
    let Some((src, tgt)) = ends(ctx, color) else { return Ok(()) };
    let pm = ctx.layer();
    if let Some(p) = geom::block_arrow(src.at, tgt.at, 6.0 * s, 18.0 * s, 20.0 * s) {
        draw::fill_outlined(pm, &p, color, WHITE, 1.6 * s, ID);
    }
    if let Some(p) = geom::circle(src.at, 5.0 * s) {
        draw::fill_outlined(pm, &p, color, WHITE, 1.6 * s, ID);
    }
    Ok(())
}

/// An arc with a dark outline and an arrowhead whose tip sits on `b`.
fn arc_arrow(pm: &mut tiny_skia::Pixmap, a: V2, b: V2, bend: f32, color: Rgba, width: f32, s: f32) {
    let outline = DARK;
    let c = bulge(a, b, bend);
    let head = 16.0 * s;
    let dir = b.sub(c).unit();
    let neck = b.sub(dir.scale(head * 0.8));
    if let Some(p) = geom::quad(a, c, neck) {
        draw::stroke(pm, &p, outline, width + 3.0 * s, ID);
        draw::stroke(pm, &p, color, width, ID);
    }
    if let Some(p) = geom::arrow_head(b, dir, head, head * 1.1) {
        draw::fill_outlined(pm, &p, color, outline, 1.5 * s, ID);
    }
}

pub fn curved_arrow(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([255, 208, 0]);
    let s = ctx.scale();
    let Some((src, tgt)) = ends(ctx, color) else { return Ok(()) };
    arc_arrow(ctx.layer(), src.at, tgt.at, 0.35, color, 5.0 * s, s);
    Ok(())
}

pub fn dashed_path(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([0, 210, 240]);
    let s = ctx.scale();
    let Some((src, tgt)) = ends(ctx, color) else { return Ok(()) };
    let pm = ctx.layer();
    let c = bulge(src.at, tgt.at, 0.15);
    let dir = tgt.at.sub(c).unit();
    let neck = tgt.at.sub(dir.scale(10.0 * s));
    if let Some(p) = geom::quad(src.at, c, neck) {
        draw::stroke_dashed(pm, &p, DARK, 5.5 * s, 9.0 * s, 6.0 * s, ID);
        draw::stroke_dashed(pm, &p, color, 3.0 * s, 9.0 * s, 6.0 * s, ID);
    }
    let r = src.radius.max(8.0 * s);
    draw::round::ring(pm, src.at, r, 5.0 * s, DARK);
    draw::round::ring(pm, src.at, r, 2.5 * s, color);
    if let Some(p) = geom::arrow_head(tgt.at, dir, 13.0 * s, 13.0 * s) {
        draw::fill_outlined(pm, &p, color, DARK, 1.3 * s, ID);
    }
    Ok(())
}

pub fn chevron_trail(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([40, 205, 80]);
    let s = ctx.scale();
    let Some((src, tgt)) = ends(ctx, color) else { return Ok(()) };
    let pm = ctx.layer();
    let d = tgt.at.sub(src.at);
    let len = d.len();
    let step = 15.0 * s;
    let size = 11.0 * s;
    // Chevrons from just past the source to the last one ending at the target.
    let n = ((len - size * 0.5) / step).floor().max(1.0) as usize;
    for i in 0..n {
        let t = 1.0 - (i as f32 * step + size * 0.5) / len.max(1.0);
        if t <= 0.0 {
            break;
        }
        let points = geom::chevron_points(src.at.lerp(tgt.at, t), d, size);
        draw::round::polyline(pm, &points, 7.0 * s, DARK);
        draw::round::polyline(pm, &points, 4.0 * s, color);
    }
    Ok(())
}

/// A round badge with a number.
fn badge(pm: &mut tiny_skia::Pixmap, at: V2, n: &str, color: Rgba, s: f32) {
    if let Some(p) = geom::circle(at, 9.5 * s) {
        draw::fill_outlined(pm, &p, color, WHITE, 1.6 * s, ID);
    }
    if let Some(p) = centered_line(Face::SansBold, 13.0 * s, n, at.add(v2(0.0, 0.5 * s))) {
        draw::fill(pm, &p, WHITE, ID);
    }
}

pub fn numbered_waypoints(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let first = ctx.color([30, 170, 70]);
    let second: Rgba = [30, 110, 235, 255];
    let s = ctx.scale();
    let Some((src, tgt)) = ends(ctx, first) else { return Ok(()) };
    let pm = ctx.layer();
    draw::round::polyline(pm, &[src.at, tgt.at], 4.0 * s, DARK);
    draw::round::polyline(pm, &[src.at, tgt.at], 2.0 * s, WHITE);
    badge(pm, src.at, "1", first, s);
    badge(pm, tgt.at, "2", second, s);
    Ok(())
}

pub fn crosshair(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([235, 0, 205]);
    let s = ctx.scale();
    let Some(goal) = ctx.place_goal(color) else { return Ok(()) };
    let pm = ctx.layer();
    let r = goal.radius.max(10.0 * s) * 1.1;
    let ticks = [v2(1.0, 0.0), v2(-1.0, 0.0), v2(0.0, 1.0), v2(0.0, -1.0)];
    for (outline, width) in [(true, 5.0 * s), (false, 2.5 * s)] {
        let c = if outline { DARK } else { color };
        draw::round::ring(pm, goal.at, r, width, c);
        for t in ticks {
            draw::round::polyline(pm, &[goal.at.add(t.scale(r * 0.45)), goal.at.add(t.scale(r * 1.45))], width, c);
        }
    }
    Ok(())
}

pub fn bullseye(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let color = ctx.color([60, 225, 90]);
    let s = ctx.scale();
    let Some(goal) = ctx.place_goal(color) else { return Ok(()) };
    let pm = ctx.layer();
    let r = goal.radius.max(10.0 * s);
    for k in [1.5, 1.05, 0.6] {
        draw::round::ring(pm, goal.at, r * k, 5.0 * s, DARK);
        draw::round::ring(pm, goal.at, r * k, 3.0 * s, color);
    }
    Ok(())
}

/// An axis-aligned box around an anchor with a name tag above it.
fn boxed(ctx: &mut Ctx<'_>, which: Which, color: Rgba, dashed: bool) -> Result<(), CueError> {
    let s = ctx.scale();
    let Some(a) = ctx.place(which, color) else { return Ok(()) };
    let name = match which {
        Which::Source => ctx.spec.source.clone(),
        Which::Target => ctx.spec.target.clone().unwrap_or_default(),
    };
    let label = ctx.cached(if which == Which::Source { "src_tag" } else { "tgt_tag" }, || {
        tag(super::head_noun(&name), (10.0 * s).max(6.0), WHITE, color)
    })?;
    let h = a.radius.max(9.0 * s) * 1.2;
    let (fw, fh) = ctx.size();
    let (lw, lh) = (label.width() as f32, label.height() as f32);
    // Over the box's top left corner; below the box where that leaves the frame, and never past
    // its sides (a name cut to "t" or "wer" names nothing).
    let above = a.at.y - h - lh;
    let ly = if above >= 0.0 { above } else { (a.at.y + h).min(fh as f32 - lh).max(0.0) };
    let lx = (a.at.x - h - 1.0 * s).clamp(0.0, (fw as f32 - lw).max(0.0));
    let pm = ctx.layer();
    if let Some(p) = geom::rect(a.at.x - h, a.at.y - h, 2.0 * h, 2.0 * h) {
        draw::stroke(pm, &p, DARK, 4.5 * s, ID);
        if dashed {
            draw::stroke_dashed(pm, &p, color, 2.5 * s, 7.0 * s, 4.0 * s, ID);
        } else {
            draw::stroke(pm, &p, color, 2.5 * s, ID);
        }
    }
    draw::blit_over(pm, &label, lx.round() as i32, ly.round() as i32);
    Ok(())
}

pub fn bounding_boxes(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let src = ctx.color([255, 140, 0]);
    boxed(ctx, Which::Source, src, false)?;
    if ctx.spec.target.is_some() {
        boxed(ctx, Which::Target, [40, 120, 255, 255], true)?;
    }
    Ok(())
}
