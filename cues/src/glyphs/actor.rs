//! Robot actor glyphs (the `a` of a sign).

use serde::{Deserialize, Serialize};
use tiny_skia::{Pixmap, Transform};

use super::Pen;
use crate::draw::geom::{circle, line, polygon, polyline, rect, rounded_rect, v2};

/// Who acts: an industrial arm (the paper's prototype), a bare parallel gripper, or a mobile
/// manipulator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Actor {
    Arm,
    Gripper,
    Mobile,
}

/// Draws the actor in the unit box, reaching towards the right edge (where the predicate sits).
pub fn draw(pm: &mut Pixmap, actor: Actor, pen: Pen, ts: Transform) {
    match actor {
        Actor::Arm => {
            // Base, shoulder, upper arm, elbow, forearm, wrist, two fingers.
            pen.fill(pm, polygon(&[v2(0.04, 0.96), v2(0.44, 0.96), v2(0.38, 0.84), v2(0.1, 0.84)]), ts);
            pen.line(pm, line(v2(0.24, 0.84), v2(0.24, 0.5)), 0.15, ts);
            pen.fill(pm, circle(v2(0.24, 0.5), 0.1), ts);
            pen.line(pm, line(v2(0.24, 0.5), v2(0.62, 0.22)), 0.13, ts);
            pen.fill(pm, circle(v2(0.62, 0.22), 0.08), ts);
            pen.line(pm, line(v2(0.62, 0.22), v2(0.8, 0.4)), 0.1, ts);
            pen.cut(pm, circle(v2(0.24, 0.5), 0.035), 0.03, ts);
            gripper_fingers(pm, pen, ts);
        }
        Actor::Gripper => {
            pen.fill(pm, rounded_rect(0.3, 0.06, 0.4, 0.16, 0.04), ts);
            pen.fill(pm, rect(0.2, 0.22, 0.6, 0.14), ts);
            pen.fill(pm, rect(0.2, 0.36, 0.12, 0.46), ts);
            pen.fill(pm, rect(0.68, 0.36, 0.12, 0.46), ts);
        }
        Actor::Mobile => {
            pen.fill(pm, rounded_rect(0.06, 0.6, 0.62, 0.24, 0.05), ts);
            pen.fill(pm, circle(v2(0.18, 0.88), 0.08), ts);
            pen.fill(pm, circle(v2(0.56, 0.88), 0.08), ts);
            pen.line(pm, polyline(&[v2(0.5, 0.6), v2(0.5, 0.32), v2(0.8, 0.24)]), 0.1, ts);
            pen.line(pm, line(v2(0.8, 0.24), v2(0.92, 0.16)), 0.05, ts);
            pen.line(pm, line(v2(0.8, 0.24), v2(0.94, 0.32)), 0.05, ts);
        }
    }
}

/// Two-finger gripper at the end of the arm's forearm, opening down-right.
fn gripper_fingers(pm: &mut Pixmap, pen: Pen, ts: Transform) {
    pen.line(pm, line(v2(0.72, 0.46), v2(0.9, 0.3)), 0.06, ts);
    pen.line(pm, polyline(&[v2(0.84, 0.36), v2(0.96, 0.44)]), 0.05, ts);
    pen.line(pm, polyline(&[v2(0.78, 0.42), v2(0.88, 0.56)]), 0.05, ts);
}
