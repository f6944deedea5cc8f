//! F6 visual signage (scene-anchored): a composed robot sign on a short post next to the
//! anchored object. The sign image is composed once per spec and frame size (cached); per
//! frame only the post and the placement are drawn.

use crate::draw::geom::ID;

use crate::draw::geom::{self, v2};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::insert::{Ctx, Which};
use crate::signage::{Category, SignSpec, compose_pixmap};

const POST: Rgba = [60, 60, 66, 255];

/// Things a hazard sign warns about: the hot appliances of LIBERO's scenes.
pub const HAZARDS: &[&str] = &["stove", "microwave"];

/// Carriers an object is handed over in, for a person to take away.
pub const CARRIERS: &[&str] = &["basket", "caddy", "tray"];

/// Draws the sign of `category` for the spec's step at the chosen anchor.
fn sign_at(ctx: &mut Ctx<'_>, category: Category, which: Which) -> Result<(), CueError> {
    let s = ctx.scale();
    let Some(a) = ctx.place(which, POST) else { return Ok(()) };
    let step = ctx.spec.steps.get(ctx.spec.step).cloned();
    let Some(step) = step else {
        return Err(CueError::BadSpec(format!("spec has no step {}", ctx.spec.step)));
    };
    let side = (56.0 * s).round().max(16.0) as u32;
    let sign = ctx.cached(&format!("sign_{category:?}_{which:?}"), || {
        Ok(compose_pixmap(&SignSpec::for_step(category, &step, which == Which::Source), side))
    })?;
    let (w, h) = ctx.size();
    let (sw, sh) = (sign.width() as f32, sign.height() as f32);
    let gap = a.radius * 0.7 + 6.0 * s;
    // Above the object when it fits, else below; always inside the frame horizontally.
    let above = a.at.y - gap - sh >= 0.0;
    let top = if above { a.at.y - gap - sh } else { (a.at.y + gap).min(h as f32 - sh) };
    let left = (a.at.x - sw / 2.0).clamp(0.0, (w as f32 - sw).max(0.0));
    let pm = ctx.layer();
    let post_end = if above { top + sh } else { top };
    if let Some(p) = geom::line(v2(a.at.x, a.at.y), v2(a.at.x.clamp(left + 3.0, left + sw - 3.0), post_end)) {
        draw::stroke(pm, &p, draw::WHITE, 4.0 * s, ID);
        draw::stroke(pm, &p, POST, 2.2 * s, ID);
    }
    if let Some(p) = geom::circle(a.at, 2.8 * s) {
        draw::fill_outlined(pm, &p, POST, draw::WHITE, 1.0 * s, ID);
    }
    draw::blit_over(pm, &sign, left.round() as i32, top.round() as i32);
    Ok(())
}

pub fn mandatory_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::Mandatory, Which::Source)
}

pub fn zone_target(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::TargetZone, Which::Target)
}

pub fn permission_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::Permission, Which::Source)
}

pub fn prohibition_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::Prohibition, Which::Source)
}

/// At the appliance: the target ("put the moka pot on the stove"), or the source of a step
/// without one ("turn on the stove").
pub fn hazard(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::Hazard, if ctx.spec.target.is_some() { Which::Target } else { Which::Source })
}

pub fn handover_target(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::HumanRobot, if ctx.spec.target.is_some() { Which::Target } else { Which::Source })
}

pub fn maintenance_source(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::Maintenance, Which::Source)
}

pub fn system_state(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    sign_at(ctx, Category::SystemState, Which::Source)
}
