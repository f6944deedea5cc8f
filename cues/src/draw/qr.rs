//! QR codes drawn as crisp module squares on a white card.

use super::geom::ID;
use qrcode::{Color, EcLevel, QrCode};
use tiny_skia::Pixmap;

use super::geom;

/// Quiet zone in modules. The standard asks for 4; 2 keeps codes legible in small frames and
/// still decodes (the card around the code is white as well).
pub const QUIET_MODULES: usize = 2;

/// Error from encoding a payload.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("QR payload of {len} bytes cannot be encoded: {reason}")]
pub struct QrError {
    pub len: usize,
    pub reason: String,
}

/// The module matrix (true = dark) and its side length.
pub fn modules(payload: &str, ec: EcLevel) -> Result<(Vec<bool>, usize), QrError> {
    let code = QrCode::with_error_correction_level(payload.as_bytes(), ec)
        .map_err(|e| QrError { len: payload.len(), reason: e.to_string() })?;
    let width = code.width();
    Ok((code.to_colors().into_iter().map(|c| c == Color::Dark).collect(), width))
}

/// Renders the code into a square white card of `side` px. Modules are whole pixels wide
/// when the card allows it (sharp edges decode best); the code is centred on the card.
pub fn render(payload: &str, ec: EcLevel, side: u32) -> Result<Pixmap, QrError> {
    let (dark, n) = modules(payload, ec)?;
    let side = side.max(1);
    let mut pm = Pixmap::new(side, side).ok_or_else(|| QrError { len: payload.len(), reason: "empty card".into() })?;
    pm.fill(tiny_skia::Color::WHITE);
    let total = (n + 2 * QUIET_MODULES) as f32;
    let fit = side as f32 / total;
    let module = if fit >= 1.0 { fit.floor() } else { fit };
    let offset = ((side as f32 - module * n as f32) / 2.0).floor();
    let mut pb = tiny_skia::PathBuilder::new();
    for y in 0..n {
        for x in 0..n {
            if dark[y * n + x] {
                let r =
                    tiny_skia::Rect::from_xywh(offset + x as f32 * module, offset + y as f32 * module, module, module);
                if let Some(r) = r {
                    pb.push_rect(r);
                }
            }
        }
    }
    if let Some(path) = pb.finish() {
        let mut paint = tiny_skia::Paint::default();
        paint.set_color_rgba8(0, 0, 0, 255);
        paint.anti_alias = module < 1.0;
        pm.fill_path(&path, &paint, tiny_skia::FillRule::Winding, ID, None);
    }
    // A thin frame so the card reads as a printed label against bright scenes.
    if let Some(border) = geom::rect(0.5, 0.5, side as f32 - 1.0, side as f32 - 1.0) {
        super::stroke(&mut pm, &border, [120, 120, 120, 255], 1.0, ID);
    }
    Ok(pm)
}
