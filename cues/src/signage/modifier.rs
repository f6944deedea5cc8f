//! Modifiers (the `m` of a sign): negation, direction, hazard, authorisation, alignment,
//! system state.

use serde::{Deserialize, Serialize};
use tiny_skia::{Pixmap, Transform};

use super::frame::Style;
use crate::draw::geom::{arrow_head, circle, line, polygon, polyline, v2};
use crate::draw::{self, Rgba};

/// A direction for the direction modifier.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    Left,
    Right,
    Up,
    Down,
}

/// Optional extra meaning on top of the pictogram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Modifier {
    /// A red diagonal slash: "not".
    Negation,
    /// An arrow in the lower corner: where to go or put.
    Direction(Direction),
    /// A small warning triangle badge.
    HazardMark,
    /// A green check badge: "authorised".
    Authorized,
    /// A crosshair badge: "align here".
    Alignment,
    /// A power badge with a status lamp: the state a device is to be in (green lamp and a
    /// closed power symbol for on, a dark lamp and a crossed symbol for off).
    Status { on: bool },
}

const BADGE_RIM: Rgba = [255, 255, 255, 255];

/// Draws the modifier over a composed sign of size `s`.
pub fn draw(pm: &mut Pixmap, modifier: Modifier, style: &Style, s: f32) {
    let ts = Transform::from_scale(s, s);
    let badge = v2(0.84, 0.16);
    match modifier {
        Modifier::Negation => {
            let (x, y, w, h) = style.content;
            if let Some(p) = line(v2(x - 0.04, y - 0.04), v2(x + w + 0.04, y + h + 0.04)) {
                draw::stroke(pm, &p, [206, 32, 41, 255], 0.09, ts);
            }
        }
        Modifier::Direction(d) => {
            let dir = match d {
                Direction::Left => v2(-1.0, 0.0),
                Direction::Right => v2(1.0, 0.0),
                Direction::Up => v2(0.0, -1.0),
                Direction::Down => v2(0.0, 1.0),
            };
            let c = v2(0.84, 0.84);
            if let Some(p) = circle(c, 0.13) {
                draw::fill_outlined(pm, &p, style.ink, BADGE_RIM, 0.015, ts);
            }
            let tip = c.add(dir.scale(0.1));
            if let Some(p) = line(c.sub(dir.scale(0.08)), c.add(dir.scale(0.02))) {
                draw::stroke(pm, &p, style.fill, 0.045, ts);
            }
            if let Some(p) = arrow_head(tip, dir, 0.09, 0.13) {
                draw::fill(pm, &p, style.fill, ts);
            }
        }
        Modifier::HazardMark => {
            if let Some(p) = polygon(&[v2(badge.x, 0.02), v2(badge.x + 0.15, 0.29), v2(badge.x - 0.15, 0.29)]) {
                draw::fill_outlined(pm, &p, [250, 200, 20, 255], [16, 16, 16, 255], 0.02, ts);
            }
            if let Some(p) = line(v2(badge.x, 0.11), v2(badge.x, 0.2)) {
                draw::stroke(pm, &p, [16, 16, 16, 255], 0.035, ts);
            }
            if let Some(p) = circle(v2(badge.x, 0.25), 0.018) {
                draw::fill(pm, &p, [16, 16, 16, 255], ts);
            }
        }
        Modifier::Authorized => {
            if let Some(p) = circle(badge, 0.13) {
                draw::fill_outlined(pm, &p, [20, 170, 80, 255], BADGE_RIM, 0.018, ts);
            }
            if let Some(p) = polyline(&[v2(0.78, 0.16), v2(0.83, 0.21), v2(0.91, 0.11)]) {
                draw::stroke(pm, &p, BADGE_RIM, 0.035, ts);
            }
        }
        Modifier::Status { on } => {
            let c = v2(0.84, 0.84);
            if let Some(p) = circle(c, 0.14) {
                draw::fill_outlined(pm, &p, [20, 20, 24, 255], BADGE_RIM, 0.015, ts);
            }
            let lamp = if on { [60, 220, 90, 255] } else { [120, 40, 40, 255] };
            // Power symbol: an open ring with a bar through the gap at the top.
            if let Some(p) = crate::draw::geom::arc(c, 0.075, -1.1, 4.24) {
                draw::stroke(pm, &p, lamp, 0.025, ts);
            }
            if let Some(p) = line(v2(c.x, c.y - 0.1), v2(c.x, c.y - 0.02)) {
                draw::stroke(pm, &p, lamp, 0.025, ts);
            }
            if !on && let Some(p) = line(v2(c.x - 0.1, c.y + 0.1), v2(c.x + 0.1, c.y - 0.1)) {
                draw::stroke(pm, &p, [230, 60, 60, 255], 0.022, ts);
            }
        }
        Modifier::Alignment => {
            if let Some(p) = circle(badge, 0.13) {
                draw::fill_outlined(pm, &p, style.ink, BADGE_RIM, 0.015, ts);
            }
            if let Some(p) = circle(badge, 0.06) {
                draw::stroke(pm, &p, style.fill, 0.02, ts);
            }
            for (a, b) in [
                (v2(0.0, -0.1), v2(0.0, -0.03)),
                (v2(0.0, 0.03), v2(0.0, 0.1)),
                (v2(-0.1, 0.0), v2(-0.03, 0.0)),
                (v2(0.03, 0.0), v2(0.1, 0.0)),
            ] {
                if let Some(p) = line(badge.add(a), badge.add(b)) {
                    draw::stroke(pm, &p, style.fill, 0.02, ts);
                }
            }
        }
    }
}
