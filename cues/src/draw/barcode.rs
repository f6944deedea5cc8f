//! Code 128 barcodes (character set B: printable ASCII).

use super::geom::ID;
use barcoders::sym::code128::Code128;
use tiny_skia::{PathBuilder, Pixmap, Rect};

/// Error from encoding a payload.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("barcode payload {payload:?} cannot be encoded: {reason}")]
pub struct BarcodeError {
    pub payload: String,
    pub reason: String,
}

/// Bar modules (1 = dark) for `payload`, which must be printable ASCII, 1 to 40 characters.
pub fn modules(payload: &str) -> Result<Vec<u8>, BarcodeError> {
    let err = |reason: &str| BarcodeError { payload: payload.to_string(), reason: reason.to_string() };
    if payload.is_empty() || payload.len() > 40 {
        return Err(err("expected 1 to 40 characters"));
    }
    if let Some(c) = payload.chars().find(|c| !(' '..='~').contains(c)) {
        return Err(err(&format!("character {c:?} is not printable ASCII")));
    }
    // 'Ɓ' selects character set B.
    Code128::new(format!("\u{0181}{payload}")).map(|c| c.encode()).map_err(|e| err(&e.to_string()))
}

/// Draws the bars into `pm` inside (x, y, w, h), leaving a quiet zone of 6 modules each side.
/// Bars snap to whole pixels when there is room; otherwise they are anti-aliased.
pub fn draw(pm: &mut Pixmap, bars: &[u8], x: f32, y: f32, w: f32, h: f32) {
    let total = bars.len() as f32 + 12.0;
    let fit = w / total;
    let module = if fit >= 1.0 { fit.floor() } else { fit };
    let x0 = x + (w - module * bars.len() as f32) / 2.0;
    let x0 = if fit >= 1.0 { x0.floor() } else { x0 };
    let mut pb = PathBuilder::new();
    let mut i = 0;
    while i < bars.len() {
        if bars[i] == 1 {
            let run = bars[i..].iter().take_while(|&&b| b == 1).count();
            if let Some(r) = Rect::from_xywh(x0 + i as f32 * module, y, run as f32 * module, h) {
                pb.push_rect(r);
            }
            i += run;
        } else {
            i += 1;
        }
    }
    if let Some(path) = pb.finish() {
        super::fill(pm, &path, super::BLACK, ID);
    }
}
