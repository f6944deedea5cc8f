//! Inserting a cue into a frame: the embeddable API of the three insertion modes.
//!
//! The caller owns the frame and the simulator; it passes the frame, a [`CueSpec`] and
//! [`FrameInputs`] (projected anchors, and for F3/F4 the RGBA layers or pictures it rendered).
//! An [`Inserter`] keeps a cache of everything static per cue (text, codes, signs, panel
//! frames) keyed by the spec, its parameters and the frame size, so after the first frame only
//! compositing is left. It also keeps the last drawn layers of scene-anchored cues: a fixed
//! camera sees its anchors unchanged until the object moves, and a layer drawn from the same
//! spec, size and anchor bits is the same layer.
//!
//! # Anchors outside the image (scene-anchored cues)
//!
//! * An anchor inside the image is used as is.
//! * An anchor in front of the camera but outside the image is **clamped** to the image border,
//!   inset by 6 % of the shorter side, where the line from the image centre to it crosses that
//!   border (so an arrow to it keeps its direction); the cue is drawn at the clamped point and
//!   an **off-screen indicator** (a small triangle pointing towards the true position, in the
//!   cue's colour with a white rim) is added there. (The paper drops such anchors; clamping
//!   keeps the cue drawn in the wrist camera, where targets are often out of view.)
//! * An anchor behind the camera, non-finite, or not given is **skipped**: parts of the cue
//!   that need it are not drawn (an arrow needs both ends); parts that need only the other
//!   anchor still are. If nothing is left, the frame is unchanged and the report says
//!   `drawn: false`.
//!
//! [`InsertReport`] says for each anchor which rule applied.

use crate::draw::geom::ID;
use std::collections::HashMap;
use std::sync::Arc;

use serde::Serialize;
use tiny_skia::Pixmap;

use crate::anchors::{Anchor, Anchors};
use crate::draw::geom::{V2, v2};
use crate::draw::{self, Rgba};
use crate::error::CueError;
use crate::image::{RgbImage, RgbaImage};
use crate::spec::{CueSpec, NormBox};

/// Per-frame inputs besides the frame itself.
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameInputs<'a> {
    /// Projected source and target (scene-anchored cues).
    pub anchors: Anchors,
    /// F3: the manipulated object rendered at K future poses from the same camera, one RGBA
    /// layer per pose (transparent elsewhere), in time order, each the size of the frame.
    pub ghost_layers: &'a [RgbaImage],
    /// F4: keyframes of a demonstration in time order; the first is the start, the last the
    /// goal state. Goal panels need one, before/after panels two.
    pub pictures: &'a [RgbaImage],
}

impl<'a> FrameInputs<'a> {
    /// Inputs with anchors only.
    pub fn anchored(anchors: Anchors) -> FrameInputs<'a> {
        FrameInputs { anchors, ..FrameInputs::default() }
    }
}

/// What happened to an anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AnchorUse {
    /// The cue does not use this anchor.
    NotUsed,
    /// Inside the image.
    InView,
    /// Outside the image; drawn at the border with an off-screen indicator.
    Clamped,
    /// Behind the camera, non-finite or missing; the parts needing it were skipped.
    Skipped,
}

/// Outcome of one insertion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct InsertReport {
    pub source: AnchorUse,
    pub target: AnchorUse,
    /// Whether anything was drawn.
    pub drawn: bool,
}

/// Which anchor a cue element refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    Source,
    Target,
}

/// An anchor resolved for drawing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    /// Where to draw (the anchor, or its clamped position).
    pub at: V2,
    /// Projected radius, or a size-dependent default.
    pub radius: f32,
}

/// Maximum number of cached assets before the cache is emptied (bounded memory when a
/// long-running process cycles through many specs).
const CACHE_LIMIT: usize = 512;

/// Drawn layers kept for the next frames: one per camera of an episode.
const DRAWN_KEPT: usize = 2;

/// Inserts cues into frames, caching static parts between calls. One per thread.
#[derive(Default)]
pub struct Inserter {
    cache: HashMap<String, Arc<Pixmap>>,
    /// The scratch layer, transparent.
    layer: Option<Pixmap>,
    /// The latest layers drawn from the anchors alone, oldest first.
    drawn: Vec<Drawn>,
}

/// A finished layer of a cue that drew only into its layer, with what it was drawn from.
struct Drawn {
    key: String,
    anchors: Anchors,
    layer: Pixmap,
    dirty: bool,
    report: InsertReport,
}

/// Equal anchors, bit for bit (a NaN anchor included).
fn same_anchors(a: &Anchors, b: &Anchors) -> bool {
    let bits = |x: &Option<Anchor>| x.map(|a| (a.u.to_bits(), a.v.to_bits(), a.radius.map(f64::to_bits), a.in_front));
    bits(&a.source) == bits(&b.source) && bits(&a.target) == bits(&b.target)
}

impl Inserter {
    pub fn new() -> Inserter {
        Inserter::default()
    }

