//! The z-buffer renderer.
//!
//! One frame runs in four steps, single-threaded, with buffers reused between frames:
//! 1. **Geometry.** Instances outside the view frustum (bounding sphere test) are skipped; the
//!    rest are sorted front to back. An instance, or a cluster of a clustered mesh
//!    ([`crate::Mesh::clustered`]), is skipped whole when what was drawn before it hides it
//!    ([`hiz`]); a cluster also when it lies outside the view or its normal cone faces away.
//!    The vertices drawn are transformed into camera space once, eight at a time ([`vertex`]),
//!    with outcodes for trivial rejection and clipping. Triangles are back-face culled in exact
//!    fixed point, near-plane (and guard-band) clipped when needed, and only the vertices of
//!    triangles that cover a pixel centre in front of what is already drawn are lit (per vertex,
//!    [`lighting`]): the winners of a cluster wait for their records until its vertices are lit
//!    eight at a time.
//! 2. **Visibility.** Opaque triangles are rasterized depth-only into a visibility buffer: per
//!    pixel, `1/z` and the index of the nearest triangle ([`triangle`] does exact coverage at
//!    pixel centres). A large triangle that the hi-z shows hidden is skipped before its pixels
//!    are tested.
//! 3. **Resolve.** Each pixel is shaded once from its triangle's screen-space attribute planes
//!    (perspective-correct colour and UV), textured, and written with depth and segment id;
//!    uncovered pixels get the background.
//! 4. **Transparency.** Instances with alpha < 1 are blended back to front over the result.
//! 5. **Reflection.** Where the scene has a [`Mirror`] and its face is visible, the scene is
//!    drawn again from the camera mirrored in the face's plane (clipped to the plane's outer
//!    side) and added to the face's pixels.
//!
//! Steps 1–3 keep, per camera, a [`layer`] of the instances that did not move since the last
//! frame, so that a fixed camera draws only what moved; the pixels come out the same.

mod clip;
mod hiz;
mod layer;
mod lighting;
mod shadow;
mod triangle;
mod vertex;

use glam::{Mat3, Vec2, Vec3};
use thiserror::Error;

use self::clip::{ClipSpace, ClipVert, Polygon, SphereClass, GUARD_FIXED, MUST_CLIP, REJECT};
use self::hiz::HiZ;
use self::layer::{Buffers, Layers, PixelBox, Plan};
use self::lighting::{LightRig, Lit, VERTEX_LANES};
use self::shadow::ShadowMap;
use self::triangle::{box_holds_centre, orientation, snap, Plane, Planes, Setup};
use self::vertex::ToScreen;
use crate::camera::{Camera, Intrinsics};
use crate::cluster::Cluster;
use crate::frame::Frame;
use crate::scene::{Background, Instance, Light, LightKind, Mirror, Scene};
use crate::texture::Texture;
use crate::transform::{cross, dot, mul_mat3, mul_mat3_mat3, normalize};

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
    /// its next frame ([`layer`]). Changes no pixel; off, every frame is drawn whole.
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

/// Per-frame view constants.
struct View {
    k: Intrinsics,
    clip: ClipSpace,
    /// World → camera rotation (rows are the camera's right, down and forward axes).
    rot: Mat3,
    position: Vec3,
    width: u32,
    height: u32,
    far: f32,
    /// A mirror's pass: only surfaces on the outer side of this plane are drawn.
    keep: Option<Keep>,
}

/// The plane a mirror's pass keeps the outer side of: as a per-pixel test, and in the world.
#[derive(Clone, Copy)]
struct Keep {
    test: PlaneTest,
    point: Vec3,
    normal: Vec3,
}

/// A world plane as a per-pixel test: `a i + b j + c + d / z` is the signed distance to the
/// plane of the point at pixel `(i, j)` and depth `z`, divided by `z` (so linear in `i`, `j`
/// and `1/z`).
#[derive(Clone, Copy)]
struct PlaneTest {
    a: f32,
    b: f32,
    c: f32,
    d: f32,
}

impl PlaneTest {
    /// The plane through `point` with unit normal `normal` (world), seen by `view`.
    fn new(view: &View, point: Vec3, normal: Vec3) -> PlaneTest {
        let m = mul_mat3(&view.rot, normal);
        let k = &view.k;
        let (a, b) = (m.x / k.fx, m.y / k.fy);
        PlaneTest { a, b, c: m.z - a * k.cx - b * k.cy, d: dot(normal, view.position - point) }
    }

    /// Distance over depth at pixel `(i, j)` with `1/z = iz`.
    #[inline]
    fn at(&self, i: f32, j: f32, iz: f32) -> f32 {
        self.a * i + (self.b * j + self.c) + self.d * iz
    }
}

impl View {
    fn new(c: &Camera) -> View {
        let k = c.intrinsics();
        let r = &c.rotation;
        View {
            k,
            clip: ClipSpace::new(&k, c.width, c.height, c.near),
            rot: Mat3::from_cols(r.x_axis, -r.y_axis, -r.z_axis).transpose(),
            position: c.position,
            width: c.width,
            height: c.height,
            far: c.far,
            keep: None,
        }
    }

    /// The view drawing only what lies on the side of the plane through `point` that unit
    /// `normal` points to.
    fn keeping(mut self, point: Vec3, normal: Vec3) -> View {
        self.keep = Some(Keep { test: PlaneTest::new(&self, point, normal), point, normal });
        self
    }

    /// Whether an instance's bounding box (corners in world space) lies wholly outside one side
    /// of the view or behind the kept side of its plane: then none of its triangles can show.
    fn box_hidden(&self, t: &crate::transform::Transform, centre: Vec3, half: Vec3) -> bool {
        let mut outside = REJECT;
        let mut behind = true;
        for k in 0..8 {
            let sign = |bit: u32| if k & bit == 0 { -1.0 } else { 1.0 };
            let corner = t.transform_point(centre + Vec3::new(sign(1) * half.x, sign(2) * half.y, sign(4) * half.z));
            outside &= self.clip.outcode(mul_mat3(&self.rot, corner - self.position));
            behind &= self.keep.is_some_and(|k| dot(k.normal, corner - k.point) < 0.0);
        }
        outside != 0 || behind
    }

    /// Whether `sink` says a camera-space sphere is hidden behind what is drawn: it must lie in
    /// front of the eye, and its nearest point behind every pixel its projection can cover.
    fn hidden(&self, sink: &mut impl Sink, c: Vec3, r: f32) -> bool {
        let (z0, z1) = (c.z - r, c.z + r);
        if !(z0 > 0.0) {
            return false;
        }
        // x/z over the box around the sphere is extreme at its corners; one pixel of margin.
        let (iz0, iz1) = (1.0 / z0, 1.0 / z1);
        let range = |m: f32, f: f32, o: f32, size: u32| {
            let q = [(m - r) * iz0, (m - r) * iz1, (m + r) * iz0, (m + r) * iz1].map(|q| f * q + o);
            let (lo, hi) = (q.iter().fold(f32::INFINITY, |a, &b| a.min(b)), q.iter().fold(f32::NEG_INFINITY, |a, &b| a.max(b)));
            let clamp = |x: f32| (x.max(0.0).min(size as f32 - 1.0)) as u32;
            (clamp(lo - 1.0), clamp(hi + 2.0))
        };
        let (x0, x1) = range(c.x, self.k.fx, self.k.cx, self.width);
        let (y0, y1) = range(c.y, self.k.fy, self.k.cy, self.height);
        sink.hidden([x0, y0, x1, y1], iz0)
    }

