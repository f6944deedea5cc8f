//! Text as tiny-skia paths, using the DejaVu fonts embedded by the `dejavu` crate (no system
//! fonts). Turning glyph outlines into paths gives outlined, rotated and scaled text with the
//! same anti-aliasing as every other shape.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, OutlineCurve, PxScale, ScaleFont};
use tiny_skia::{Path, PathBuilder};

use super::geom::V2;

/// The typefaces cues use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Face {
    Sans,
    SansBold,
    /// Condensed bold oblique: the "hand-written note" look.
    Note,
    MonoBold,
}

fn load(cell: &'static OnceLock<FontRef<'static>>, bytes: fn() -> &'static [u8]) -> &'static FontRef<'static> {
    // The embedded TTFs are valid; failure here means a corrupt build of the `dejavu` crate.
    cell.get_or_init(|| FontRef::try_from_slice(bytes()).expect("embedded DejaVu font parses"))
}

/// The parsed font for a face (parsed once, zero-copy).
pub fn font(face: Face) -> &'static FontRef<'static> {
    static SANS: OnceLock<FontRef<'static>> = OnceLock::new();
    static BOLD: OnceLock<FontRef<'static>> = OnceLock::new();
    static NOTE: OnceLock<FontRef<'static>> = OnceLock::new();
    static MONO_BOLD: OnceLock<FontRef<'static>> = OnceLock::new();
    match face {
        Face::Sans => load(&SANS, dejavu::sans::regular),
        Face::SansBold => load(&BOLD, dejavu::sans::bold),
        Face::Note => load(&NOTE, dejavu::sans_condensed::bold_oblique),
        Face::MonoBold => load(&MONO_BOLD, dejavu::sans_mono::bold),
    }
}

/// Advance width of one line of text at `size` px.
pub fn line_width(face: Face, size: f32, text: &str) -> f32 {
    let scaled = font(face).as_scaled(PxScale::from(size));
    let mut width = 0.0;
    let mut previous = None;
    for ch in text.chars() {
        let id = scaled.glyph_id(ch);
        if let Some(p) = previous {
            width += scaled.kern(p, id);
        }
        width += scaled.h_advance(id);
        previous = Some(id);
    }
    width
}

/// Ascent (above the baseline) and line height at `size` px.
pub fn metrics(face: Face, size: f32) -> (f32, f32) {
    let scaled = font(face).as_scaled(PxScale::from(size));
    (scaled.ascent(), scaled.height() + scaled.line_gap())
}

/// Appends one line of text with its baseline starting at `origin`.
fn push_line(pb: &mut PathBuilder, face: Face, size: f32, text: &str, origin: V2) {
    let f = font(face);
    let scaled = f.as_scaled(PxScale::from(size));
    let (sx, sy) = (scaled.h_scale_factor(), scaled.v_scale_factor());
    let map = |p: ab_glyph::Point, x0: f32| (x0 + p.x * sx, origin.y - p.y * sy);
    let mut x = origin.x;
    let mut previous = None;
    for ch in text.chars() {
        let id = scaled.glyph_id(ch);
        if let Some(p) = previous {
            x += scaled.kern(p, id);
        }
        if let Some(outline) = f.outline(id) {
            let mut last: Option<ab_glyph::Point> = None;
            for curve in &outline.curves {
                let start = match curve {
                    OutlineCurve::Line(a, _) | OutlineCurve::Quad(a, _, _) | OutlineCurve::Cubic(a, _, _, _) => *a,
                };
                if last != Some(start) {
                    if last.is_some() {
                        pb.close();
                    }
                    let (px, py) = map(start, x);
                    pb.move_to(px, py);
                }
                let end = match curve {
                    OutlineCurve::Line(_, b) => {
                        let (bx, by) = map(*b, x);
                        pb.line_to(bx, by);
                        *b
                    }
                    OutlineCurve::Quad(_, c, b) => {
                        let ((cx, cy), (bx, by)) = (map(*c, x), map(*b, x));
                        pb.quad_to(cx, cy, bx, by);
                        *b
                    }
                    OutlineCurve::Cubic(_, c1, c2, b) => {
                        let ((ax, ay), (cx, cy), (bx, by)) = (map(*c1, x), map(*c2, x), map(*b, x));
                        pb.cubic_to(ax, ay, cx, cy, bx, by);
                        *b
                    }
                };
                last = Some(end);
            }
            if last.is_some() {
                pb.close();
            }
        }
        x += scaled.h_advance(id);
        previous = Some(id);
    }
}

/// Horizontal alignment of a text block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Left,
    Center,
}

/// Wrapped lines at one font size, with their measured extent.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    pub face: Face,
    pub size: f32,
    pub lines: Vec<String>,
    pub width: f32,
    pub height: f32,
}

/// Greedy word wrap to `max_width`; a single word wider than the box stays on its own line.
pub fn wrap(face: Face, size: f32, text: &str, max_width: f32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut current = String::new();
    for word in text.split_whitespace() {
        let candidate = if current.is_empty() { word.to_string() } else { format!("{current} {word}") };
        if current.is_empty() || line_width(face, size, &candidate) <= max_width {
            current = candidate;
        } else {
            lines.push(std::mem::replace(&mut current, word.to_string()));
        }
    }
    if !current.is_empty() {
        lines.push(current);
    }
    lines
}

/// Lays `text` out at `size`, wrapped to `max_width`.
pub fn block(face: Face, size: f32, text: &str, max_width: f32) -> Block {
    let lines = wrap(face, size, text, max_width);
    let (_, line_height) = metrics(face, size);
    let width = lines.iter().map(|l| line_width(face, size, l)).fold(0.0, f32::max);
    let height = line_height * lines.len() as f32;
    Block { face, size, lines, width, height }
}

/// The largest size in [min_size, max_size] (1 px steps) whose wrapped block fits in
/// `max_w` × `max_h`; `min_size` when nothing fits.
pub fn fit(face: Face, text: &str, max_w: f32, max_h: f32, min_size: f32, max_size: f32) -> Block {
    let mut size = max_size.floor().max(min_size);
    loop {
        let b = block(face, size, text, max_w);
        if (b.width <= max_w && b.height <= max_h) || size <= min_size {
            return b;
        }
        size -= 1.0;
    }
}

/// The block as one path, its top-left at (x, y) (centred lines are centred in `box_w`).
pub fn block_path(b: &Block, x: f32, y: f32, box_w: f32, align: Align) -> Option<Path> {
    let (ascent, line_height) = metrics(b.face, b.size);
    let mut pb = PathBuilder::new();
    for (i, line) in b.lines.iter().enumerate() {
        let lx = match align {
            Align::Left => x,
            Align::Center => x + (box_w - line_width(b.face, b.size, line)) / 2.0,
        };
        push_line(&mut pb, b.face, b.size, line, super::geom::v2(lx, y + ascent + i as f32 * line_height));
    }
    pb.finish()
}

/// One line of text as a path, centred on `center`.
pub fn centered_line(face: Face, size: f32, text: &str, center: V2) -> Option<Path> {
    let b = Block {
        face,
        size,
        lines: vec![text.to_string()],
        width: line_width(face, size, text),
        height: metrics(face, size).1,
    };
    block_path(&b, center.x - b.width / 2.0, center.y - b.height / 2.0, b.width, Align::Left)
}
