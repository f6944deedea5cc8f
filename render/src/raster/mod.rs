//! The z-buffer renderer.
//!
//! One frame runs in five steps, single-threaded, with buffers reused between frames:
//! 1. **Geometry** ([`assemble`]). Instances outside the view frustum (bounding sphere test) are
//!    skipped; the rest are sorted front to back. An instance, or a cluster of a clustered mesh
//!    ([`crate::Mesh::clustered`]), is skipped whole when what was drawn before it hides it
//!    ([`hiz`]); a cluster also when it lies outside the view or its normal cone faces away. The
//!    vertices drawn are transformed into camera space once, eight at a time ([`vertex`]), with
//!    outcodes for trivial rejection and clipping. Triangles are back-face culled in exact fixed
//!    point, near-plane (and guard-band) clipped when needed, and only the vertices of triangles
//!    that cover a pixel centre in front of what is already drawn are lit (per vertex,
//!    [`lighting`]): the winners of a cluster wait for their records until its vertices are lit
//!    eight at a time.
//! 2. **Visibility** ([`opaque`]). Opaque triangles are rasterized depth-only into a visibility
//!    buffer: per pixel, `1/z` and the index of the nearest triangle ([`triangle`] does exact
//!    coverage at pixel centres). A large triangle that the hi-z shows hidden is skipped before its
//!    pixels are tested.
//! 3. **Resolve** ([`resolve`]). Each pixel is shaded once from its triangle's screen-space
//!    attribute planes (perspective-correct colour and UV), textured, and written with depth and
//!    segment id; uncovered pixels get the background.
//! 4. **Transparency** ([`blend`]). Instances with alpha < 1 are blended back to front over the
//!    result.
//! 5. **Reflection** ([`mirror`]). Where the scene has a [`Mirror`](crate::Mirror) and its face is
//!    visible, the scene is drawn again from the camera mirrored in the face's plane (clipped to
//!    the plane's outer side) and added to the face's pixels.
//!
//! Steps 1–3 keep, per camera, a [`layer`] of the instances that did not move since the last
//! frame, so that a fixed camera draws only what moved; the pixels come out the same.

mod assemble;
mod blend;
mod clip;
mod hiz;
mod layer;
mod lighting;
mod mirror;
mod opaque;
mod resolve;
mod shadow;
mod triangle;
mod vertex;
mod view;

use glam::Vec2;
use thiserror::Error;

use self::assemble::{Assembled, Deferred, LitCache};
use self::clip::{Polygon, SphereClass};
use self::hiz::HiZ;
use self::layer::{Buffers, Layers, PixelBox, Plan};
use self::lighting::{LightRig, Lit};
use self::shadow::ShadowMap;
use self::triangle::Plane;
use self::vertex::Verts;
use self::view::View;
use crate::camera::Camera;
use crate::frame::Frame;
use crate::scene::Scene;
use crate::transform::mul_mat3;

/// Largest accepted image side (pixels), after supersampling.
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// Renderer settings. The defaults match what LIBERO renders: no shadows (its scene lights
/// have `castshadow="false"`), no supersampling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Shadow mapping for the first light with `cast_shadow` (one light at most).
    pub shadows: bool,
    /// Side of the square shadow map in texels.
    pub shadow_map_size: u32,
    /// Render `k × k` samples per pixel and average the colours (1 = off, at most 8). Depth and
    /// segmentation come from the sample at offset `(k/2, k/2)` of each block, which is the
    /// pixel centre for odd `k`.
    pub supersample: u32,
    /// Keep what a camera saw of the instances that did not move, and draw only the others in
    /// its next frame (the static layer). Changes no pixel; off, every frame is drawn whole.
    pub static_layer: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { shadows: false, shadow_map_size: 1024, supersample: 1, static_layer: true }
    }
}