    /// Draws the cue described by `spec` into `frame`. On error the frame is unchanged.
    pub fn insert(
        &mut self,
        frame: &mut RgbImage,
        spec: &CueSpec,
        inputs: &FrameInputs<'_>,
    ) -> Result<InsertReport, CueError> {
        frame.validate()?;
        let variant = spec.check()?;
        for (i, l) in inputs.ghost_layers.iter().enumerate() {
            l.validate().map_err(|source| CueError::Input { what: format!("ghost layer {i}"), source })?;
            if (l.width, l.height) != (frame.width, frame.height) {
                return Err(CueError::BadParam(format!(
                    "ghost layer {i} is {}x{}, the frame {}x{}",
                    l.width, l.height, frame.width, frame.height
                )));
            }
        }
        for (i, p) in inputs.pictures.iter().enumerate() {
            p.validate().map_err(|source| CueError::Input { what: format!("picture {i}"), source })?;
        }
        if self.cache.len() > CACHE_LIMIT {
            self.cache.clear();
        }
        // The whole spec, not only its id: a caller may give one task key to specs of other
        // instructions or objects, whose captions, codes and labels differ.
        let key_prefix = format!(
            "{}|{:016x}|{}x{}",
            spec.id(),
            crate::hash::fnv1a64(&serde_json::to_vec(spec).unwrap_or_default()),
            frame.width,
            frame.height
        );
        // Only the anchors vary between frames of a cue without ghost layers or pictures.
        let from_anchors = inputs.ghost_layers.is_empty() && inputs.pictures.is_empty();
        if from_anchors {
            let same = |d: &Drawn| d.key == key_prefix && same_anchors(&d.anchors, &inputs.anchors);
            if let Some(i) = self.drawn.iter().position(same) {
                let d = self.drawn.remove(i);
                if d.dirty {
                    draw::composite(frame, &d.layer, 0, 0);
                }
                let report = d.report;
                self.drawn.push(d);
                return Ok(report);
            }
        }
        let layer = match self.layer.take() {
            Some(l) if (l.width(), l.height()) == (frame.width, frame.height) => l,
            _ => Pixmap::new(frame.width, frame.height).ok_or(CueError::BadParam("frame too large".into()))?,
        };
        let mut ctx = Ctx {
            frame,
            spec,
            inputs,
            cache: &mut self.cache,
            key_prefix,
            layer,
            layer_dirty: false,
            frame_touched: false,
            report: InsertReport { source: AnchorUse::NotUsed, target: AnchorUse::NotUsed, drawn: false },
            clamped: Vec::new(),
        };
        let result = (variant.draw)(&mut ctx);
        let Ctx { mut layer, mut layer_dirty, frame_touched, report, clamped, key_prefix, .. } = ctx;
        if result.is_ok() && report.drawn {
            for (at, toward, color) in clamped {
                draw_offscreen_indicator(&mut layer, at, toward, color, frame.width.min(frame.height) as f32 / 256.0);
                layer_dirty = true;
            }
        }
        if result.is_ok() && layer_dirty {
            draw::composite(frame, &layer, 0, 0);
        }
        if result.is_ok() && from_anchors && !frame_touched {
            // Keep the layer; the oldest kept one becomes the scratch layer.
            self.drawn.push(Drawn { key: key_prefix, anchors: inputs.anchors, layer, dirty: layer_dirty, report });
            if self.drawn.len() <= DRAWN_KEPT {
                return Ok(report);
            }
            let oldest = self.drawn.remove(0);
            (layer, layer_dirty) = (oldest.layer, oldest.dirty);
        }
        if layer_dirty {
            layer.fill(tiny_skia::Color::TRANSPARENT);
        }
        self.layer = Some(layer);
        result.map(|()| report)
    }
}

/// Everything a variant's draw function needs.
pub struct Ctx<'a> {
    frame: &'a mut RgbImage,
    pub spec: &'a CueSpec,
    pub inputs: &'a FrameInputs<'a>,
    cache: &'a mut HashMap<String, Arc<Pixmap>>,
    key_prefix: String,
    layer: Pixmap,
    layer_dirty: bool,
    /// Whether the variant drew into the frame itself: its result then depends on the frame.
    frame_touched: bool,
    report: InsertReport,
    clamped: Vec<(V2, V2, Rgba)>,
}

