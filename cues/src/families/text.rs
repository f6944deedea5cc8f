//! F1 text overlays (fixed-region): the instruction (or `params.text`) in a reserved box. The
//! whole overlay is rasterised once per spec and frame size and then only composited.

use tiny_skia::{FilterQuality, Pixmap, PixmapPaint};

use super::canvas;
use crate::draw::geom::{self, v2};
use crate::draw::text::{Align, Face, block_path, fit};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::insert::Ctx;
use crate::spec::NormBox;

use crate::draw::geom::ID;

/// Rasterises `text` centred in a `w` × `h` box with padding, optional background and an
/// optional outline around the letters.
fn text_box(
    text: &str,
    w: u32,
    h: u32,
    face: Face,
    fg: Rgba,
    bg: Option<Rgba>,
    outline: Option<Rgba>,
) -> Result<Pixmap, CueError> {
    let mut pm = canvas(w, h)?;
    let (wf, hf) = (w as f32, h as f32);
    if let Some(bg) = bg
        && let Some(p) = geom::rect(0.0, 0.0, wf, hf)
    {
        draw::fill(&mut pm, &p, bg, ID);
    }
    let pad = (hf * 0.1).max(2.0);
    let b = fit(face, text, wf - 2.0 * pad, hf - 2.0 * pad, 6.0, (hf * 0.38).max(6.0));
    if let Some(p) = block_path(&b, pad, (hf - b.height) / 2.0, wf - 2.0 * pad, Align::Center) {
        if let Some(o) = outline {
            draw::stroke(&mut pm, &p, o, (b.size * 0.18).max(1.5), ID);
        }
        draw::fill(&mut pm, &p, fg, ID);
    }
    Ok(pm)
}

pub fn caption_bar(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.0, 0.79, 1.0, 0.21));
    let fg = ctx.color([255, 255, 255]);
    let text = ctx.spec.payload_text().to_string();
    let pm = ctx.cached("caption", || text_box(&text, w, h, Face::SansBold, fg, Some([0, 0, 0, 175]), None))?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn top_banner(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.0, 0.0, 1.0, 0.2));
    let bg = ctx.color([250, 204, 21]);
    let text = ctx.spec.payload_text().to_string();
    let pm = ctx.cached("banner", || {
        let mut pm = text_box(&text, w, h, Face::SansBold, [15, 15, 15, 255], Some(bg), None)?;
        let t = (h as f32 * 0.05).max(1.5);
        if let Some(p) = geom::rect(0.0, h as f32 - t, w as f32, t) {
            draw::fill(&mut pm, &p, [40, 40, 40, 255], ID);
        }
        Ok(pm)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}

pub fn sticky_note(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let (x, y, w, h) = ctx.region(NormBox::new(0.55, 0.03, 0.42, 0.36));
    let paper = ctx.color([255, 238, 120]);
    let text = ctx.spec.payload_text().to_string();
    let pm = ctx.cached("note", || {
        // Draw the note upright, slightly smaller than the region, then tilt it by 4°.
        let (nw, nh) = ((w as f32 * 0.9) as u32, (h as f32 * 0.88) as u32);
        let mut note = canvas(nw, nh)?;
        let (fw, fh) = (nw as f32, nh as f32);
        let fold = fw.min(fh) * 0.16;
        if let Some(p) = geom::polygon(&[v2(0.0, 0.0), v2(fw, 0.0), v2(fw, fh - fold), v2(fw - fold, fh), v2(0.0, fh)])
        {
            draw::fill(&mut note, &p, paper, ID);
        }
        if let Some(p) = geom::polygon(&[v2(fw, fh - fold), v2(fw - fold, fh - fold), v2(fw - fold, fh)]) {
            draw::fill(&mut note, &p, [200, 178, 70, 255], ID);
        }
        let inner = text_box(&text, nw, (fh * 0.9) as u32, Face::Note, [22, 44, 128, 255], None, None)?;
        note.draw_pixmap(0, (fh * 0.08) as i32, inner.as_ref(), &PixmapPaint::default(), ID, None);
        let mut out = canvas(w, h)?;
        let angle = -4.0f32.to_radians();
        let centre = v2(w as f32 / 2.0, h as f32 / 2.0);
        let place = geom::rotate_translate(angle, centre).pre_translate(-fw / 2.0, -fh / 2.0);
        // Drop shadow, then the note.
        if let Some(shape) = geom::rect(0.0, 0.0, fw, fh) {
            draw::fill(&mut out, &shape, [0, 0, 0, 60], place.post_translate(2.0, 3.0));
        }
        let paint = PixmapPaint { quality: FilterQuality::Bilinear, ..PixmapPaint::default() };
        out.draw_pixmap(0, 0, note.as_ref(), &paint, place, None);
        if let Some(p) = geom::circle(v2(w as f32 / 2.0, h as f32 * 0.1), (w.min(h) as f32 * 0.035).max(2.0)) {
            draw::fill_outlined(&mut out, &p, [210, 40, 40, 255], [120, 20, 20, 255], 0.8, ID);
        }
        Ok(out)
    })?;
    ctx.blit(&pm, x, y);
    Ok(())
}