    /// The part of this view from pixel `(x0, y0)` to `(x1, y1)` (inclusive), as a view of its own.
    fn cropped(mut self, x0: u32, y0: u32, x1: u32, y1: u32, near: f32) -> View {
        self.k.cx -= x0 as f32;
        self.k.cy -= y0 as f32;
        self.width = x1 - x0 + 1;
        self.height = y1 - y0 + 1;
        self.clip = ClipSpace::new(&self.k, self.width, self.height, near);
        self
    }

    /// Screen position (snapped) and `1/z` of a camera-space point in front of the near plane
    /// and inside the guard band; the same arithmetic as [`Camera::project`].
    #[inline]
    fn project(&self, c: Vec3) -> ([i32; 2], f32) {
        let u = self.k.fx * (c.x / c.z) + self.k.cx;
        let v = self.k.fy * (c.y / c.z) + self.k.cy;
        ([View::fixed(u), View::fixed(v)], 1.0 / c.z)
    }

    /// A projected coordinate (pixels) snapped to the fixed-point grid. Clipping keeps real
    /// vertices inside the guard band; the clamp only bounds what absurd (but finite) inputs
    /// could produce, so the fixed-point arithmetic cannot overflow.
    #[inline]
    fn fixed(x: f32) -> i32 {
        snap(x).clamp(-GUARD_FIXED, GUARD_FIXED) as i32
    }
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
            Plan::Plain => {
                self.clear(view, only);
                for v in &order {
                    self.draw_opaque(scene, v, view, None);
                }
                self.resolve(scene, view, out, 0, PixelBox::all(view.width, view.height));
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

    /// Adds what `mirror` reflects to the pixels of `out` that show its face, as MuJoCo does:
    /// the other instances, colours scaled by the reflectance, drawn from the camera mirrored in
    /// the face's plane and clipped to the plane's outer side, over black. The mirrored camera
    /// is turned right-handed again by flipping its x axis, so its image is read mirrored
    /// (column `W − 1 − i`). Lighting is unchanged by the mirroring, except MuJoCo's headlight,
    /// which keeps shining along the real camera's view axis.
    fn reflect(&mut self, scene: &Scene, camera: &Camera, mirror: &Mirror, out: &mut Frame) {
        let Some(face) = scene.instances.get(mirror.instance) else { return };
        let t = &face.transform;
        let point = t.transform_point(Vec3::new(0.0, 0.0, mirror.face_z));
        let normal = normalize(cross(t.linear.x_axis, t.linear.y_axis));
        let height = dot(normal, camera.position - point);
        if !(height > 0.0 && mirror.reflectance > 0.0) {
            return;
        }
        // The face's pixels: the mirror's own triangles lying in its plane (within 1 mm).
        let on_plane = PlaneTest::new(&View::new(camera), point, normal);
        let w = camera.width as usize;
        let mut pixels = std::mem::take(&mut self.mirror_pixels);
        pixels.clear();
        let on_face = |id: u32| id != NO_TRIANGLE && self.records[id as usize].instance as usize == mirror.instance;
        let (mut last_id, mut last_on) = (NO_TRIANGLE, false);
        for (p, (&id, &iz)) in self.tri_id.iter().zip(&self.depth).enumerate() {
            if id != last_id {
                (last_id, last_on) = (id, on_face(id));
            }
            if last_on {
                let (i, j) = ((p % w) as f32, (p / w) as f32);
                if (on_plane.at(i, j, iz) / iz).abs() < 1e-3 {
                    pixels.push(p as u32);
                }
            }
        }
        if let Some((x0, y0, x1, y1)) = bounds(&pixels, w) {
            let scaled = |rgba: [f32; 4]| [rgba[0] * mirror.reflectance, rgba[1] * mirror.reflectance, rgba[2] * mirror.reflectance, rgba[3]];
            let h = &scene.headlight;
            let headlight = h.active.then(|| Light {
                kind: LightKind::Directional { direction: camera.forward() },
                ambient: h.ambient,
                diffuse: h.diffuse,
                specular: h.specular,
                cast_shadow: false,
            });
            // Instances wholly behind the mirror's plane cannot show in it.
            let in_front = |i: &Instance| {
                let b = i.mesh.bounds();
                dot(normal, i.transform.transform_point(b.center) - point) > -b.radius * i.transform.max_scale()
            };
            let mut mirrored = std::mem::take(&mut self.mirrored_scene);
            mirrored.instances.clear();
            mirrored.instances.extend(
                scene.instances.iter().enumerate().filter(|&(k, i)| k != mirror.instance && in_front(i)).map(|(_, i)| Instance {
                    material: crate::Material { rgba: scaled(i.material.rgba), ..i.material.clone() },
                    ..i.clone()
                }),
            );
            mirrored.lights.clear();
            mirrored.lights.extend(headlight.into_iter().chain(scene.lights.iter().copied()));
            mirrored.headlight = crate::Headlight { active: false, ..*h };
            mirrored.background = Background::Solid([0.0; 3]);
            let flip = |v: Vec3| v - 2.0 * dot(normal, v) * normal;
            let r = &camera.rotation;
            let cam = Camera {
                position: camera.position - 2.0 * height * normal,
                rotation: Mat3::from_cols(-flip(r.x_axis), flip(r.y_axis), flip(r.z_axis)),
                ..*camera
            };
            // Only the mirrored columns of the face's bounding box are drawn.
            let last = w as u32 - 1;
            let view = View::new(&cam).cropped(last - x1, y0, last - x0, y1, cam.near).keeping(point, normal);
            let mut image = std::mem::take(&mut self.reflected);
            image.resize(view.width, view.height);
            let cw = view.width as usize;
            let mut mirrored_pixels = std::mem::take(&mut self.mirrored_pixels);
            mirrored_pixels.clear();
            mirrored_pixels.extend(pixels.iter().map(|&p| {
                let (i, j) = (p as usize % w, p as usize / w);
                ((j - y0 as usize) * cw + (last as usize - i - (last - x1) as usize)) as u32
            }));
            self.draw_pass(&mirrored, &cam, &view, &mut image, Some(&mirrored_pixels), Plan::Plain);
            for (&p, &q) in pixels.iter().zip(&mirrored_pixels) {
                let q = q as usize;
                for c in 0..3 {
                    let sum = u16::from(out.color.data[3 * p as usize + c]) + u16::from(image.color.data[3 * q + c]);
                    out.color.data[3 * p as usize + c] = sum.min(255) as u8;
                }
            }
            self.reflected = image;
            self.mirrored_scene = mirrored;
            self.mirrored_pixels = mirrored_pixels;
        }
        self.mirror_pixels = pixels;
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

    /// Draws one opaque instance into the visibility buffer. With `layer_records`, the buffer
    /// starts from the camera's static layer, whose records are the first `layer_records`.
    fn draw_opaque(&mut self, scene: &Scene, visible: &Visible, view: &View, layer_records: Option<u32>) {
        let (idx, inst) = (visible.index, &scene.instances[visible.index as usize]);
        let ties = layer_records.and_then(|n| Some(Ties { layer: self.layers.layer()?, records: n, depth: visible.depth, index: idx }));
        let mut sink = Opaque {
            depth: &mut self.depth,
            tri_id: &mut self.tri_id,
            records: &mut self.records,
            deferred: &mut self.deferred,
            shadow_rgb: &mut self.shadow_rgb,
            hiz: &mut self.hiz,
            touched: &mut self.touched,
            view,
            inst,
            idx,
            shadows: self.shadows_active,
            ties,
            rasterized: 0,
            hidden: 0,
        };
        let mut front = Frontend { verts: &mut self.verts, lit: &mut self.lit, poly: &mut self.poly, rig: &self.rig };
        let done = front.assemble(inst, visible.inside, view, &mut sink);
        self.stats.triangles_rasterized += sink.rasterized;
        self.stats.triangles_hidden += sink.hidden;
        self.stats.add(done);
    }

    fn draw_blended(&mut self, scene: &Scene, visible: &Visible, view: &View, out: &mut Frame) {
        let (idx, inst) = (visible.index, &scene.instances[visible.index as usize]);
        let shadows = self.shadows_active.then_some(&self.shadow);
        let depth = &self.depth;
        let mut rasterized = 0;
        let mut front = Frontend { verts: &mut self.verts, lit: &mut self.lit, poly: &mut self.poly, rig: &self.rig };
        let done = front.assemble(inst, visible.inside, view, &mut |setup: &Setup, _: [f32; 3], light: &mut dyn FnMut() -> [ScreenVert; 3]| {
            let (rec, sh) = build_record(&setup.planes, &light(), inst, idx, shadows.is_some());
            rasterized += 1;
            let texture = texture_of(&rec, scene);
            setup.for_each_pixel(&rec.iz, view.width, |p, i, j, iz| {
                if iz > depth[p] && view.keep.is_none_or(|k| k.test.at(i as f32, j as f32, iz) >= 0.0) {
                    let src = shade(&rec, sh.as_ref(), shadows, texture, view, i, j, 1.0 / iz);
                    let dst = &mut out.color.data[p * 3..p * 3 + 3];
                    let a = src[3];
                    for c in 0..3 {
                        let d = dst[c] as f32 * (1.0 / 255.0);
                        dst[c] = to_u8(src[c] * a + d * (1.0 - a));
                    }
                    out.segmentation[p] = rec.segment;
                }
            });
        });
        self.stats.triangles_rasterized += rasterized;
        self.stats.add(done);
    }

    /// Shades every pixel of `region` once from the visibility buffer, one run of same-triangle
    /// pixels at a time. With `from > 0`, only pixels of records from `from` on, which all lie
    /// in `region`: `out` holds the others (the static layer's).
    fn resolve(&self, scene: &Scene, view: &View, out: &mut Frame, from: u32, region: PixelBox) {
        let shadows = self.shadows_active.then_some(&self.shadow);
        let sky = Sky::new(scene.background, view);
        let w = view.width as usize;
        for j in region.y0..=region.y1 {
            let row = j as usize * w..(j as usize + 1) * w;
            let ids = &self.tri_id[row.clone()];
            let depths = &self.depth[row.clone()];
            let rgb_out = &mut out.color.data[row.start * 3..row.end * 3];
            let depth_out = &mut out.depth[row.clone()];
            let seg_out = &mut out.segmentation[row];
            let fj = j as f32;
            let (mut start, stop) = (region.x0 as usize, region.x1 as usize + 1);
            while start < stop {
                let id = ids[start];
                let end = start + run_length(&ids[start..stop]);
                if from > 0 && (id < from || id == NO_TRIANGLE) {
                    // Already in `out`.
                } else if id == NO_TRIANGLE {
                    for k in start..end {
                        depth_out[k] = f32::INFINITY;
                        seg_out[k] = 0;
                        put_rgb(rgb_out, k, sky.color(k as u32, j));
                    }
                } else {
                    let rec = &self.records[id as usize];
                    seg_out[start..end].fill(rec.segment);
                    if rec.mip == u32::MAX && shadows.is_none() {
                        // Common case: Gouraud colour only.
                        let rows = rec.rgb.map(|p| p.b * fj + p.c);
                        for k in start..end {
                            let z = 1.0 / depths[k];
                            depth_out[k] = z;
                            // Through i32 (the same float): its conversion vectorizes.
                            let fi = k as i32 as f32;
                            put_rgb(rgb_out, k, std::array::from_fn(|c| (rec.rgb[c].a * fi + rows[c]) * z));
                        }
                    } else {
                        let sh = shadows.map(|_| self.shadow_rgb[id as usize]);
                        let texture = texture_of(rec, scene);
                        let mut first = start;
                        if let (Some(tex), None) = (texture, shadows) {
                            // Long runs (large textured triangles) eight pixels at a time.
                            while end - first >= LANES {
                                let px = first..first + LANES;
                                let (z, rgb) = shade_textured8(rec, tex, first, fj, depths[px.clone()].try_into().unwrap());
                                depth_out[px].copy_from_slice(&z);
                                for l in 0..LANES {
                                    rgb_out[3 * (first + l)..3 * (first + l) + 3].copy_from_slice(&[rgb[0][l], rgb[1][l], rgb[2][l]]);
                                }
                                first += LANES;
                            }
                        }
                        for k in first..end {
                            let z = 1.0 / depths[k];
                            depth_out[k] = z;
                            let c = shade(rec, sh.as_ref(), shadows, texture, view, k as u32, j, z);
                            put_rgb(rgb_out, k, [c[0], c[1], c[2]]);
                        }
                    }
                }
                start = end;
            }
        }
    }
}

/// What a span's depth test does besides comparing depths.
#[derive(Clone, Copy)]
enum SpanTest<'a> {
    Plain,
    /// A mirror's pass: only pixels on the kept side of its plane count.
    Keep(&'a PlaneTest),
    /// Over the camera's static layer: exact ties with it go as a whole frame would draw them.
    Ties(&'a Ties<'a>),
}

/// Depth-tests one span of a triangle (row `j`, pixels from `first`, whose depth and id slices
/// are given) and writes where it wins; returns the won pixels' masks or-ed. Each [`SpanTest`]
/// compiles its own loop: the plain pass's has no plane test, which would cost the innermost
/// loop a fifth of its time.
#[inline(always)]
fn depth_span(depth: &mut [f32], tri_id: &mut [u32], first: u32, j: u32, plane: &Plane, test: SpanTest, id: u32) -> u32 {
    match test {
        SpanTest::Keep(k) => span_where::<false>(depth, tri_id, first, j, plane, id, |i, iz| k.at(i, j as f32, iz) >= 0.0).0,
        SpanTest::Plain => span_where::<false>(depth, tri_id, first, j, plane, id, |_, _| true).0,
        SpanTest::Ties(t) => {
            let (won, tied) = span_where::<true>(depth, tri_id, first, j, plane, id, |_, _| true);
            if tied == 0 {
                return won;
            }
            won | t.settle(depth, tri_id, first, j, plane, id)
        }
    }
}

/// [`depth_span`]'s loop, counting only pixels where `kept(i, 1/z)` holds. With `TIES`, also
/// returns whether any pixel tied (equal `1/z`) before the writes.
#[inline(always)]
fn span_where<const TIES: bool>(depth: &mut [f32], tri_id: &mut [u32], first: u32, j: u32, plane: &Plane, id: u32, kept: impl Fn(f32, f32) -> bool) -> (u32, u32) {
    let row_key = plane.b * j as f32 + plane.c;
    let (mut won, mut tied) = (0u32, 0u32);
    // Columns as i32: the same floats as from u32, but the signed conversion vectorizes.
    for ((d, t), i) in depth.iter_mut().zip(tri_id).zip(first as i32..) {
        let iz = plane.a * i as f32 + row_key;
        if TIES {
            tied |= (iz == *d) as u32;
        }
        // Bit selects rather than branches: depth-test outcomes are hard to predict.
        let mask = (((iz > *d) & kept(i as f32, iz)) as u32).wrapping_neg();
        won |= mask;
        *t = (*t & !mask) | (id & mask);
        *d = f32::from_bits((d.to_bits() & !mask) | (iz.to_bits() & mask));
    }
    (won, tied)
}

/// How an instance drawn over the camera's static layer settles exact depth ties with it.
struct Ties<'a> {
    layer: &'a layer::Layer,
    /// The layer's records are the first `records`.
    records: u32,
    /// The instance's key in the front-to-back order, and its index.
    depth: f32,
    index: u32,
}

impl Ties<'_> {
    /// After a span's depth test: takes the pixels where it tied with a layer record that a
    /// whole frame would have drawn after it. Returns a non-zero mask if it took any.
    #[cold]
    fn settle(&self, depth: &[f32], tri_id: &mut [u32], first: u32, j: u32, plane: &Plane, id: u32) -> u32 {
        let row_key = plane.b * j as f32 + plane.c;
        let mut won = 0u32;
        for ((&d, t), i) in depth.iter().zip(tri_id).zip(first as i32..) {
            let iz = plane.a * i as f32 + row_key;
            if iz == d && *t < self.records && self.layer.wins_tie(*t, self.depth, self.index) {
                *t = id;
                won = u32::MAX;
            }
        }
        won
    }
}