impl Ctx<'_> {
    /// Frame width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.frame.width, self.frame.height)
    }

    /// Size factor: the shorter frame side over 256 (the design size), times `params.scale`.
    pub fn scale(&self) -> f32 {
        self.frame.width.min(self.frame.height) as f32 / 256.0 * self.spec.params.scale.unwrap_or(1.0)
    }

    /// `params.color` or the variant's default.
    pub fn color(&self, default: [u8; 3]) -> Rgba {
        draw::rgb(self.spec.params.color.unwrap_or(default))
    }

    /// The full-frame drawing layer for scene-anchored and ghost cues, composited after the
    /// variant returns.
    pub fn layer(&mut self) -> &mut Pixmap {
        self.layer_dirty = true;
        self.report.drawn = true;
        &mut self.layer
    }

    /// Resolves an anchor under the off-screen rule (module docs). `color` tints the
    /// off-screen indicator if the anchor had to be clamped.
    pub fn place(&mut self, which: Which, color: Rgba) -> Option<Placed> {
        let anchor: Option<Anchor> = match which {
            Which::Source => self.inputs.anchors.source,
            Which::Target => self.inputs.anchors.target,
        };
        let (w, h) = self.size();
        let default_radius = 12.0 * self.scale();
        // A spec without a target has nothing to anchor there: not a skip.
        let anchor = if which == Which::Target && self.spec.target.is_none() { None } else { anchor };
        let unused = which == Which::Target && self.spec.target.is_none();
        let (use_, placed) = match anchor {
            Some(a) if a.usable() => {
                let radius = a.radius.map_or(default_radius, |r| (r as f32).clamp(2.0, (w.max(h) as f32).max(2.0)));
                let truth = v2(a.u as f32, a.v as f32);
                if a.inside(w, h) {
                    (AnchorUse::InView, Some(Placed { at: truth, radius }))
                } else {
                    let m = 0.06 * w.min(h) as f32;
                    let at = toward(truth, w as f32, h as f32, m);
                    self.clamped.push((at, truth, color));
                    (AnchorUse::Clamped, Some(Placed { at, radius: radius.min(m) }))
                }
            }
            _ if unused => (AnchorUse::NotUsed, None),
            _ => (AnchorUse::Skipped, None),
        };
        let slot = match which {
            Which::Source => &mut self.report.source,
            Which::Target => &mut self.report.target,
        };
        // An anchor asked for twice keeps its first verdict.
        if *slot == AnchorUse::NotUsed {
            *slot = use_;
        }
        placed
    }

    /// The cue's target anchor when the spec has a target, else its source: for cues that
    /// mark "where to act" (crosshairs, washes, zone signs).
    pub fn place_goal(&mut self, color: Rgba) -> Option<Placed> {
        if self.spec.target.is_some() { self.place(Which::Target, color) } else { self.place(Which::Source, color) }
    }

    /// A static asset for this spec and frame size, built on first use. `part` distinguishes
    /// several assets of one cue.
    pub fn cached(
        &mut self,
        part: &str,
        build: impl FnOnce() -> Result<Pixmap, CueError>,
    ) -> Result<Arc<Pixmap>, CueError> {
        let key = format!("{}|{part}", self.key_prefix);
        if let Some(p) = self.cache.get(&key) {
            return Ok(Arc::clone(p));
        }
        let p = Arc::new(build()?);
        self.cache.insert(key, Arc::clone(&p));
        Ok(p)
    }

    /// The frame itself, for cues that blend into it directly (ghost layers).
    pub fn frame_mut(&mut self) -> &mut RgbImage {
        self.report.drawn = true;
        self.frame_touched = true;
        self.frame
    }

    /// Composites an asset straight onto the frame (fixed-region cues).
    pub fn blit(&mut self, pm: &Pixmap, x: i32, y: i32) {
        draw::composite(self.frame, pm, x, y);
        self.report.drawn = true;
        self.frame_touched = true;
    }

    /// The spec's fixed region (or `default`) in pixels.
    pub fn region(&self, default: NormBox) -> (i32, i32, u32, u32) {
        let (w, h) = self.size();
        self.spec.params.region.unwrap_or(default).to_pixels(w, h)
    }

    /// Error for a missing caller input.
    pub fn missing(&self, what: &str) -> CueError {
        CueError::MissingInput { variant: self.spec.variant.clone(), what: what.to_string() }
    }
}

/// A triangle at `at` pointing towards `toward` (the true, off-screen anchor position).
fn draw_offscreen_indicator(pm: &mut Pixmap, at: V2, toward: V2, color: Rgba, s: f32) {
    let dir = toward.sub(at).unit();
    let size = 11.0 * s;
    let tip = at.add(dir.scale(size * 0.6));
    if let Some(p) = draw::geom::arrow_head(tip, dir, size, size) {
        draw::fill_outlined(pm, &p, color, draw::WHITE, 1.2 * s, ID);
    }
}

/// Where the line from the centre of a `w`×`h` image to `truth` (outside it) crosses the border
/// inset by `m`: clamping x and y apart would send every far point to a corner, turning an
/// arrow towards it by up to 45°.
fn toward(truth: V2, w: f32, h: f32, m: f32) -> V2 {
    let centre = v2(w / 2.0, h / 2.0);
    let d = truth.sub(centre);
    let reach = |half: f32, along: f32| if along == 0.0 { f32::INFINITY } else { (half - m).max(0.0) / along.abs() };
    centre.add(d.scale(reach(w / 2.0, d.x).min(reach(h / 2.0, d.y)).min(1.0)))
}