/// Counts from the last frame, for benchmarks and tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Instances inside the view frustum.
    pub instances_drawn: usize,
    /// Instances skipped by frustum culling (or for non-finite transforms).
    pub instances_culled: usize,
    /// Triangles of the drawn instances.
    pub triangles_in_view: usize,
    /// Screen triangles that passed culling and covered at least one pixel centre.
    pub triangles_rasterized: usize,
    /// Vertices lit: only those of triangles that cover a pixel centre in front of what was
    /// drawn before them.
    pub vertices_lit: usize,
    /// Triangle clusters of clustered meshes skipped whole: outside the view or facing away.
    pub clusters_culled: usize,
    /// Clusters and instances skipped whole because what was drawn before hides them.
    pub hidden: usize,
    /// Large triangles (counted in `triangles_rasterized`) skipped before their pixels were
    /// depth-tested, because what was drawn before hides them.
    pub triangles_hidden: usize,
    /// Instances inside the view (counted in `instances_drawn`) that came from the camera's
    /// static layer: taken from it, or, in a frame that rebuilt it, drawn into it.
    pub instances_reused: usize,
}

impl RenderStats {
    fn add(&mut self, a: Assembled) {
        self.vertices_lit += a.lit;
        self.clusters_culled += a.culled;
        self.hidden += a.hidden;
    }
}

/// Why a frame could not be rendered.
#[derive(Debug, Error, PartialEq)]
pub enum RenderError {
    #[error("invalid camera: {0}")]
    InvalidCamera(String),
}

/// A vertex on screen, ready for triangle setup.
#[derive(Clone, Copy)]
struct ScreenVert {
    xy: (i64, i64),
    iz: f32,
    lit: Lit,
    uv: Vec2,
}

/// Everything the resolve and blend passes need to shade a pixel of one triangle.
#[derive(Clone, Copy)]
struct TriRecord {
    /// `1/z`, and colour and UV premultiplied by `1/z` (perspective-correct interpolation).
    iz: Plane,
    rgb: [Plane; 3],
    uv: [Plane; 2],
    instance: u32,
    segment: u32,
    /// Mip level, or `u32::MAX` when untextured.
    mip: u32,
    /// Material opacity (used when blending).
    alpha: f32,
}

const NO_TRIANGLE: u32 = u32::MAX;

/// An instance that survived frustum culling.
#[derive(Clone, Copy)]
struct Visible {
    /// View depth of its bounding sphere's centre (the drawing order key).
    depth: f32,
    index: u32,
    /// Its bounding sphere lies wholly inside the view: no per-vertex outcodes needed.
    inside: bool,
}

/// A software rasterizer with its reusable buffers. One renderer per thread; scenes are shared.
#[derive(Default)]
pub struct Renderer {
    options: RenderOptions,
    stats: RenderStats,
    rig: LightRig,
    shadow: ShadowMap,
    shadows_active: bool,
    /// Visibility buffer: `1/z` (0 = empty) and triangle index per pixel.
    depth: Vec<f32>,
    tri_id: Vec<u32>,
    hiz: HiZ,
    records: Vec<TriRecord>,
    /// Triangles of the instance being drawn that wait for their lit corners.
    deferred: Vec<Deferred>,
    /// Per-record colour of the shadow-casting light (only while shadows are active).
    shadow_rgb: Vec<[Plane; 3]>,
    verts: Verts,
    /// Lit colours, two slots (front, back) per vertex, and whether each is computed.
    lit: LitCache,
    poly: Polygon,
    order: Vec<Visible>,
    blended: Vec<Visible>,
    supersampled: Frame,
    /// The mirrored view, the pixels showing the mirror, and the same pixels in the mirrored
    /// view (reused between frames).
    reflected: Frame,
    mirror_pixels: Vec<u32>,
    mirrored_pixels: Vec<u32>,
    mirrored_scene: Scene,
    layers: Layers,
    /// The pixels that the instances drawn over a static layer won in this frame.
    touched: PixelBox,
}

impl Renderer {
    pub fn new(options: RenderOptions) -> Renderer {
        Renderer { options, ..Renderer::default() }
    }

    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    pub fn set_options(&mut self, options: RenderOptions) {
        self.options = options;
    }

