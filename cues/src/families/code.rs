//! F8 machine-readable codes (fixed-region): QR codes of the instruction or of a JSON task
//! description, a Code 128 barcode of a compact action code, and a VIFO-36 fiducial tag.
//! Codes are encoded once per spec and frame size (cached).

use qrcode::EcLevel;
use serde_json::json;
use tiny_skia::{Pixmap, PixmapPaint};

use super::{canvas, head_noun};
use crate::draw::text::{Align, Face, block_path, fit};
use crate::draw::{self, barcode, fiducial, geom, qr};
use crate::error::CueError;
use crate::insert::Ctx;
use crate::spec::{CueSpec, NormBox};

use crate::draw::geom::ID;

/// The JSON payload of `qr_json`: task key and every step.
pub fn json_payload(spec: &CueSpec) -> String {
    let steps: Vec<_> = spec
        .steps
        .iter()
        .map(|s| {
            let mut o = json!({ "source": s.source, "relation": s.relation });
            // Which of two alike objects is meant (libero_spatial's two black bowls).
            if let Some(q) = &s.source_qualifier {
                o["source_qualifier"] = json!(q);
            }
            if let Some(t) = &s.target {
                o["target"] = json!(t);
            }
            o
        })
        .collect();
    json!({ "task": spec.task, "steps": steps }).to_string()
}

/// The compact action code of `barcode_code128`: RELATION:SOURCE>TARGET in capitals, using
/// head nouns ("ON:BOWL>PLATE", "TURN_ON:STOVE"), at most 24 characters.
pub fn action_code(spec: &CueSpec) -> String {
    let mut code = format!("{}:{}", spec.relation.name(), head_noun(&spec.source));
    if let Some(t) = &spec.target {
        code.push('>');
        code.push_str(head_noun(t));
    }
    code.to_ascii_uppercase().chars().filter(|c| (' '..='~').contains(c)).take(24).collect()
}

/// The fiducial id of a spec: FNV-1a of "relation|source|target" modulo the codebook size.
pub fn fiducial_id(spec: &CueSpec) -> usize {
    let key = format!("{}|{}|{}", spec.relation.name(), spec.source, spec.target.as_deref().unwrap_or(""));
    (crate::hash::fnv1a64(key.as_bytes()) % fiducial::CODEBOOK_SIZE as u64) as usize
}

fn qr_card(payload: &str, w: u32, h: u32) -> Result<Pixmap, CueError> {
    let side = w.min(h);
    qr::render(payload, EcLevel::L, side).map_err(|e| CueError::Encode(e.to_string()))
}

pub fn qr_instruction(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.64, 0.62, 0.34, 0.34));
    let text = ctx.spec.payload_text().to_string();
    let pm = ctx.cached("qr", || qr_card(&text, w, h))?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn qr_json(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.02, 0.02, 0.42, 0.42));
    let payload = json_payload(ctx.spec);
    let pm = ctx.cached("qr_json", || qr_card(&payload, w, h))?;
    ctx.blit(&pm, x, y);
    Ok(())
}

/// A white label: bars over the top 68 %, the code in monospace below.
pub fn barcode(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.03, 0.8, 0.94, 0.18));
    let code = ctx.spec.params.text.clone().unwrap_or_else(|| action_code(ctx.spec));
    let pm = ctx.cached("barcode", || {
        let bars = barcode::modules(&code).map_err(|e| CueError::Encode(e.to_string()))?;
        let mut pm = canvas(w, h)?;
        pm.fill(tiny_skia::Color::WHITE);
        let (wf, hf) = (w as f32, h as f32);
        let pad = (hf * 0.08).max(1.0);
        barcode::draw(&mut pm, &bars, 0.0, pad, wf, hf * 0.62);
        let b = fit(Face::MonoBold, &code, wf * 0.9, hf * 0.3 - pad, 5.0, hf * 0.28);
        if let Some(p) = block_path(&b, wf * 0.05, hf * 0.64 + pad * 0.5, wf * 0.9, Align::Center) {
            draw::fill(&mut pm, &p, draw::BLACK, ID);
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

/// The tag with its family name and id printed under it.
/// The smallest tag drawn (pixels a side): its 6×6 cells need at least one pixel plus a border.
const MIN_TAG: u32 = 10;

pub fn fiducial(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.74, 0.02, 0.24, 0.3));
    let id = fiducial_id(ctx.spec);
    let pm = ctx.cached("tag", || {
        let side = w.min((h as f32 * 0.8) as u32);
        if side < MIN_TAG {
            return Err(CueError::BadParam(format!("the tag's region is {w}x{h} pixels: a fiducial tag needs {MIN_TAG} across (a larger frame)")));
        }
        let tag = fiducial::render(id, side).ok_or_else(|| CueError::BadParam("empty tag region".into()))?;
        let mut pm = canvas(w, h)?;
        let left = ((w - side) / 2) as i32;
        pm.draw_pixmap(left, 0, tag.as_ref(), &PixmapPaint::default(), ID, None);
        let caption_h = h as f32 - side as f32;
        if let Some(p) = geom::rect(left as f32, side as f32, side as f32, caption_h) {
            draw::fill(&mut pm, &p, draw::WHITE, ID);
        }
        let b = fit(Face::MonoBold, &format!("VIFO36 #{id}"), side as f32 * 0.9, caption_h * 0.9, 4.0, caption_h * 0.7);
        if let Some(p) = block_path(
            &b,
            left as f32 + side as f32 * 0.05,
            side as f32 + (caption_h - b.height) / 2.0,
            side as f32 * 0.9,
            Align::Center,
        ) {
            draw::fill(&mut pm, &p, draw::BLACK, ID);
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}