/// Bounding box `(x0, y0, x1, y1)` of pixel indices in an image `width` wide.
fn bounds(pixels: &[u32], width: usize) -> Option<(u32, u32, u32, u32)> {
    let w = width as u32;
    let (first, last) = (*pixels.first()?, *pixels.last()?);
    let (x0, x1) = pixels.iter().fold((u32::MAX, 0), |(lo, hi), &p| (lo.min(p % w), hi.max(p % w)));
    Some((x0, first / w, x1, last / w))
}

/// How many ids at the start of `ids` (not empty) equal the first, compared eight at a time:
/// runs are long where large triangles fill the view.
#[inline]
fn run_length(ids: &[u32]) -> usize {
    use wide::u32x8;
    let first = u32x8::splat(ids[0]);
    let mut n = 0;
    for chunk in ids.chunks_exact(8) {
        let differ = !u32x8::from(chunk).simd_eq(first).to_bitmask() & 0xFF;
        if differ != 0 {
            return n + differ.trailing_zeros() as usize;
        }
        n += 8;
    }
    n + ids[n..].iter().take_while(|&&x| x == ids[0]).count()
}

/// Writes pixel `k` of a packed RGB row.
#[inline]
fn put_rgb(row: &mut [u8], k: usize, rgb: [f32; 3]) {
    let px = &mut row[3 * k..3 * k + 3];
    px[0] = to_u8(rgb[0]);
    px[1] = to_u8(rgb[1]);
    px[2] = to_u8(rgb[2]);
}