    /// Counts from the last rendered frame.
    pub fn stats(&self) -> RenderStats {
        self.stats
    }

    /// Renders `scene` as seen by `camera` into a new frame.
    pub fn render(&mut self, scene: &Scene, camera: &Camera) -> Result<Frame, RenderError> {
        let mut frame = Frame::default();
        self.render_into(scene, camera, &mut frame)?;
        Ok(frame)
    }

    /// Renders into `frame`, reusing its memory (it is resized to the camera's image size).
    pub fn render_into(&mut self, scene: &Scene, camera: &Camera, frame: &mut Frame) -> Result<(), RenderError> {
        let k = self.options.supersample.clamp(1, 8);
        validate(camera, k)?;
        frame.resize(camera.width, camera.height);
        if k == 1 {
            self.render_view(scene, camera, frame);
        } else {
            let mut hi = std::mem::take(&mut self.supersampled);
            let hi_cam = camera.scaled(k);
            hi.resize(hi_cam.width, hi_cam.height);
            self.render_view(scene, &hi_cam, &mut hi);
            downsample(&hi, k, frame);
            self.supersampled = hi;
        }
        Ok(())
    }

    /// Renders only the pixels that `scene`'s instances cover, for a layer of a few small things
    /// (an object alone at one pose): returns their bounding box `[x0, y0, x1, y1]` (inclusive),
    /// `None` where nothing is seen. Inside the box the pixels of `frame` (resized to the
    /// camera's image size) are those of [`Renderer::render_into`]; outside it they are left as
    /// they were. Only the box is shaded, so a small object costs little however large the
    /// image. A scene with transparent instances or a mirror, or supersampling, is drawn whole
    /// (the box is then the image).
    pub fn render_covered(&mut self, scene: &Scene, camera: &Camera, frame: &mut Frame) -> Result<Option<[u32; 4]>, RenderError> {
        let whole = self.options.supersample > 1 || scene.mirror.is_some() || scene.instances.iter().any(|i| i.material.is_transparent());
        if whole {
            self.render_into(scene, camera, frame)?;
            return Ok(Some([0, 0, camera.width - 1, camera.height - 1]));
        }
        validate(camera, 1)?;
        frame.resize(camera.width, camera.height);
        self.stats = RenderStats::default();
        self.draw_pass(scene, camera, &View::new(camera), frame, None, Plan::Covered);
        let drawn = self.touched;
        Ok((!drawn.is_empty()).then_some([drawn.x0, drawn.y0, drawn.x1, drawn.y1]))
    }

    fn render_view(&mut self, scene: &Scene, camera: &Camera, out: &mut Frame) {
        self.stats = RenderStats::default();
        // Shadows move with what casts them, over static surfaces too.
        let plan = if self.options.static_layer && !self.options.shadows { self.layers.plan(scene, camera) } else { Plan::Plain };
        let layered = !matches!(plan, Plan::Plain);
        self.draw_pass(scene, camera, &View::new(camera), out, None, plan);
        let moved = self.touched;
        if let Some(mirror) = &scene.mirror {
            self.reflect(scene, camera, mirror, out);
        }
        if layered {
            // The reflection's pass draws over the whole buffer.
            let dirty = scene.mirror.is_none().then_some(moved);
            let buffers = Buffers { depth: &mut self.depth, tri_id: &mut self.tri_id, records: &mut self.records };
            if let Some(layer) = self.layers.layer_mut() {
                layer.take_back(buffers, dirty);
            }
        }
    }

