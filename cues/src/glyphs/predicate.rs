//! Predicate pictograms (the `p` of a sign): what the actor does.

use serde::{Deserialize, Serialize};
use tiny_skia::{Pixmap, Transform};

use super::Pen;
use crate::draw::geom::{arc, arrow_head, circle, line, polygon, polyline, rect, rounded_rect, v2};
use crate::parse::Relation;

/// Operational predicates of the signage grammar.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Predicate {
    Grasp,
    Place,
    Open,
    Close,
    TurnOn,
    TurnOff,
    Push,
    Stack,
    Avoid,
    HandOver,
    Inspect,
    Charge,
    Calibrate,
}

impl Predicate {
    pub const ALL: [Predicate; 13] = [
        Predicate::Grasp,
        Predicate::Place,
        Predicate::Open,
        Predicate::Close,
        Predicate::TurnOn,
        Predicate::TurnOff,
        Predicate::Push,
        Predicate::Stack,
        Predicate::Avoid,
        Predicate::HandOver,
        Predicate::Inspect,
        Predicate::Charge,
        Predicate::Calibrate,
    ];

    /// The predicate that carries out a task relation.
    pub fn for_relation(r: Relation) -> Predicate {
        match r {
            Relation::PickUp => Predicate::Grasp,
            Relation::Open => Predicate::Open,
            Relation::Close => Predicate::Close,
            Relation::TurnOn => Predicate::TurnOn,
            Relation::TurnOff => Predicate::TurnOff,
            Relation::PushTo => Predicate::Push,
            _ => Predicate::Place,
        }
    }

    /// Short label for captions ("grasp", "turn on").
    pub fn label(self) -> &'static str {
        match self {
            Predicate::Grasp => "grasp",
            Predicate::Place => "place",
            Predicate::Open => "open",
            Predicate::Close => "close",
            Predicate::TurnOn => "turn on",
            Predicate::TurnOff => "turn off",
            Predicate::Push => "push",
            Predicate::Stack => "stack",
            Predicate::Avoid => "avoid",
            Predicate::HandOver => "hand over",
            Predicate::Inspect => "inspect",
            Predicate::Charge => "charge",
            Predicate::Calibrate => "calibrate",
        }
    }
}

fn arrow(pm: &mut Pixmap, pen: Pen, from: (f32, f32), to: (f32, f32), ts: Transform) {
    let (a, b) = (v2(from.0, from.1), v2(to.0, to.1));
    let d = b.sub(a);
    pen.line(pm, line(a, b.sub(d.unit().scale(0.12))), 0.08, ts);
    pen.fill(pm, arrow_head(b, d, 0.2, 0.26), ts);
}

fn power_symbol(pm: &mut Pixmap, pen: Pen, ts: Transform) {
    let c = v2(0.5, 0.56);
    pen.line(pm, arc(c, 0.26, -1.05, 4.19), 0.09, ts);
    pen.line(pm, line(v2(0.5, 0.16), v2(0.5, 0.52)), 0.09, ts);
}

