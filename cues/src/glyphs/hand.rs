//! A drawn human hand in three poses, for the gesture family (F5).
//!
//! The hand is built in a local frame one "hand length" long, with the point of action (the
//! index fingertip, or the middle of the grip) at the origin and the fingers along +x. Every
//! part is an outlined capsule or rounded box in skin colour, drawn back to front so each
//! part's outline separates it from the one behind: the eye reads palm, knuckles and fingers.

use tiny_skia::{Path, Pixmap, Transform};

use crate::draw::geom::{V2, line, quad, rounded_rect, v2};
use crate::draw::{self, Rgba};

/// Hand poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pose {
    /// Index finger extended, others curled: "this one".
    Point,
    /// Fingers and thumb curled around the origin: "grab this".
    Grasp,
    /// All fingers extended together: "put it here".
    Flat,
}

/// Colours of a hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HandColors {
    pub skin: Rgba,
    pub outline: Rgba,
    pub sleeve: Rgba,
}

pub const DEFAULT_COLORS: HandColors =
    HandColors { skin: [241, 196, 160, 255], outline: [84, 52, 32, 255], sleeve: [46, 98, 170, 255] };

/// Outline width in hand lengths.
const OUTLINE: f32 = 0.022;

struct Painter<'a> {
    pm: &'a mut Pixmap,
    ts: Transform,
    colors: HandColors,
}

impl Painter<'_> {
    /// A limb: a capsule along `path`, outlined.
    fn limb(&mut self, path: Option<Path>, width: f32) {
        if let Some(p) = path {
            draw::stroke(self.pm, &p, self.colors.outline, width + 2.0 * OUTLINE, self.ts);
            draw::stroke(self.pm, &p, self.colors.skin, width, self.ts);
        }
    }
    /// A filled, outlined box.
    fn block(&mut self, path: Option<Path>, color: Rgba) {
        if let Some(p) = path {
            draw::fill_outlined(self.pm, &p, color, self.colors.outline, OUTLINE, self.ts);
        }
    }
}

/// Draws a hand of `length` px whose point of action is at `at`, fingers along `dir`.
/// Hands pointing leftwards are mirrored so the thumb stays on top.
pub fn draw(pm: &mut Pixmap, pose: Pose, at: V2, dir: V2, length: f32, colors: HandColors) {
    let d = dir.unit();
    let mirror = if d.x < 0.0 { -1.0 } else { 1.0 };
    let ts = crate::draw::geom::rotate_translate(d.angle(), at).pre_scale(length, length * mirror);
    let mut p = Painter { pm, ts, colors };
    match pose {
        Pose::Point => {
            p.block(rounded_rect(-1.26, -0.2, 0.34, 0.56, 0.06), colors.sleeve);
            p.block(rounded_rect(-0.98, -0.14, 0.56, 0.44, 0.13), colors.skin);
            for y in [0.25, 0.17, 0.09] {
                p.limb(line(v2(-0.56, y), v2(-0.4, y)), 0.085);
            }
            p.limb(line(v2(-0.62, 0.0), v2(-0.055, 0.0)), 0.11);
            p.limb(line(v2(-0.84, -0.11), v2(-0.5, -0.1)), 0.1);
        }
        Pose::Grasp => {
            p.block(rounded_rect(-1.36, -0.34, 0.34, 0.62, 0.06), colors.sleeve);
            p.block(rounded_rect(-1.06, -0.32, 0.46, 0.56, 0.14), colors.skin);
            p.limb(quad(v2(-0.66, 0.16), v2(-0.3, 0.3), v2(-0.02, 0.12)), 0.12);
            for (y, reach) in [(-0.12, 0.0), (-0.2, 0.04), (-0.28, 0.06)] {
                p.limb(quad(v2(-0.66, y), v2(-0.3, y - 0.26), v2(reach, y + 0.02)), 0.1);
            }
        }
        Pose::Flat => {
            p.block(rounded_rect(-1.26, -0.22, 0.34, 0.52, 0.06), colors.sleeve);
            p.block(rounded_rect(-0.98, -0.16, 0.52, 0.38, 0.12), colors.skin);
            for (i, y) in [0.14, 0.06, -0.02, -0.1].into_iter().enumerate() {
                let tip = -0.02 - [0.08, 0.03, 0.0, 0.04][i];
                p.limb(line(v2(-0.56, y), v2(tip, y)), 0.085);
            }
            p.limb(line(v2(-0.82, -0.17), v2(-0.46, -0.24)), 0.09);
        }
    }
}