    /// Draws `scene` through `view` (of `camera`) into `out`: geometry, resolve, transparency.
    /// With `only`, just those pixels of the view (indices) are drawn; the rest keep the
    /// background. `plan` says which instances come from the camera's static layer.
    fn draw_pass(&mut self, scene: &Scene, camera: &Camera, view: &View, out: &mut Frame, only: Option<&[u32]>, plan: Plan) {
        self.shadows_active = self.options.shadows && self.shadow.build(scene, camera, self.options.shadow_map_size);
        self.rig.prepare(scene, camera, self.shadows_active);
        self.sort_instances(scene, view);
        let order = std::mem::take(&mut self.order);
        match plan {
            Plan::Plain | Plan::Covered => {
                self.clear(view, only);
                self.touched = PixelBox::EMPTY;
                for v in &order {
                    self.draw_opaque(scene, v, view, None);
                }
                let region = if matches!(plan, Plan::Covered) { self.touched } else { PixelBox::all(view.width, view.height) };
                self.resolve(scene, view, out, 0, region);
            }
            Plan::Rebuild(statics) => {
                self.clear(view, None);
                let mut layer = self.layers.spare();
                layer.order.clear();
                layer.order.resize(scene.instances.len(), f32::NAN);
                for v in order.iter().filter(|v| statics[v.index as usize]) {
                    layer.order[v.index as usize] = v.depth;
                    self.draw_opaque(scene, v, view, None);
                }
                layer.statics = statics;
                layer.image.resize(view.width, view.height);
                self.resolve(scene, view, &mut layer.image, 0, PixelBox::all(view.width, view.height));
                layer.depth.clone_from(&self.depth);
                layer.tri_id.clone_from(&self.tri_id);
                layer.records.clone_from(&self.records);
                layer.hiz.copy_from(&self.hiz);
                self.layers.store(layer);
                self.draw_moved(scene, view, out, &order);
            }
            Plan::Reuse => {
                if let Some(layer) = self.layers.layer_mut() {
                    layer.lend(Buffers { depth: &mut self.depth, tri_id: &mut self.tri_id, records: &mut self.records }, view.width);
                    self.hiz.copy_from(&layer.hiz);
                    self.shadow_rgb.clear();
                }
                self.draw_moved(scene, view, out, &order);
            }
        }
        self.order = order;
        let blended = std::mem::take(&mut self.blended);
        for v in &blended {
            self.draw_blended(scene, v, view, out);
        }
        self.blended = blended;
    }

    /// On the visibility buffer of the camera's static layer: starts `out` from the layer's
    /// pixels, then draws and shades the instances of `order` that are not in the layer.
    fn draw_moved(&mut self, scene: &Scene, view: &View, out: &mut Frame, order: &[Visible]) {
        let Some(layer) = self.layers.layer() else { return };
        out.color.data.copy_from_slice(&layer.image.color.data);
        out.depth.copy_from_slice(&layer.image.depth);
        out.segmentation.copy_from_slice(&layer.image.segmentation);
        let layer_records = layer.records.len() as u32;
        self.touched = PixelBox::EMPTY;
        for v in order {
            if self.layers.layer().is_some_and(|l| l.statics.get(v.index as usize) == Some(&true)) {
                self.stats.instances_reused += 1;
            } else {
                self.draw_opaque(scene, v, view, Some(layer_records));
            }
        }
        self.resolve(scene, view, out, layer_records, self.touched);
    }

    /// Empties the visibility buffer, records and hi-z for `view` (see [`Renderer::draw_pass`]
    /// for `only`).
    fn clear(&mut self, view: &View, only: Option<&[u32]>) {
        let n = view.width as usize * view.height as usize;
        self.depth.clear();
        self.depth.resize(n, 0.0);
        self.tri_id.clear();
        self.tri_id.resize(n, NO_TRIANGLE);
        self.hiz.reset(view.width, view.height);
        if let Some(only) = only {
            // The other pixels start nearer than anything can be (1/z = ∞): nothing is drawn
            // there, and the hi-z skips what would only show there.
            self.depth.fill(f32::INFINITY);
            for &q in only {
                self.depth[q as usize] = 0.0;
            }
            self.hiz.mark_all();
        }
        self.records.clear();
        self.shadow_rgb.clear();
    }

