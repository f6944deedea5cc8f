//! Renderers of the eight cue families, one module each. Every public function here is the
//! draw function of one catalogue entry in [`crate::variants`].

pub mod code;
pub mod geometric;
pub mod gesture;
pub mod ghost;
pub mod highlight;
pub mod pictorial;
pub mod signs;
pub mod text;

use crate::draw::geom::ID;
use tiny_skia::Pixmap;

use crate::draw::text::{Align, Face, fit};
use crate::draw::{self, Rgba, geom};
use crate::error::CueError;

/// A rounded tag with one line of text, sized to the text (e.g. box labels, badges).
pub(crate) fn tag(text: &str, size: f32, fg: Rgba, bg: Rgba) -> Result<Pixmap, CueError> {
    let b = fit(Face::SansBold, text, f32::MAX, f32::MAX, size, size);
    let pad = (size * 0.35).max(1.0);
    let w = (b.width + 2.0 * pad).ceil() as u32 + 1;
    let h = (b.height + pad).ceil() as u32 + 1;
    let mut pm = Pixmap::new(w, h).ok_or_else(|| CueError::BadParam(format!("tag {text:?} is too large")))?;
    if let Some(p) = geom::rounded_rect(0.5, 0.5, w as f32 - 1.0, h as f32 - 1.0, pad) {
        draw::fill(&mut pm, &p, bg, ID);
    }
    if let Some(p) = draw::text::block_path(&b, pad, pad / 2.0, b.width, Align::Left) {
        draw::fill(&mut pm, &p, fg, ID);
    }
    Ok(pm)
}

/// A new transparent pixmap of a region's size.
pub(crate) fn canvas(w: u32, h: u32) -> Result<Pixmap, CueError> {
    Pixmap::new(w.max(1), h.max(1)).ok_or_else(|| CueError::BadParam(format!("region {w}x{h} is too large")))
}

/// The head noun of a name ("middle drawer of the cabinet" → "drawer", "black bowl" → "bowl").
pub(crate) fn head_noun(name: &str) -> &str {
    let before_of = name.split(" of ").next().unwrap_or(name);
    before_of.rsplit(' ').next().unwrap_or(before_of)
}
