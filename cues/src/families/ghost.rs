//! F3 ghost trajectories (simulator-state overlay): the caller renders the manipulated object
//! at K future poses from the current camera, one RGBA layer each, and these are composited
//! onto the frame as Ĩ = Composite(I, {(G_i, α_i)}), earliest first.

use crate::draw::geom::ID;

use crate::draw::geom::{self, V2, v2};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::image::RgbaImage;
use crate::insert::{Ctx, Which};

/// α_i: `params.alphas` (one per layer), else a linear ramp from `first` to `last`.
fn alphas(ctx: &Ctx<'_>, k: usize, first: f32, last: f32) -> Result<Vec<f32>, CueError> {
    match &ctx.spec.params.alphas {
        Some(a) if a.len() == k => Ok(a.clone()),
        Some(a) => Err(CueError::BadParam(format!("{} alphas for {k} ghost layers", a.len()))),
        None if k == 1 => Ok(vec![last]),
        None => Ok((0..k).map(|i| first + (last - first) * i as f32 / (k - 1) as f32).collect()),
    }
}

fn layers<'a>(ctx: &Ctx<'a>) -> Result<&'a [RgbaImage], CueError> {
    let l = ctx.inputs.ghost_layers;
    if l.is_empty() { Err(ctx.missing("ghost layers (FrameInputs::ghost_layers)")) } else { Ok(l) }
}

pub fn fade(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let layers = layers(ctx)?;
    let a = alphas(ctx, layers.len(), 0.25, 0.65)?;
    let tint = ctx.spec.params.color.map(|c| (c, 0.35));
    let frame = ctx.frame_mut();
    for (layer, alpha) in layers.iter().zip(a) {
        draw::composite_rgba(frame, layer, alpha, tint);
    }
    Ok(())
}

/// Outline pixels of a layer's silhouette (alpha ≥ 128): inside pixels whose (2t+1)²
/// neighbourhood leaves the silhouette. Returns the pixel indices; work is limited to the
/// silhouette's bounding box, which is small next to the frame.
fn outline_pixels(layer: &RgbaImage, t: usize) -> Vec<usize> {
    let (w, h) = (layer.width as usize, layer.height as usize);
    let inside = |x: usize, y: usize| layer.data[(y * w + x) * 4 + 3] >= 128;
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    for (i, p) in draw::pixels_not_clear(&layer.data) {
        if p[3] >= 128 {
            let (x, y) = (i % w, i / w);
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    if x0 > x1 {
        return Vec::new();
    }
    // Erosion by a square, separably: a pixel survives horizontally if its whole row window
    // is inside (pixels at the image edge never survive).
    let bw = x1 - x0 + 1;
    let mut horiz = vec![false; bw * (y1 - y0 + 1)];
    for y in y0..=y1 {
        for x in x0..=x1 {
            horiz[(y - y0) * bw + x - x0] = x >= t && x + t < w && (x - t..=x + t).all(|xx| inside(xx, y));
        }
    }
    let survives = |x: usize, y: usize| y >= y0 && y <= y1 && horiz[(y - y0) * bw + x - x0];
    let mut out = Vec::new();
    for y in y0..=y1 {
        for x in x0..=x1 {
            if inside(x, y) && !(y >= t && y + t < h && (y - t..=y + t).all(|yy| survives(x, yy))) {
                out.push(y * w + x);
            }
        }
    }
    out
}

pub fn outline(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let layers = layers(ctx)?;
    let a = alphas(ctx, layers.len(), 0.55, 1.0)?;
    let color = ctx.color([0, 235, 255]);
    let t = (1.6 * ctx.scale()).round().max(1.0) as usize;
    let frame = ctx.frame_mut();
    for (layer, alpha) in layers.iter().zip(a) {
        let op = (alpha.clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
        for i in outline_pixels(layer, t) {
            let d = &mut frame.data[i * 3..i * 3 + 3];
            for c in 0..3 {
                d[c] = ((color[c] as u32 * op + d[c] as u32 * (255 - op) + 127) / 255) as u8;
            }
        }
    }
    Ok(())
}

/// Alpha-weighted centre of a layer's silhouette.
fn centroid(layer: &RgbaImage) -> Option<V2> {
    let (mut sx, mut sy, mut sw) = (0u64, 0u64, 0u64);
    let w = layer.width as u64;
    for (i, p) in draw::pixels_not_clear(&layer.data) {
        let a = p[3] as u64;
        if a > 0 {
            sx += (i as u64 % w) * a;
            sy += (i as u64 / w) * a;
            sw += a;
        }
    }
    (sw > 0).then(|| v2(sx as f32 / sw as f32 + 0.5, sy as f32 / sw as f32 + 0.5))
}

pub fn trail_path(ctx: &mut Ctx<'_>) -> Result<(), CueError> {
    let layers = layers(ctx)?;
    let a = alphas(ctx, layers.len(), 0.15, 0.45)?;
    let color: Rgba = ctx.color([255, 120, 30]);
    let s = ctx.scale();
    let frame = ctx.frame_mut();
    for (layer, alpha) in layers.iter().zip(a) {
        draw::composite_rgba(frame, layer, alpha, None);
    }
    // The trail starts at the object itself where its anchor is known, then runs through the
    // ghosts' centres.
    let start = ctx.place(Which::Source, color).map(|p| p.at);
    let centres: Vec<V2> = start.into_iter().chain(layers.iter().filter_map(centroid)).collect();
    if centres.len() < 2 {
        return Ok(());
    }
    let pm = ctx.layer();
    let last = centres[centres.len() - 1];
    let dir = last.sub(centres[centres.len() - 2]);
    let neck = last.sub(dir.unit().scale(8.0 * s));
    let mut points = centres[..centres.len() - 1].to_vec();
    points.push(neck);
    if let Some(p) = geom::polyline(&points) {
        draw::stroke(pm, &p, [20, 20, 20, 255], 5.0 * s, ID);
        draw::stroke(pm, &p, color, 2.8 * s, ID);
    }
    for c in &centres[..centres.len() - 1] {
        if let Some(p) = geom::circle(*c, 3.0 * s) {
            draw::fill_outlined(pm, &p, color, [20, 20, 20, 255], 1.0 * s, ID);
        }
    }
    if let Some(p) = geom::arrow_head(last, dir, 12.0 * s, 12.0 * s) {
        draw::fill_outlined(pm, &p, color, [20, 20, 20, 255], 1.2 * s, ID);
    }
    Ok(())
}