    /// Frustum-culls instances and orders them: opaque front to back, transparent back to front.
    fn sort_instances(&mut self, scene: &Scene, view: &View) {
        self.order.clear();
        self.blended.clear();
        for (idx, inst) in scene.instances.iter().enumerate() {
            let t = &inst.transform;
            let b = inst.mesh.bounds();
            let centre = mul_mat3(&view.rot, t.transform_point(b.center) - view.position);
            let radius = b.radius * t.max_scale();
            let finite = t.linear.is_finite() && t.translation.is_finite();
            let mut class = if finite { view.clip.classify_sphere(centre, radius, view.far) } else { SphereClass::Outside };
            if class == SphereClass::Straddles && view.box_hidden(t, b.center, inst.mesh.half_extent()) {
                class = SphereClass::Outside;
            }
            if class == SphereClass::Outside {
                self.stats.instances_culled += 1;
                continue;
            }
            let entry = Visible { depth: centre.z, index: idx as u32, inside: class == SphereClass::Inside };
            self.stats.instances_drawn += 1;
            self.stats.triangles_in_view += inst.mesh.triangle_count();
            if inst.material.is_transparent() {
                self.blended.push(entry);
            } else {
                self.order.push(entry);
            }
        }
        let by_key = |a: &Visible, b: &Visible| a.depth.total_cmp(&b.depth).then(a.index.cmp(&b.index));
        self.order.sort_unstable_by(by_key);
        self.blended.sort_unstable_by(|a, b| by_key(b, a));
    }
}

/// The tests' pseudo-random numbers, uniform in `[0, 1)`: the top 24 bits of the next state of
/// a 64-bit linear congruential generator (Knuth's MMIX constants).
#[cfg(test)]
pub(crate) fn next_unit(seed: &mut u64) -> f32 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 40) as f32 / (1u64 << 24) as f32
}


fn validate(c: &Camera, supersample: u32) -> Result<(), RenderError> {
    let bad = |m: String| Err(RenderError::InvalidCamera(m));
    if c.width == 0 || c.height == 0 || c.width.saturating_mul(supersample) > MAX_IMAGE_SIDE || c.height.saturating_mul(supersample) > MAX_IMAGE_SIDE {
        return bad(format!(
            "image size {}×{} (×{supersample} supersampling) must be between 1 and {MAX_IMAGE_SIDE} per side",
            c.width, c.height
        ));
    }
    if !(c.fovy_deg > 0.0 && c.fovy_deg < 180.0) {
        return bad(format!("fovy {}° must be strictly between 0 and 180", c.fovy_deg));
    }
    if !(c.position.is_finite() && c.rotation.is_finite()) {
        return bad("pose is not finite".into());
    }
    if !(c.near > 0.0 && c.near.is_finite() && c.far > c.near) {
        return bad(format!("clip range near {} / far {} must satisfy 0 < near < far", c.near, c.far));
    }
    Ok(())
}

/// Box-filters colour; depth and segmentation from the sample at `(k/2, k/2)` of each block.
fn downsample(hi: &Frame, k: u32, out: &mut Frame) {
    let (w, h) = (out.width() as usize, out.height() as usize);
    let (k, hw) = (k as usize, hi.width() as usize);
    let n = (k * k) as u32;
    for y in 0..h {
        for x in 0..w {
            let mut sum = [0u32; 3];
            for sy in 0..k {
                let row = (y * k + sy) * hw;
                for sx in 0..k {
                    let q = (row + x * k + sx) * 3;
                    for (s, &v) in sum.iter_mut().zip(&hi.color.data[q..q + 3]) {
                        *s += v as u32;
                    }
                }
            }
            let p = y * w + x;
            for (o, s) in out.color.data[p * 3..p * 3 + 3].iter_mut().zip(sum) {
                *o = ((s + n / 2) / n) as u8;
            }
            let centre = (y * k + k / 2) * hw + x * k + k / 2;
            out.depth[p] = hi.depth[centre];
            out.segmentation[p] = hi.segmentation[centre];
        }
    }
}
