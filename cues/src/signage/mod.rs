//! Robot-oriented visual signage (paper appendix C): a sign is composed as
//! s = (g, a, p, t, m) — category frame, robot actor, predicate, target, optional modifier.
//!
//! [`compose`] never draws a whole sign by hand: the frame comes from the category
//! ([`frame`]), the actor, predicate and target glyphs from [`crate::glyphs`], the modifier
//! from [`modifier`], each placed in a fixed slot of the frame's content box. Any category can
//! be combined with any actor, predicate, target and modifier.

pub mod frame;
pub mod modifier;

use crate::draw::geom::ID;
use serde::{Deserialize, Serialize};
use tiny_skia::Pixmap;

use crate::draw::geom::unit_box;
use crate::draw::text::{self, Align, Face};
use crate::draw::{self, geom};
use crate::glyphs::Pen;
use crate::glyphs::actor::{self, Actor};
use crate::glyphs::object::{self, ObjectShape};
use crate::glyphs::predicate::{self, Predicate};
use crate::image::RgbaImage;
use crate::parse::Step;

pub use frame::Category;
pub use modifier::Modifier;

/// What the sign is about: an object silhouette, a text label, or both (the label then goes on
/// a supplementary plate under the sign, as on road signs).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SignTarget {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<ObjectShape>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label: Option<String>,
}

impl SignTarget {
    /// Silhouette chosen from the name, and the name as label.
    pub fn named(name: &str) -> SignTarget {
        SignTarget { shape: Some(ObjectShape::for_name(name)), label: Some(name.to_string()) }
    }
}

/// The five elements of a sign.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SignSpec {
    pub category: Category,
    pub actor: Actor,
    pub predicate: Predicate,
    pub target: SignTarget,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modifier: Option<Modifier>,
}

impl SignSpec {
    /// The sign for one task step in a category. The predicate carries out the step's
    /// relation (grasp at a source that is carried away), the target is the thing the sign
    /// stands at, and the category adds its meaning:
    /// - prohibition forbids the opposite of a state change ("do not close" at a drawer to
    ///   open), with the negation slash;
    /// - permission gets the authorised check; system state a status badge with the state to
    ///   reach (on/off); human–robot interaction the hand-over predicate;
    /// - side relations ("to the right of") get a direction arrow at the target.
    pub fn for_step(category: Category, step: &Step, on_source: bool) -> SignSpec {
        use crate::parse::Relation;
        let name = if on_source { &step.source } else { step.target.as_ref().unwrap_or(&step.source) };
        let mut predicate = if on_source && step.relation.moves_source() {
            Predicate::Grasp
        } else {
            Predicate::for_relation(step.relation)
        };
        let modifier = match (category, step.relation) {
            (Category::Permission, _) => Some(Modifier::Authorized),
            (Category::Prohibition, r) => {
                predicate = match r {
                    Relation::Open => Predicate::Close,
                    Relation::Close => Predicate::Open,
                    Relation::TurnOn => Predicate::TurnOff,
                    Relation::TurnOff => Predicate::TurnOn,
                    _ => predicate,
                };
                Some(Modifier::Negation)
            }
            (Category::SystemState, Relation::TurnOn) => Some(Modifier::Status { on: true }),
            (Category::SystemState, Relation::TurnOff) => Some(Modifier::Status { on: false }),
            (Category::HumanRobot, _) => {
                predicate = Predicate::HandOver;
                None
            }
            (_, Relation::LeftOf) if !on_source => Some(Modifier::Direction(modifier::Direction::Left)),
            (_, Relation::RightOf) if !on_source => Some(Modifier::Direction(modifier::Direction::Right)),
            _ => None,
        };
        SignSpec { category, actor: Actor::Arm, predicate, target: SignTarget::named(name), modifier }
    }
}

/// Default sign size in pixels for [`compose`].
pub const DEFAULT_SIZE: u32 = 128;

/// Composes a sign at [`DEFAULT_SIZE`].
pub fn compose(spec: &SignSpec) -> RgbaImage {
    draw::to_rgba_image(&compose_pixmap(spec, DEFAULT_SIZE))
}

/// Height of the label plate relative to the sign size.
const PLATE: f32 = 0.34;

/// Largest sign side we draw; larger requests are clamped.
pub const MAX_SIZE: u32 = 4096;

/// Composes a sign `size` px wide, clamped to 16..=[`MAX_SIZE`] (taller when it has a label
/// plate).
pub fn compose_pixmap(spec: &SignSpec, size: u32) -> Pixmap {
    let size = size.clamp(16, MAX_SIZE);
    let s = size as f32;
    let plate_h = spec.target.label.as_ref().map_or(0.0, |_| (s * PLATE).round());
    let mut pm = Pixmap::new(size, size + plate_h as u32 + if plate_h > 0.0 { 2 } else { 0 })
        .expect("a sign of 16..=4096 px always fits in a pixmap");
    let style = frame::draw(&mut pm, spec.category, s);
    let pen = Pen { ink: style.ink, paper: style.fill };
    let (bx, by, bw, bh) = style.content;
    let slot = |x: f32, y: f32, w: f32, h: f32| unit_box((bx + x * bw) * s, (by + y * bh) * s, w * bw * s, h * bh * s);
    // Slots: actor top-left, predicate top-right, target bottom centre.
    actor::draw(&mut pm, spec.actor, pen, slot(0.0, 0.0, 0.46, 0.5));
    predicate::draw(&mut pm, spec.predicate, pen, slot(0.5, 0.02, 0.48, 0.46));
    match spec.target.shape {
        Some(shape) => object::draw(&mut pm, shape, pen, slot(0.27, 0.52, 0.46, 0.48)),
        None => {
            if let Some(path) = geom::rect(0.3, 0.58, 0.4, 0.36) {
                draw::stroke_dashed(&mut pm, &path, pen.ink, 0.04, 0.08, 0.06, slot(0.0, 0.0, 1.0, 1.0));
            }
        }
    }
    if let Some(m) = spec.modifier {
        modifier::draw(&mut pm, m, &style, s);
    }
    if let Some(label) = &spec.target.label {
        draw_plate(&mut pm, label, s, plate_h);
    }
    pm
}

/// The supplementary text plate under the sign.
fn draw_plate(pm: &mut Pixmap, label: &str, s: f32, h: f32) {
    let (x, y, w) = (s * 0.04, s + 2.0, s * 0.92);
    if let Some(p) = geom::rounded_rect(x, y, w, h - 1.0, h * 0.18) {
        draw::fill_outlined(pm, &p, draw::WHITE, [30, 30, 30, 255], (s * 0.012).max(0.6), ID);
    }
    let b = text::fit(Face::SansBold, label, w * 0.9, h * 0.86, 5.0, h * 0.62);
    if let Some(p) = text::block_path(&b, x + w * 0.05, y + (h - b.height) / 2.0, w * 0.9, Align::Center) {
        draw::fill(pm, &p, [20, 20, 20, 255], ID);
    }
}

#[cfg(test)]
mod tests;