/// Borrowed per-instance state for geometry processing.
struct Frontend<'a> {
    verts: &'a mut Verts,
    lit: &'a mut LitCache,
    poly: &'a mut Polygon,
    rig: &'a LightRig,
}

impl Frontend<'_> {
    /// Transforms, culls, clips and lights one instance, sending `sink` each screen triangle
    /// that covers a pixel centre (vertices are lit only when the sink asks).
    fn assemble(&mut self, inst: &Instance, inside: bool, view: &View, sink: &mut impl Sink) -> Assembled {
        let mesh = &*inst.mesh;
        let t = &inst.transform;
        let linear = mul_mat3_mat3(&view.rot, &t.linear);
        let trans = mul_mat3(&view.rot, t.translation - view.position);
        let to_screen = ToScreen::new(linear, trans, inside, view);
        let uvs = inst.material.texture.as_ref().and(mesh.uvs());
        let placed = Placed {
            normals: mesh.normals(),
            normal_m: mul_mat3_mat3(&view.rot, &t.normal_matrix()),
            surface: self.rig.surface(&inst.material),
            double_sided: inst.material.double_sided,
            uvs,
            uv_scale: inst.material.uv_scale,
            uv_offset: inst.material.uv_offset,
            rig: self.rig,
        };
        let scale = t.max_scale();
        let mut done = Assembled::default();
        let b = mesh.bounds();
        if view.hidden(sink, mul_mat3(&linear, b.center) + trans, b.radius * scale) {
            done.hidden += 1;
            return done;
        }
        self.lit.begin(mesh.vertex_count());
        let clusters = mesh.clusters();
        if clusters.list.is_empty() {
            self.verts.fill(mesh.positions(), &to_screen);
            placed.draw(mesh.triangles(), &*self.verts, &mut *self.lit, &mut *self.poly, view, sink);
        } else {
            self.verts.begin(mesh.vertex_count());
            let cones = !inst.material.double_sided && is_similarity(&t.linear);
            // The eye is at the origin of camera space.
            let faces_away = |c: &Cluster| dot(normalize(mul_mat3(&linear, c.cone_apex) + trans), normalize(mul_mat3(&linear, c.cone_axis))) >= c.cone_cutoff + CONE_MARGIN;
            for c in &clusters.list {
                let centre = mul_mat3(&linear, c.centre) + trans;
                let outside = !inside && view.clip.classify_sphere(centre, c.radius * scale, view.far) == SphereClass::Outside;
                if outside || (cones && faces_away(c)) {
                    done.culled += 1;
                    continue;
                }
                if view.hidden(sink, centre, c.radius * scale) {
                    done.hidden += 1;
                    continue;
                }
                let used = &clusters.vertices[c.first_vertex as usize..(c.first_vertex + c.vertex_count) as usize];
                self.verts.ensure(used, mesh.positions(), &to_screen);
                let tris = &mesh.triangles()[c.first as usize..(c.first + c.count) as usize];
                placed.draw(tris, &*self.verts, &mut *self.lit, &mut *self.poly, view, sink);
            }
        }
        done.lit = self.lit.count;
        done
    }
}

/// What [`Frontend::assemble`] did with one instance, for [`RenderStats`].
#[derive(Clone, Copy, Default)]
struct Assembled {
    lit: usize,
    culled: usize,
    hidden: usize,
}

/// Where the geometry stage sends what it assembled.
trait Sink {
    /// Whether every pixel of `rect` (inclusive `[x0, y0, x1, y1]`) already shows a surface
    /// clearly nearer than `1/z = nearest`, so nothing at that depth or beyond can show there.
    fn hidden(&mut self, _rect: [u32; 4], _nearest: f32) -> bool {
        false
    }

    /// A screen triangle covering a pixel centre, its vertices' `1/z`, its mesh corners (in
    /// the order its setup uses, and which side faces the camera) unless it was clipped, and a
    /// function that lights its vertices now.
    fn triangle(&mut self, setup: &Setup, iz: [f32; 3], corners: Option<Corners>, light: &mut dyn FnMut() -> [ScreenVert; 3]);

    /// Triangles kept for lighting later: the frontend lights their corners together (eight
    /// vertices at a time) and hands them back through [`Sink::commit`]. `None`: lights now.
    fn deferred(&mut self) -> Option<&mut Vec<Deferred>> {
        None
    }

