//! F4 pictorial demonstrations (fixed-region): goal-state pictures, start/goal pairs and
//! keyframe storyboards from caller-supplied pictures, and pictogram strips and step cards
//! drawn from the task's steps.
//!
//! Panels are composed once and cached. Pictures are part of the cache key through a
//! fingerprint of their sizes and every byte (a fast non-cryptographic hash, 11 µs for a
//! 256² picture), so any change to a picture gives a new panel.

use std::hash::{BuildHasher, Hash, Hasher};
use std::sync::Arc;

use foldhash::fast::FixedState;
use tiny_skia::{FilterQuality, Pixmap, PixmapPaint, Transform};

use super::{canvas, tag};
use crate::draw::geom::{self, v2};
use crate::draw::text::{Align, Face, block_path, centered_line, fit};
use crate::draw::{self, Rgba, WHITE};
use crate::error::CueError;
use crate::glyphs::Pen;
use crate::glyphs::object::{self, ObjectShape};
use crate::glyphs::predicate::{self, Predicate};
use crate::image::RgbaImage;
use crate::insert::Ctx;
use crate::spec::NormBox;

use crate::draw::geom::ID;
const GOAL_GREEN: Rgba = [24, 150, 64, 255];

/// Content fingerprint of the pictures: their sizes and every byte (see module docs).
fn fingerprint(pictures: &[RgbaImage]) -> u64 {
    let mut h = FixedState::default().build_hasher();
    for p in pictures {
        (p.width, p.height, p.data.as_slice()).hash(&mut h);
    }
    h.finish()
}

/// Draws `pic` scaled to cover (x, y, w, h), cropping the overflow, with bilinear filtering.
fn draw_picture(pm: &mut Pixmap, pic: &RgbaImage, x: f32, y: f32, w: f32, h: f32) -> Result<(), CueError> {
    let src = draw::from_rgba_image(pic).ok_or_else(|| CueError::BadParam("picture is empty or malformed".into()))?;
    let k = (w / pic.width as f32).max(h / pic.height as f32);
    let (sw, sh) = (pic.width as f32 * k, pic.height as f32 * k);
    let ts = Transform::from_row(k, 0.0, 0.0, k, x + (w - sw) / 2.0, y + (h - sh) / 2.0);
    let clip = geom::rect(x, y, w, h).ok_or_else(|| CueError::BadParam("empty picture slot".into()))?;
    let mut mask =
        tiny_skia::Mask::new(pm.width(), pm.height()).ok_or_else(|| CueError::BadParam("empty panel".into()))?;
    mask.fill_path(&clip, tiny_skia::FillRule::Winding, false, ID);
    let paint = PixmapPaint { quality: FilterQuality::Bilinear, ..PixmapPaint::default() };
    pm.draw_pixmap(0, 0, src.as_ref(), &paint, ts, Some(&mask));
    Ok(())
}

/// The cached panel for this spec, frame size and pictures; `needs` pictures must be given.
fn panel(
    ctx: &mut Ctx<'_>,
    name: &str,
    needs: (usize, &str),
    build: impl FnOnce(&[RgbaImage]) -> Result<Pixmap, CueError>,
) -> Result<Arc<Pixmap>, CueError> {
    let pictures = ctx.inputs.pictures;
    if pictures.len() < needs.0 {
        return Err(ctx.missing(needs.1));
    }
    let key = format!("{name}_{:016x}", fingerprint(pictures));
    ctx.cached(&key, || build(pictures))
}

const GOAL: (usize, &str) = (1, "a goal picture (FrameInputs::pictures)");

/// The goal picture: the last one.
fn goal_of(pictures: &[RgbaImage]) -> Result<&RgbaImage, CueError> {
    pictures.last().ok_or_else(|| CueError::BadParam("no pictures".into()))
}

