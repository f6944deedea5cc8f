//! Vector pictograms shared by the cue families and the signage system: object silhouettes,
//! robot actors, predicate pictograms and human hands.
//!
//! Monochrome glyphs are drawn in the unit box \[0,1\]² (y down) through a transform, in an
//! `ink` colour, with detail lines in the `paper` colour (the colour underneath), so a glyph
//! works white-on-blue inside a sign and black-on-white in a pictogram strip.

pub mod actor;
pub mod hand;
pub mod object;
pub mod predicate;

use tiny_skia::{Path, Pixmap, Transform};

use crate::draw::{self, Rgba};

/// Ink and paper colours of a monochrome glyph.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pen {
    pub ink: Rgba,
    pub paper: Rgba,
}

impl Pen {
    pub fn fill(&self, pm: &mut Pixmap, path: Option<Path>, ts: Transform) {
        if let Some(p) = path {
            draw::fill(pm, &p, self.ink, ts);
        }
    }
    pub fn line(&self, pm: &mut Pixmap, path: Option<Path>, width: f32, ts: Transform) {
        if let Some(p) = path {
            draw::stroke(pm, &p, self.ink, width, ts);
        }
    }
    /// Detail line in the paper colour (cuts through filled ink).
    pub fn cut(&self, pm: &mut Pixmap, path: Option<Path>, width: f32, ts: Transform) {
        if let Some(p) = path {
            draw::stroke(pm, &p, self.paper, width, ts);
        }
    }
    /// Fills with paper colour (holes).
    pub fn hole(&self, pm: &mut Pixmap, path: Option<Path>, ts: Transform) {
        if let Some(p) = path {
            draw::fill(pm, &p, self.paper, ts);
        }
    }
}