    /// Takes back the deferred triangles, with their lit corners.
    fn commit(&mut self, _corner: &dyn Fn(u32, bool) -> ScreenVert) {}
}

/// Any such function is a sink that hides nothing and lights at once.
impl<F: FnMut(&Setup, [f32; 3], &mut dyn FnMut() -> [ScreenVert; 3])> Sink for F {
    fn triangle(&mut self, setup: &Setup, iz: [f32; 3], _: Option<Corners>, light: &mut dyn FnMut() -> [ScreenVert; 3]) {
        self(setup, iz, light)
    }
}

/// The mesh vertices of a triangle, in its setup's order, and whether its back faces the camera.
#[derive(Clone, Copy)]
struct Corners {
    ids: [u32; 3],
    back: bool,
}

/// A triangle that won pixels and waits for its corners' colours.
struct Deferred {
    planes: Planes,
    corners: Corners,
}

/// The opaque pass: depth-tests triangles into the visibility buffer and records the winners.
struct Opaque<'a> {
    depth: &'a mut [f32],
    tri_id: &'a mut [u32],
    records: &'a mut Vec<TriRecord>,
    /// Winners whose records wait for their lit corners; their ids follow `records`.
    deferred: &'a mut Vec<Deferred>,
    shadow_rgb: &'a mut Vec<[Plane; 3]>,
    hiz: &'a mut HiZ,
    /// Grows to hold the spans where the instance won pixels.
    touched: &'a mut PixelBox,
    view: &'a View,
    inst: &'a Instance,
    idx: u32,
    shadows: bool,
    /// Set when drawing over the camera's static layer.
    ties: Option<Ties<'a>>,
    rasterized: usize,
    /// Triangles skipped by the hi-z.
    hidden: usize,
}

impl Sink for Opaque<'_> {
    fn hidden(&mut self, rect: [u32; 4], nearest: f32) -> bool {
        self.hiz.hidden(self.depth, self.view.width, rect, nearest)
    }

    fn triangle(&mut self, setup: &Setup, iz: [f32; 3], corners: Option<Corners>, light: &mut dyn FnMut() -> [ScreenVert; 3]) {
        self.rasterized += 1;
        let plane = setup.plane(iz);
        // A large triangle behind what is drawn (the floor under the table, a cabinet behind
        // the robot) is skipped before its pixels are tested. No pixel of it gets a `1/z` above
        // its nearest vertex's by more than the rounding of the plane's f32 coefficients and
        // evaluation (under 4 ε of the terms' magnitudes), so nothing it could win is lost.
        // Small triangles are tested pixel by pixel, which costs less than the hi-z's query.
        let [i0, j0, i1, j1] = setup.bounds();
        if (i1 - i0 + 1) * (j1 - j0 + 1) >= HIZ_TRIANGLE_AREA {
            let rounding = 4.0 * f32::EPSILON * (plane.a.abs() * i1 as f32 + plane.b.abs() * j1 as f32 + plane.c.abs());
            if self.hiz.hidden(self.depth, self.view.width, [i0, j0, i1, j1], iz[0].max(iz[1]).max(iz[2]) + rounding) {
                self.hidden += 1;
                return;
            }
        }
        // Depth test and write first, under the id the record is about to get: a triangle that
        // loses every test (common: instances go front to back) wrote nothing, and is neither
        // lit nor recorded.
        let id = (self.records.len() + self.deferred.len()) as u32;
        let mut won = 0u32;
        let view = self.view;
        let keep = view.keep.map(|k| k.test);
        let test = match (keep.as_ref(), self.ties.as_ref()) {
            (Some(k), _) => SpanTest::Keep(k),
            (None, Some(t)) => SpanTest::Ties(t),
            (None, None) => SpanTest::Plain,
        };
        let (depth, tri_id, hiz, touched) = (&mut *self.depth, &mut *self.tri_id, &mut *self.hiz, &mut *self.touched);
        setup.for_each_span(|j, first, last| {
            let base = j as usize * view.width as usize;
            let range = base + first as usize..base + last as usize + 1;
            let mask = depth_span(&mut depth[range.clone()], &mut tri_id[range], first, j, &plane, test, id);
            if mask != 0 {
                hiz.mark(j, first, last);
                touched.add(j, first, last);
            }
            won |= mask;
        });
        if won == 0 {
            return;
        }
        match corners {
            Some(corners) => self.deferred.push(Deferred { planes: setup.planes, corners }),
            None => {
                // Ids follow the records: the frontend commits deferred triangles before it
                // sends a clipped one.
                debug_assert!(self.deferred.is_empty());
                self.record(&setup.planes, &light());
            }
        }
    }

    fn deferred(&mut self) -> Option<&mut Vec<Deferred>> {
        Some(self.deferred)
    }

    fn commit(&mut self, corner: &dyn Fn(u32, bool) -> ScreenVert) {
        let deferred = std::mem::take(self.deferred);
        for d in &deferred {
            let [a, b, c] = d.corners.ids;
            let back = d.corners.back;
            self.record(&d.planes, &[corner(a, back), corner(b, back), corner(c, back)]);
        }
        *self.deferred = deferred;
        self.deferred.clear();
    }
}

impl Opaque<'_> {
    fn record(&mut self, planes: &Planes, corners: &[ScreenVert; 3]) {
        let (rec, sh) = build_record(planes, corners, self.inst, self.idx, self.shadows);
        self.records.push(rec);
        if let Some(sh) = sh {
            self.shadow_rgb.push(sh);
        }
    }
}

/// Pixels in a triangle's bounding box from which the opaque pass asks the hi-z whether the
/// triangle is hidden before testing its pixels.
const HIZ_TRIANGLE_AREA: u32 = 128;

/// How far inside its cone's cutoff the eye must be before a cluster counts as facing away: its
/// triangles then face away by a clear angle, so none of them could come out front-facing from
/// the renderer's fixed-point orientation test.
const CONE_MARGIN: f32 = 0.01;

/// Whether `m` is a rotation times a uniform positive scale (normal cones keep their angles).
fn is_similarity(m: &Mat3) -> bool {
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    let s = dot(a, a);
    let near = |x: f32, y: f32| (x - y).abs() <= 1e-4 * s;
    near(dot(b, b), s) && near(dot(c, c), s) && near(dot(a, b), 0.0) && near(dot(b, c), 0.0) && near(dot(a, c), 0.0) && dot(cross(a, b), c) > 0.0
}

/// Per-instance constants for shading its triangles.
struct Placed<'a> {
    normals: &'a [Vec3],
    /// Mesh → camera for normals.
    normal_m: Mat3,
    surface: lighting::Surface<'a>,
    double_sided: bool,
    uvs: Option<&'a [Vec2]>,
    uv_scale: Vec2,
    uv_offset: Vec2,
    rig: &'a LightRig,
}

