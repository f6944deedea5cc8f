//! F5 hand gestures (scene-anchored): a drawn human hand pointing at, grasping, or showing
//! where to put an object.

use super::canvas;
use crate::draw::geom::{self, ID, V2, v2};
use crate::draw::text::{Face, centered_line};
use crate::draw::{self, Rgba, WHITE};
use crate::error::CueError;
use crate::glyphs::hand::{self, DEFAULT_COLORS, HandColors, Pose};
use crate::insert::{Ctx, Placed, Which};

fn colors(ctx: &Ctx<'_>) -> HandColors {
    HandColors { sleeve: ctx.color([46, 98, 170]), ..DEFAULT_COLORS }
}

/// Direction from which a hand of length `reach` reaches `at`: down from the side with more
/// room, or up from below when the hand would not fit above the anchor.
fn approach(at: V2, size: (u32, u32), reach: f32) -> V2 {
    let from_left = at.x > size.0 as f32 / 2.0;
    let x = if from_left { 0.55 } else { -0.55 };
    let y = if at.y < reach * 1.15 { -1.0 } else { 1.0 };
    v2(x, y).unit()
}

/// Like [`approach`], but from the side facing away from `other`, so two hands showing two
/// nearby anchors do not cover each other.
fn approach_away(at: V2, other: V2, size: (u32, u32), reach: f32) -> V2 {
    let d = approach(at, size, reach);
    if (at.x - other.x).abs() < 1.0 {
        return d;
    }
    // The hand's body lies along −dir from the tip: put it on the far side from `other`.
    let x = if at.x > other.x { -d.x.abs() } else { d.x.abs() };
    v2(x, d.y)
}

/// Draws a hand from a cached sprite: each (pose, direction, length, colour) is rasterised
/// once with its point of action at the sprite's centre, then only placed. Approach
/// directions come from a small set and lengths are rounded to 2 px, so few sprites exist.
fn draw_hand(ctx: &mut Ctx<'_>, pose: Pose, at: V2, dir: V2, length: f32) -> Result<(), CueError> {
    let length = (length / 2.0).round().max(4.0) * 2.0;
    let half = (1.45 * length).ceil();
    let c = colors(ctx);
    let key = format!("hand_{pose:?}_{:.4}_{:.4}_{length}", dir.x, dir.y);
    let sprite = ctx.cached(&key, || {
        let mut pm = canvas(2 * half as u32, 2 * half as u32)?;
        hand::draw(&mut pm, pose, v2(half, half), dir, length, c);
        Ok(pm)
    })?;
    let (x, y) = ((at.x - half).round() as i32, (at.y - half).round() as i32);
    draw::blit_over(ctx.layer(), &sprite, x, y);
    Ok(())
}

/// A hand coming along `dir` whose fingertip stops at the rim of the anchored object; returns
/// the fingertip.
fn point_at(ctx: &mut Ctx<'_>, a: Placed, pose: Pose, dir: V2, length: f32) -> Result<V2, CueError> {
    let tip = a.at.sub(dir.scale(a.radius * 0.8 + 2.0));
    draw_hand(ctx, pose, tip, dir, length)?;
    Ok(tip)
}

pub fn point_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let length = 62.0 * ctx.scale();
    let sleeve = colors(ctx).sleeve;
    match ctx.place(Which::Source, sleeve) {
        Some(src) => point_at(ctx, src, Pose::Point, approach(src.at, ctx.size(), length), length).map(|_| ()),
        None => Ok(()),
    }
}

pub fn grasp_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let s = ctx.scale();
    let sleeve = colors(ctx).sleeve;
    let Some(src) = ctx.place(Which::Source, sleeve) else { return Ok(()) };
    // The grip opening is about 0.4 hand lengths tall, centred 0.3 behind the hand's origin.
    let length = (src.radius * 2.6).clamp(58.0 * s, 120.0 * s);
    let dir = if src.at.x > ctx.size().0 as f32 / 2.0 { v2(1.0, 0.0) } else { v2(-1.0, 0.0) };
    draw_hand(ctx, Pose::Grasp, src.at.add(dir.scale(0.3 * length)), dir, length)
}

/// A round numbered badge as a cached sprite centred on `at`.
fn number_badge(ctx: &mut Ctx<'_>, at: V2, n: &str, color: Rgba) -> Result<(), CueError> {
    let s = ctx.scale();
    let half = (10.0 * s).ceil();
    let sprite = ctx.cached(&format!("badge_{n}"), || {
        let mut pm = canvas(2 * half as u32, 2 * half as u32)?;
        let c = v2(half, half);
        if let Some(p) = geom::circle(c, 8.0 * s) {
            draw::fill_outlined(&mut pm, &p, color, WHITE, 1.4 * s, ID);
        }
        if let Some(p) = centered_line(Face::SansBold, 11.0 * s, n, c.add(v2(0.0, 0.5 * s))) {
            draw::fill(&mut pm, &p, WHITE, ID);
        }
        Ok(pm)
    })?;
    let (x, y) = ((at.x - half).round() as i32, (at.y - half).round() as i32);
    draw::blit_over(ctx.layer(), &sprite, x, y);
    Ok(())
}

pub fn point_then_place(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let s = ctx.scale();
    let length = 56.0 * s;
    let sleeve = colors(ctx).sleeve;
    let src = ctx.place(Which::Source, sleeve);
    let tgt = ctx.place(Which::Target, sleeve);
    if let (Some(a), Some(b)) = (src, tgt) {
        // A dashed arc over the scene from the source to the target.
        let ctrl = a.at.lerp(b.at, 0.5).add(v2(0.0, -0.25 * a.at.sub(b.at).len()));
        let dir = b.at.sub(ctrl).unit();
        let pm = ctx.layer();
        if let Some(p) = geom::quad(a.at, ctrl, b.at) {
            draw::stroke_dashed(pm, &p, [20, 20, 20, 255], 4.5 * s, 8.0 * s, 5.0 * s, ID);
            draw::stroke_dashed(pm, &p, WHITE, 2.2 * s, 8.0 * s, 5.0 * s, ID);
        }
        if let Some(p) = geom::arrow_head(b.at, dir, 11.0 * s, 11.0 * s) {
            draw::fill_outlined(pm, &p, WHITE, [20, 20, 20, 255], 1.2 * s, ID);
        }
    }
    let ends = [(src, tgt, Pose::Point, "1", [30, 170, 70, 255]), (tgt, src, Pose::Flat, "2", [30, 110, 235, 255])];
    for (placed, other, pose, n, badge) in ends {
        if let Some(p) = placed {
            let dir = match other {
                Some(o) => approach_away(p.at, o.at, ctx.size(), length),
                None => approach(p.at, ctx.size(), length),
            };
            let tip = point_at(ctx, p, pose, dir, length)?;
            // Badge on the back of the hand.
            number_badge(ctx, tip.sub(dir.scale(length * 0.75)), n, badge)?;
        }
    }
    Ok(())
}