pub fn goal_inset(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.63, 0.02, 0.35, 0.35));
    let label = ctx.color([24, 150, 64]);
    let pm = panel(ctx, "inset", GOAL, |pictures| {
        let goal = goal_of(pictures)?;
        let mut pm = canvas(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        let border = (wf.min(hf) * 0.04).max(1.5);
        if let Some(p) = geom::rect(0.0, 0.0, wf, hf) {
            draw::fill(&mut pm, &p, WHITE, ID);
        }
        draw_picture(&mut pm, goal, border, border, wf - 2.0 * border, hf - 2.0 * border)?;
        let t = tag("GOAL", (hf * 0.11).max(6.0), WHITE, label)?;
        pm.draw_pixmap(border as i32 + 1, border as i32 + 1, t.as_ref(), &PixmapPaint::default(), ID, None);
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn goal_polaroid(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.56, 0.5, 0.42, 0.48));
    let ink = ctx.color([30, 40, 110]);
    let pm = panel(ctx, "polaroid", GOAL, |pictures| {
        let goal = goal_of(pictures)?;
        let (wf, hf) = (w as f32, h as f32);
        // An upright card 85 % of the region, tilted 5°.
        let (cw, ch) = (wf * 0.8, hf * 0.85);
        let mut card = canvas(cw as u32, ch as u32)?;
        card.fill(tiny_skia::Color::from_rgba8(250, 250, 246, 255));
        let m = cw * 0.07;
        let photo = (cw - 2.0 * m).min(ch - 3.5 * m);
        draw_picture(&mut card, goal, (cw - photo) / 2.0, m, photo, photo)?;
        let caption_top = m + photo;
        let b = fit(Face::Note, "goal", cw * 0.8, ch - caption_top - m * 0.3, 5.0, (ch - caption_top) * 0.7);
        if let Some(p) =
            block_path(&b, cw * 0.1, caption_top + (ch - caption_top - b.height) / 2.0, cw * 0.8, Align::Center)
        {
            draw::fill(&mut card, &p, ink, ID);
        }
        let mut out = canvas(w, h)?;
        let place =
            geom::rotate_translate(5f32.to_radians(), v2(wf / 2.0, hf / 2.0)).pre_translate(-cw / 2.0, -ch / 2.0);
        if let Some(shape) = geom::rect(0.0, 0.0, cw, ch) {
            draw::fill(&mut out, &shape, [0, 0, 0, 70], place.post_translate(2.0, 3.0));
        }
        let paint = PixmapPaint { quality: FilterQuality::Bilinear, ..PixmapPaint::default() };
        out.draw_pixmap(0, 0, card.as_ref(), &paint, place, None);
        Ok(out)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn goal_monitor(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.6, 0.38, 0.38));
    let bar = ctx.color([36, 38, 46]);
    let pm = panel(ctx, "monitor", GOAL, |pictures| {
        let goal = goal_of(pictures)?;
        let mut pm = canvas(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        if let Some(p) = geom::rounded_rect(0.0, 0.0, wf, hf, wf * 0.05) {
            draw::fill(&mut pm, &p, bar, ID);
        }
        let title = hf * 0.17;
        if let Some(p) = geom::circle(v2(title * 0.5, title * 0.5), title * 0.2) {
            draw::fill(&mut pm, &p, [235, 50, 50, 255], ID);
        }
        let b = fit(Face::SansBold, "GOAL VIEW", wf - title * 1.2, title * 0.9, 4.0, title * 0.6);
        if let Some(p) = block_path(&b, title, (title - b.height) / 2.0, wf - title * 1.2, Align::Left) {
            draw::fill(&mut pm, &p, [230, 230, 235, 255], ID);
        }
        let m = wf * 0.04;
        draw_picture(&mut pm, goal, m, title, wf - 2.0 * m, hf - title - m)?;
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

/// A translucent white strip panel.
fn strip(w: u32, h: u32) -> Result<Pixmap, CueError> {
    let mut pm = canvas(w, h)?;
    if let Some(p) = geom::rounded_rect(0.0, 0.0, w as f32, h as f32, h as f32 * 0.1) {
        draw::fill(&mut pm, &p, [255, 255, 255, 225], ID);
    }
    Ok(pm)
}

/// A right-pointing arrow between panels, centred on (cx, cy).
fn small_arrow(pm: &mut Pixmap, cx: f32, cy: f32, len: f32, color: Rgba) {
    if let Some(p) = geom::block_arrow(v2(cx - len / 2.0, cy), v2(cx + len / 2.0, cy), len * 0.22, len * 0.5, len * 0.6)
    {
        draw::fill(pm, &p, color, ID);
    }
}

pub fn before_after(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.69, 0.96, 0.29));
    let accent = ctx.color([24, 150, 64]);
    let pm = panel(ctx, "before_after", (2, "two pictures, start and goal (FrameInputs::pictures)"), |pictures| {
        let (start, goal) = (&pictures[0], goal_of(pictures)?);
        let mut pm = strip(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        let m = hf * 0.08;
        let side = hf - 2.0 * m;
        let label = hf * 0.16;
        for (i, (pic, text, color)) in
            [(start, "start", [90, 90, 90, 255]), (goal, "goal", accent)].into_iter().enumerate()
        {
            let px = if i == 0 { wf * 0.27 - side / 2.0 } else { wf * 0.73 - side / 2.0 };
            draw_picture(&mut pm, pic, px, m, side, side)?;
            if let Some(p) = geom::rect(px, m, side, side) {
                draw::stroke(&mut pm, &p, color, (hf * 0.025).max(1.0), ID);
            }
            let t = tag(text, label.max(6.0), WHITE, color)?;
            pm.draw_pixmap(px as i32 + 2, m as i32 + 2, t.as_ref(), &PixmapPaint::default(), ID, None);
        }
        small_arrow(&mut pm, wf / 2.0, hf / 2.0, (wf * 0.46 - side).max(hf * 0.3) * 0.8, accent);
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn storyboard(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.76, 0.96, 0.22));
    let accent = ctx.color([230, 120, 20]);
    let pm = panel(ctx, "storyboard", (1, "at least one keyframe (FrameInputs::pictures)"), |pictures| {
        // Up to four keyframes, evenly spaced, always including the first and the last.
        let n = pictures.len().min(4);
        let picks: Vec<&RgbaImage> =
            (0..n).map(|i| &pictures[if n == 1 { 0 } else { i * (pictures.len() - 1) / (n - 1) }]).collect();
        let mut pm = strip(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        let m = hf * 0.08;
        let side = (hf - 2.0 * m).min((wf - m) / n as f32 * 0.78);
        let slot = wf / n as f32;
        for (i, pic) in picks.iter().enumerate() {
            let px = slot * (i as f32 + 0.5) - side / 2.0;
            draw_picture(&mut pm, pic, px, m, side, side)?;
            let t = tag(&(i + 1).to_string(), (hf * 0.18).max(6.0), WHITE, accent)?;
            pm.draw_pixmap(px as i32 + 1, m as i32 + 1, t.as_ref(), &PixmapPaint::default(), ID, None);
            if i + 1 < n {
                small_arrow(&mut pm, slot * (i as f32 + 1.0), hf / 2.0, (slot - side) * 0.8, accent);
            }
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

/// Source, predicate, target glyphs of every step in one row, steps separated by chevrons.
pub fn pictogram_strip(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.02, 0.96, 0.2));
    let steps = ctx.spec.steps.clone();
    let ink = ctx.color([28, 28, 32]);
    let pm = ctx.cached("strip", || {
        let mut pm = strip(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        let pen = Pen { ink, paper: [255, 255, 255, 255] };
        let glyphs: usize = steps.iter().map(|s| if s.target.is_some() { 3 } else { 2 }).sum();
        let seps = steps.len().saturating_sub(1);
        let cell = (hf * 0.78).min(wf / (glyphs as f32 + 0.6 * seps as f32 + 0.4));
        let total = cell * (glyphs as f32 + 0.6 * seps as f32);
        let mut cx = (wf - total) / 2.0;
        let top = (hf - cell) / 2.0;
        for (i, s) in steps.iter().enumerate() {
            if i > 0 {
                if let Some(p) = geom::chevron(v2(cx + cell * 0.3, hf / 2.0), v2(1.0, 0.0), cell * 0.35) {
                    draw::stroke(&mut pm, &p, [150, 150, 150, 255], cell * 0.08, ID);
                }
                cx += cell * 0.6;
            }
            let slot = |cx: f32| geom::unit_box(cx + cell * 0.08, top + cell * 0.08, cell * 0.84, cell * 0.84);
            object::draw(&mut pm, ObjectShape::for_name(&s.source), pen, slot(cx));
            cx += cell;
            predicate::draw(&mut pm, Predicate::for_relation(s.relation), Pen { ink: GOAL_GREEN, ..pen }, slot(cx));
            cx += cell;
            if let Some(t) = &s.target {
                object::draw(&mut pm, ObjectShape::for_name(t), pen, slot(cx));
                cx += cell;
            }
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

/// One card per step (at most three): number, action pictogram, and "source → target".
pub fn step_cards(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.02, 0.34, 0.56));
    let steps = ctx.spec.steps.clone();
    let accent = ctx.color([30, 110, 235]);
    let pm = ctx.cached("cards", || {
        let mut pm = canvas(w, h)?;
        let (wf, hf) = (w as f32, h as f32);
        let n = steps.len().clamp(1, 3);
        let gap = hf * 0.03;
        let card_h = ((hf - gap * (n as f32 - 1.0)) / n as f32).min(hf * 0.4);
        for (i, s) in steps.iter().take(3).enumerate() {
            let top = i as f32 * (card_h + gap);
            if let Some(p) = geom::rounded_rect(0.0, top, wf, card_h, card_h * 0.12) {
                draw::fill_outlined(&mut pm, &p, [255, 255, 255, 235], accent, 1.0, ID);
            }
            let r = card_h * 0.16;
            if let Some(p) = geom::circle(v2(r * 1.3, top + r * 1.3), r) {
                draw::fill(&mut pm, &p, accent, ID);
            }
            if let Some(p) = centered_line(Face::SansBold, r * 1.4, &(i + 1).to_string(), v2(r * 1.3, top + r * 1.35)) {
                draw::fill(&mut pm, &p, WHITE, ID);
            }
            let icon = card_h * 0.5;
            let pen = Pen { ink: accent, paper: WHITE };
            predicate::draw(
                &mut pm,
                Predicate::for_relation(s.relation),
                pen,
                geom::unit_box(r * 2.8, top + card_h * 0.06, icon, icon),
            );
            object::draw(
                &mut pm,
                ObjectShape::for_name(&s.source),
                Pen { ink: [30, 30, 30, 255], ..pen },
                geom::unit_box(r * 2.8 + icon * 1.1, top + card_h * 0.06, icon, icon),
            );
            let text = match &s.target {
                Some(t) => format!("{} \u{2192} {}", s.source, t),
                None => format!("{} {}", s.relation.verb(), s.source),
            };
            let tb = fit(Face::SansBold, &text, wf * 0.92, card_h * 0.38, 4.0, card_h * 0.2);
            if let Some(p) = block_path(&tb, wf * 0.04, top + card_h * 0.6, wf * 0.92, Align::Left) {
                draw::fill(&mut pm, &p, [25, 25, 25, 255], ID);
            }
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}