impl Placed<'_> {
    /// Culls, clips and emits `tris`, whose vertices are in `verts`.
    fn draw(&self, tris: &[[u32; 3]], verts: &Verts, lit: &mut LitCache, poly: &mut Polygon, view: &View, sink: &mut impl Sink) {
        let (w, h) = (view.width, view.height);
        let uv_of = |i: usize| self.uv(i);
        let light = |i: usize, back: bool| {
            let nrm = mul_mat3(&self.normal_m, self.normals[i]);
            self.rig.shade(&self.surface, verts.cam[i], if back { -nrm } else { nrm })
        };
        let xy = |i: usize| verts.screen(i);
        let double_sided = self.double_sided;

        for tri in tris {
            let [a, b, c] = tri.map(|i| i as usize);
            let (ca, cb, cc) = (verts.code[a], verts.code[b], verts.code[c]);
            if ca & cb & cc & REJECT != 0 {
                continue;
            }
            let clip_bits = (ca | cb | cc) & MUST_CLIP;
            if clip_bits == 0 {
                if !box_holds_centre([verts.xy[a], verts.xy[b], verts.xy[c]]) {
                    continue;
                }
                let o = orientation([xy(a), xy(b), xy(c)]);
                // Counter-clockwise front faces have negative orientation on screen (y down);
                // setup wants positive, so front faces swap their last two vertices.
                let back = o > 0;
                if o == 0 || (back && !double_sided) {
                    continue;
                }
                let (b, c) = if back { (b, c) } else { (c, b) };
                let Some(setup) = &Setup::new([xy(a), xy(b), xy(c)], w, h) else { continue };
                let sv = |i: usize, lit: Lit| self.screen_vert(verts, i, lit);
                let lit = &mut *lit;
                let corners = Corners { ids: [a as u32, b as u32, c as u32], back };
                sink.triangle(setup, [verts.iz[a], verts.iz[b], verts.iz[c]], Some(corners), &mut || {
                    let (la, lb, lc) = (lit.get(a, back, &light), lit.get(b, back, &light), lit.get(c, back, &light));
                    [sv(a, la), sv(b, lb), sv(c, lc)]
                });
            } else {
                // Facing from camera space: the eye is at the origin.
                let (pa, pb, pc) = (verts.cam[a], verts.cam[b], verts.cam[c]);
                let facing = dot(cross(pb - pa, pc - pa), pa);
                let back = facing > 0.0;
                if !(facing != 0.0) || (back && !double_sided) {
                    continue;
                }
                self.commit(verts, lit, sink);
                let cv = |i: usize, lit: Lit| ClipVert { p: verts.cam[i], lit, uv: uv_of(i) };
                let (la, lb, lc) = (lit.get(a, back, &light), lit.get(b, back, &light), lit.get(c, back, &light));
                let count = view.clip.clip([cv(a, la), cv(b, lb), cv(c, lc)], clip_bits, poly);
                let on_screen = |v: &ClipVert| {
                    let (xy, iz) = view.project(v.p);
                    ScreenVert { xy: (xy[0] as i64, xy[1] as i64), iz, lit: v.lit, uv: v.uv }
                };
                for k in 1..count.saturating_sub(1) {
                    let p = &poly.verts;
                    let mut sv = [on_screen(&p[0]), on_screen(&p[k]), on_screen(&p[k + 1])];
                    if orientation([sv[0].xy, sv[1].xy, sv[2].xy]) < 0 {
                        sv.swap(1, 2);
                    }
                    if let Some(setup) = &Setup::new([sv[0].xy, sv[1].xy, sv[2].xy], w, h) {
                        sink.triangle(setup, sv.map(|v| v.iz), None, &mut || sv);
                    }
                }
            }
        }
        self.commit(verts, lit, sink);
    }

    /// Lights the corners of the triangles `sink` deferred that are not lit yet, eight at a
    /// time, and hands the triangles back to it.
    fn commit(&self, verts: &Verts, lit: &mut LitCache, sink: &mut impl Sink) {
        let Some(deferred) = sink.deferred() else { return };
        if deferred.is_empty() {
            return;
        }
        let mut batch = std::mem::take(&mut lit.batch);
        batch.clear();
        for d in deferred.iter() {
            for &v in &d.corners.ids {
                let slot = 2 * v as usize + d.corners.back as usize;
                if lit.claim(slot) {
                    batch.push(slot as u32);
                }
            }
        }
        for chunk in batch.chunks(VERTEX_LANES) {
            // Lanes past the chunk repeat its last vertex; their colours are dropped.
            let slot = |l: usize| chunk[l.min(chunk.len() - 1)] as usize;
            let mut p = [[0.0; VERTEX_LANES]; 3];
            let mut n = [[0.0; VERTEX_LANES]; 3];
            for l in 0..VERTEX_LANES {
                let v = slot(l) / 2;
                let nrm = mul_mat3(&self.normal_m, self.normals[v]);
                let nrm = if slot(l) % 2 == 1 { -nrm } else { nrm };
                let cam = verts.cam[v];
                for k in 0..3 {
                    (p[k][l], n[k][l]) = (cam[k], nrm[k]);
                }
            }
            let lanes = self.rig.shade_lanes(&self.surface, p, n);
            for (l, &slot) in chunk.iter().enumerate() {
                lit.colours[slot as usize] = lanes.lit(l);
            }
        }
        lit.batch = batch;
        let colours = &lit.colours;
        sink.commit(&|v, back| self.screen_vert(verts, v as usize, colours[2 * v as usize + back as usize]));
    }

    /// Texture coordinates of vertex `i`, with the material's scale and offset.
    #[inline]
    fn uv(&self, i: usize) -> Vec2 {
        self.uvs.map_or(Vec2::ZERO, |u| u[i] * self.uv_scale + self.uv_offset)
    }

    /// Vertex `i` on screen, lit `lit`.
    #[inline]
    fn screen_vert(&self, verts: &Verts, i: usize, lit: Lit) -> ScreenVert {
        ScreenVert { xy: verts.screen(i), iz: verts.iz[i], lit, uv: self.uv(i) }
    }
}

/// Lit vertex colours of the current instance, computed on first use. Two slots per vertex
/// (front and back side); a slot is valid when its stamp equals the instance's, so starting a
/// new instance costs nothing per vertex.
#[derive(Default)]
struct LitCache {
    colours: Vec<Lit>,
    stamps: Vec<u32>,
    current: u32,
    /// Slots computed for the current instance.
    count: usize,
    /// Slots to light together (reused between instances).
    batch: Vec<u32>,
}

impl LitCache {
    fn begin(&mut self, vertices: usize) {
        if self.colours.len() < 2 * vertices {
            self.colours.resize(2 * vertices, Lit::default());
            self.stamps.resize(2 * vertices, 0);
        }
        self.current = self.current.wrapping_add(1);
        if self.current == 0 {
            // Stamps wrapped around: forget everything once.
            self.stamps.fill(0);
            self.current = 1;
        }
        self.count = 0;
    }

    /// Marks `slot` computed for the current instance; `false` if it already was.
    #[inline]
    fn claim(&mut self, slot: usize) -> bool {
        let fresh = self.stamps[slot] != self.current;
        if fresh {
            self.stamps[slot] = self.current;
            self.count += 1;
        }
        fresh
    }

    #[inline]
    fn get(&mut self, vertex: usize, back: bool, light: &impl Fn(usize, bool) -> Lit) -> Lit {
        let slot = 2 * vertex + back as usize;
        if self.stamps[slot] != self.current {
            self.colours[slot] = light(vertex, back);
            self.stamps[slot] = self.current;
            self.count += 1;
        }
        self.colours[slot]
    }
}