/// Draws the pictogram in the unit box.
pub fn draw(pm: &mut Pixmap, predicate: Predicate, pen: Pen, ts: Transform) {
    match predicate {
        Predicate::Grasp => {
            // Open jaws with arrows closing on a small object.
            pen.fill(pm, rect(0.1, 0.12, 0.8, 0.1), ts);
            pen.fill(pm, rect(0.1, 0.12, 0.1, 0.62), ts);
            pen.fill(pm, rect(0.8, 0.12, 0.1, 0.62), ts);
            pen.fill(pm, rounded_rect(0.4, 0.5, 0.2, 0.3, 0.03), ts);
            arrow(pm, pen, (0.22, 0.5), (0.38, 0.5), ts);
            arrow(pm, pen, (0.78, 0.5), (0.62, 0.5), ts);
        }
        Predicate::Place => {
            arrow(pm, pen, (0.5, 0.06), (0.5, 0.6), ts);
            pen.fill(pm, rect(0.1, 0.72, 0.8, 0.09), ts);
            pen.line(pm, line(v2(0.22, 0.66), v2(0.3, 0.66)), 0.05, ts);
            pen.line(pm, line(v2(0.7, 0.66), v2(0.78, 0.66)), 0.05, ts);
        }
        Predicate::Open | Predicate::Close => {
            // Drawer front sliding out of (or into) its cabinet.
            pen.line(pm, rect(0.08, 0.2, 0.5, 0.6), 0.06, ts);
            pen.fill(pm, rect(0.26, 0.36, 0.42, 0.28), ts);
            pen.cut(pm, line(v2(0.4, 0.5), v2(0.54, 0.5)), 0.05, ts);
            if predicate == Predicate::Open {
                arrow(pm, pen, (0.6, 0.86), (0.94, 0.86), ts);
            } else {
                arrow(pm, pen, (0.94, 0.86), (0.62, 0.86), ts);
            }
        }
        Predicate::TurnOn | Predicate::TurnOff => {
            power_symbol(pm, pen, ts);
            let c = v2(0.5, 0.56);
            let (a0, a1) = if predicate == Predicate::TurnOn { (-0.6, 0.5) } else { (3.74, 2.64) };
            pen.line(pm, arc(c, 0.42, a0, a1), 0.06, ts);
            let tip = v2(c.x + 0.42 * libm::cosf(a1), c.y + 0.42 * libm::sinf(a1));
            let dir = if predicate == Predicate::TurnOn {
                v2(-libm::sinf(a1), libm::cosf(a1))
            } else {
                v2(libm::sinf(a1), -libm::cosf(a1))
            };
            pen.fill(pm, arrow_head(tip, dir, 0.16, 0.2), ts);
        }
        Predicate::Push => {
            pen.fill(pm, rect(0.58, 0.36, 0.32, 0.36), ts);
            arrow(pm, pen, (0.06, 0.54), (0.52, 0.54), ts);
            for y in [0.3, 0.78] {
                pen.line(pm, line(v2(0.12, y), v2(0.36, y)), 0.05, ts);
            }
        }
        Predicate::Stack => {
            pen.fill(pm, rect(0.3, 0.66, 0.4, 0.24), ts);
            pen.fill(pm, rect(0.34, 0.34, 0.32, 0.2), ts);
            arrow(pm, pen, (0.5, 0.0), (0.5, 0.3), ts);
        }
        Predicate::Avoid => {
            pen.fill(pm, rect(0.4, 0.5, 0.2, 0.3), ts);
            pen.line(
                pm,
                polyline(&[v2(0.08, 0.66), v2(0.22, 0.66), v2(0.36, 0.28), v2(0.64, 0.28), v2(0.76, 0.6)]),
                0.07,
                ts,
            );
            pen.fill(pm, arrow_head(v2(0.86, 0.8), v2(0.3, 0.6), 0.2, 0.24), ts);
        }
        Predicate::HandOver => {
            pen.fill(pm, rounded_rect(0.36, 0.14, 0.28, 0.22, 0.04), ts);
            arrow(pm, pen, (0.08, 0.56), (0.48, 0.56), ts);
            // An open receiving hand.
            pen.fill(pm, rounded_rect(0.56, 0.5, 0.34, 0.22, 0.08), ts);
            for (i, x) in [0.6, 0.68, 0.76, 0.84].into_iter().enumerate() {
                pen.line(pm, line(v2(x, 0.52), v2(x, 0.4 - 0.03 * (i % 2) as f32)), 0.06, ts);
            }
        }
        Predicate::Inspect => {
            pen.line(pm, circle(v2(0.42, 0.42), 0.24), 0.08, ts);
            pen.line(pm, line(v2(0.6, 0.6), v2(0.88, 0.88)), 0.12, ts);
        }
        Predicate::Charge => {
            pen.line(pm, rounded_rect(0.1, 0.28, 0.72, 0.44, 0.06), 0.06, ts);
            pen.fill(pm, rect(0.82, 0.42, 0.08, 0.16), ts);
            pen.fill(
                pm,
                polygon(&[v2(0.5, 0.3), v2(0.3, 0.52), v2(0.44, 0.52), v2(0.38, 0.7), v2(0.6, 0.46), v2(0.46, 0.46)]),
                ts,
            );
        }
        Predicate::Calibrate => {
            pen.line(pm, circle(v2(0.5, 0.5), 0.3), 0.06, ts);
            for (a, b) in [
                ((0.5, 0.04), (0.5, 0.32)),
                ((0.5, 0.68), (0.5, 0.96)),
                ((0.04, 0.5), (0.32, 0.5)),
                ((0.68, 0.5), (0.96, 0.5)),
            ] {
                pen.line(pm, line(v2(a.0, a.1), v2(b.0, b.1)), 0.06, ts);
            }
            pen.fill(pm, circle(v2(0.5, 0.5), 0.06), ts);
        }
    }
}