/// Per-vertex results of one instance, in separate arrays so that the culling loop touches
/// only screen positions and outcodes. A clustered mesh fills only the vertices of the clusters
/// it draws; a stamp per vertex says which are filled for the current instance.
#[derive(Default)]
struct Verts {
    cam: Vec<Vec3>,
    /// Snapped screen position (fits `i32`: the guard band keeps it below 2^28 sub-pixels).
    xy: Vec<[i32; 2]>,
    iz: Vec<f32>,
    code: Vec<u16>,
    stamps: Vec<u32>,
    current: u32,
    /// The vertices to fill next (reused between instances).
    fresh: Vec<u32>,
}

impl Verts {
    /// Fills every vertex.
    fn fill(&mut self, positions: &[Vec3], to: &ToScreen) {
        let n = positions.len();
        self.cam.resize(n, Vec3::ZERO);
        self.xy.resize(n, [0; 2]);
        self.iz.resize(n, 0.0);
        self.code.resize(n, 0);
        let mut ids = std::mem::take(&mut self.fresh);
        ids.clear();
        ids.extend(0..n as u32);
        to.each(&ids, positions, |v, s| self.put(v, s));
        self.fresh = ids;
    }

    #[inline]
    fn put(&mut self, v: usize, (cam, xy, iz, code): vertex::Screen) {
        (self.cam[v], self.xy[v], self.iz[v], self.code[v]) = (cam, xy, iz, code);
    }

    /// Snapped screen position of vertex `i`.
    #[inline]
    fn screen(&self, i: usize) -> (i64, i64) {
        (self.xy[i][0] as i64, self.xy[i][1] as i64)
    }

    /// Starts an instance whose vertices are filled on demand by [`Verts::ensure`].
    fn begin(&mut self, vertices: usize) {
        if self.stamps.len() < vertices {
            self.stamps.resize(vertices, 0);
        }
        if self.cam.len() < vertices {
            self.cam.resize(vertices, Vec3::ZERO);
            self.xy.resize(vertices, [0; 2]);
            self.iz.resize(vertices, 0.0);
            self.code.resize(vertices, 0);
        }
        self.current = self.current.wrapping_add(1);
        if self.current == 0 {
            self.stamps.fill(0);
            self.current = 1;
        }
    }

    /// Fills the vertices `used` that this instance has not filled yet.
    #[inline]
    fn ensure(&mut self, used: &[u32], positions: &[Vec3], to: &ToScreen) {
        let mut fresh = std::mem::take(&mut self.fresh);
        fresh.clear();
        for &v in used {
            if self.stamps[v as usize] != self.current {
                self.stamps[v as usize] = self.current;
                fresh.push(v);
            }
        }
        to.each(&fresh, positions, |v, s| self.put(v, s));
        self.fresh = fresh;
    }
}

/// The shading record of a set-up screen triangle, plus the shadow-light colour planes when
/// shadows are on.
fn build_record(planes: &Planes, sv: &[ScreenVert; 3], inst: &Instance, idx: u32, shadows: bool) -> (TriRecord, Option<[Plane; 3]>) {
    let iz = [sv[0].iz, sv[1].iz, sv[2].iz];
    let per_z = |f: fn(&ScreenVert) -> f32| planes.plane([f(&sv[0]) * iz[0], f(&sv[1]) * iz[1], f(&sv[2]) * iz[2]]);
    let texture = inst.material.texture.as_deref().filter(|_| inst.mesh.uvs().is_some());
    let mip = texture.map_or(u32::MAX, |t| mip_level(t, sv, planes.area2));
    let rec = TriRecord {
        iz: planes.plane(iz),
        rgb: [per_z(|v| v.lit.base[0]), per_z(|v| v.lit.base[1]), per_z(|v| v.lit.base[2])],
        uv: if texture.is_some() { [per_z(|v| v.uv.x), per_z(|v| v.uv.y)] } else { [Plane::default(); 2] },
        instance: idx,
        segment: inst.segment,
        mip,
        alpha: inst.material.rgba[3].clamp(0.0, 1.0),
    };
    let sh = shadows.then(|| [per_z(|v| v.lit.shadowed[0]), per_z(|v| v.lit.shadowed[1]), per_z(|v| v.lit.shadowed[2])]);
    (rec, sh)
}

/// The mip level whose texels best match this triangle's pixels (one level per triangle).
fn mip_level(t: &Texture, sv: &[ScreenVert; 3], screen_area2: f32) -> u32 {
    let (d1, d2) = (sv[1].uv - sv[0].uv, sv[2].uv - sv[0].uv);
    let uv_area2 = (d1.x * d2.y - d1.y * d2.x).abs() * t.width() as f32 * t.height() as f32;
    t.level_for_density(uv_area2 / screen_area2) as u32
}

/// The texture a record samples (`None` when untextured).
#[inline]
fn texture_of<'a>(rec: &TriRecord, scene: &'a Scene) -> Option<&'a Texture> {
    scene.instances[rec.instance as usize].material.texture.as_deref().filter(|_| rec.mip != u32::MAX)
}

/// Colour (RGBA, `[0, 1]`) of pixel `(i, j)` of a triangle at view depth `z`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn shade(
    rec: &TriRecord,
    shadow_rgb: Option<&[Plane; 3]>,
    shadow: Option<&ShadowMap>,
    texture: Option<&Texture>,
    view: &View,
    i: u32,
    j: u32,
    z: f32,
) -> [f32; 4] {
    let (fi, fj) = (i as f32, j as f32);
    let mut rgb = [rec.rgb[0].eval(fi, fj) * z, rec.rgb[1].eval(fi, fj) * z, rec.rgb[2].eval(fi, fj) * z];
    if let (Some(sh), Some(map)) = (shadow_rgb, shadow) {
        let p = Vec3::new((fi - view.k.cx) / view.k.fx * z, (fj - view.k.cy) / view.k.fy * z, z);
        let vis = map.visibility(p);
        for c in 0..3 {
            rgb[c] += sh[c].eval(fi, fj) * z * vis;
        }
    }
    let mut out = [rgb[0].clamp(0.0, 1.0), rgb[1].clamp(0.0, 1.0), rgb[2].clamp(0.0, 1.0), rec.alpha];
    if let Some(tex) = texture {
        let t = tex.sample_level(rec.uv[0].eval(fi, fj) * z, rec.uv[1].eval(fi, fj) * z, rec.mip as usize);
        for (o, t) in out.iter_mut().zip(t) {
            *o *= t;
        }
    }
    out
}

/// Pixels shaded together by [`shade_textured8`].
const LANES: usize = 8;

/// [`shade`] for the eight pixels from column `first` of row `j` (as `fj`) of a textured
/// triangle without shadows, whose `1/z` are `iz`: their view depths, and their colours as
/// [`to_u8`] rounds them, by channel. Each lane does the same float operations as one pixel
/// alone, so the bits are the same.
#[inline]
fn shade_textured8(rec: &TriRecord, tex: &Texture, first: usize, fj: f32, iz: [f32; LANES]) -> ([f32; LANES], [[u8; LANES]; 3]) {
    use wide::f32x8;
    let (zero, one) = (f32x8::ZERO, f32x8::ONE);
    // Through i32, as the scalar resolve converts columns (the same floats).
    let fi = f32x8::from(std::array::from_fn::<f32, LANES, _>(|l| (first + l) as i32 as f32));
    let z = one / f32x8::from(iz);
    let eval = |p: &Plane| (f32x8::splat(p.a) * fi + f32x8::splat(p.b * fj + p.c)) * z;
    let texel = tex.sample_level_rgb8(eval(&rec.uv[0]), eval(&rec.uv[1]), rec.mip as usize);
    let rgb = std::array::from_fn(|c| {
        // `f32::clamp(0, 1)`, which keeps NaN, then the texel.
        let x = eval(&rec.rgb[c]);
        let x = x.simd_lt(zero).select(zero, x);
        let x = x.simd_gt(one).select(one, x) * texel[c];
        // `to_u8`: NaN and below 0 → 0, above 1 → 1, rounded in the low mantissa bits.
        let y = x.simd_gt(zero).select(x, zero);
        let y = y.simd_lt(one).select(y, one) * f32x8::splat(255.0) + f32x8::splat(8_388_608.0);
        y.to_array().map(|y| (y.to_bits() & 0xFF) as u8)
    });
    (z.to_array(), rgb)
}

/// The tests' pseudo-random numbers, uniform in `[0, 1)`: the top 24 bits of the next state of
/// a 64-bit linear congruential generator (Knuth's MMIX constants).
#[cfg(test)]
pub(crate) fn next_unit(seed: &mut u64) -> f32 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 40) as f32 / (1u64 << 24) as f32
}

/// `[0, 1]` → `0..=255`, rounding to nearest (ties to even; NaN → 0). Adding 2^23 leaves
/// the rounded integer in the low mantissa bits, which is cheaper than a saturating cast.
#[inline]
fn to_u8(x: f32) -> u8 {
    // Not `clamp`, which passes NaN through.
    #[allow(clippy::manual_clamp)]
    let y = x.max(0.0).min(1.0) * 255.0 + 8_388_608.0;
    (y.to_bits() & 0xFF) as u8
}

/// Background colour per pixel.
struct Sky {
    solid: Option<[f32; 3]>,
    up: [f32; 3],
    down: [f32; 3],
    /// World z of the camera's right, down and forward axes (for the gradient).
    zr: f32,
    zd: f32,
    zf: f32,
    k: Intrinsics,
    inv_fx: f32,
    inv_fy: f32,
}

impl Sky {
    fn new(bg: Background, view: &View) -> Sky {
        let z = view.rot.transpose().z_axis; // Row 2 of camera → world.
        let (solid, up, down) = match bg {
            Background::Solid(c) => (Some(c), c, c),
            Background::Gradient { up, down } => (None, up, down),
        };
        Sky { solid, up, down, zr: z.x, zd: z.y, zf: z.z, k: view.k, inv_fx: 1.0 / view.k.fx, inv_fy: 1.0 / view.k.fy }
    }

    #[inline]
    fn color(&self, i: u32, j: u32) -> [f32; 3] {
        if let Some(c) = self.solid {
            return c;
        }
        let (x, y) = ((i as f32 - self.k.cx) * self.inv_fx, (j as f32 - self.k.cy) * self.inv_fy);
        let dz = (self.zr * x + self.zd * y + self.zf) / (x * x + y * y + 1.0).sqrt();
        let t = 0.5 + 0.5 * dz;
        std::array::from_fn(|c| self.down[c] + (self.up[c] - self.down[c]) * t)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_length_counts_the_leading_equal_ids() {
        for len in 1..40usize {
            for cut in 0..=len {
                let ids: Vec<u32> = (0..len).map(|k| if k < cut.max(1) { 7 } else { 8 }).collect();
                assert_eq!(run_length(&ids), cut.max(1), "len {len}, cut {cut}");
            }
        }
    }

    #[test]
    fn lit_cache_computes_each_slot_once_per_instance_and_survives_wrap_around() {
        let calls = std::cell::Cell::new(0);
        let light = |v: usize, back: bool| {
            calls.set(calls.get() + 1);
            Lit { base: [v as f32, back as u8 as f32, 0.0, 1.0], shadowed: [0.0; 3] }
        };
        let mut cache = LitCache::default();
        cache.begin(3);
        assert_eq!(cache.get(2, true, &light).base[..2], [2.0, 1.0]);
        cache.get(2, true, &light);
        cache.get(2, false, &light);
        assert_eq!((calls.get(), cache.count), (2, 2));
        cache.current = u32::MAX;
        cache.begin(3);
        cache.get(2, true, &light);
        assert_eq!((calls.get(), cache.count, cache.current), (3, 1, 1));
    }

    #[test]
    fn the_opaque_resolve_writes_what_shade_computes() {
        // A lit, textured (bilinear, mipmapped) sphere and box and a lit untextured plane behind
        // them: every pixel must get the bits `shade` gives it, also where the resolve's own
        // row-hoisted Gouraud loop (the plane) or its eight-wide textured runs (the box's faces)
        // stand in for `shade`.
        use crate::{Instance, Material, Mesh, Texture, Transform};
        use std::sync::Arc;
        let data: Vec<u8> = (0..32 * 32 * 3).map(|i| ((i * 37) % 251) as u8).collect();
        let tex = Arc::new(Texture::from_rgb8(32, 32, &data).unwrap());
        let textured = Material { rgba: [0.9, 0.8, 0.7, 1.0], specular: 0.5, shininess: 0.3, texture: Some(tex), uv_scale: Vec2::splat(3.0), ..Material::default() };
        let sphere = Instance::new(Arc::new(Mesh::sphere(0.5, 24)), Transform::IDENTITY, 1).with_material(textured.clone());
        let block = Instance::new(Arc::new(Mesh::cuboid(Vec3::splat(0.3))), Transform::from_translation(Vec3::new(-0.9, 0.2, -0.2)), 3).with_material(textured);
        let plane = Instance::new(Arc::new(Mesh::plane(2.0, 2.0)), Transform::from_translation(Vec3::new(0.0, 0.0, -1.0)), 2)
            .with_material(Material { rgba: [0.4, 0.5, 0.6, 1.0], specular: 0.3, ..Material::default() });
        let scene = Scene { instances: vec![sphere, block, plane], ..Scene::default() };
        let camera = Camera::look_at(Vec3::new(0.3, -1.5, 1.2), Vec3::ZERO, Vec3::Z, 50.0, 96, 80);
        let mut r = Renderer::new(RenderOptions::default());
        let frame = r.render(&scene, &camera).unwrap();
        let view = View::new(&camera);
        let (mut textured_px, mut plain_px) = (0, 0);
        for (p, (&id, &iz)) in r.tri_id.iter().zip(&r.depth).enumerate() {
            if id == NO_TRIANGLE {
                continue;
            }
            let rec = &r.records[id as usize];
            let texture = texture_of(rec, &scene);
            *if texture.is_some() { &mut textured_px } else { &mut plain_px } += 1;
            let (i, j) = ((p % 96) as u32, (p / 96) as u32);
            let c = shade(rec, None, None, texture, &view, i, j, 1.0 / iz);
            assert_eq!(frame.color.data[3 * p..3 * p + 3], [to_u8(c[0]), to_u8(c[1]), to_u8(c[2])], "pixel ({i}, {j})");
        }
        assert!(textured_px > 1000 && plain_px > 1000, "{textured_px} textured and {plain_px} plain pixels");
        let long_runs = r.tri_id.chunks(96).flat_map(|row| row.chunk_by(|a, b| a == b)).filter(|run| run[0] != NO_TRIANGLE && run.len() >= LANES);
        let wide_px: usize = long_runs.filter(|run| texture_of(&r.records[run[0] as usize], &scene).is_some()).map(|run| run.len() / LANES * LANES).sum();
        assert!(wide_px > 300, "{wide_px} pixels shaded eight at a time");
    }
}
