//! The static layer: what a fixed camera saw of the instances that did not move, kept between
//! frames so that the next frame draws only what moved.
//!
//! LIBERO's agentview camera never moves, and in most control steps only the robot and what it
//! holds do: the table, floor, walls, fixtures and resting objects give the same visibility
//! buffer and the same colours frame after frame. So the renderer keeps, per camera, the
//! instances of the last frame; an instance whose mesh, material and pose (bit for bit) are
//! those of the last frame counts as static. The static instances are drawn once into a layer
//! (visibility buffer, triangle records, hi-z and resolved pixels); while none of them changes,
//! a frame starts from a copy of the layer and draws, tests and shades only the other instances.
//! One that moved joins the layer again once it has stayed still for [`SETTLED`] frames.
//!
//! A frame drawn on a layer is bit-identical to one drawn without: depth tests are
//! order-independent except on exact ties of `1/z`, and there a moved instance still wins
//! where it comes first in the front-to-back order of a whole frame ([`Layer::wins_tie`]).

use std::sync::Arc;

use crate::camera::Camera;
use crate::frame::Frame;
use crate::mesh::Mesh;
use crate::scene::{Background, Instance, LightKind, Scene};
use crate::texture::Texture;

use super::hiz::HiZ;
use super::TriRecord;

/// Cameras remembered per renderer: the two LIBERO cameras and a spare, so that a moving wrist
/// camera (a new entry each frame) never pushes out the fixed agentview.
const ENTRIES: usize = 3;

/// Largest image (pixels) kept in a layer: about 28 bytes per pixel, with the last frame's buffers.
const MAX_PIXELS: usize = 1 << 20;

/// Frames an instance outside the layer must stay unchanged before the layer is rebuilt with
/// it: an object that came to rest after falling, or that the robot put down. A few frames, so
/// that one that only pauses does not cost a rebuild each time.
const SETTLED: u32 = 8;

/// What a frame does with the layer of its camera.
pub(super) enum Plan {
    /// Draw everything: no instance is known to be static yet.
    Plain,
    /// Draw the static instances (`true` per instance index) into a new layer, then the rest.
    Rebuild(Vec<bool>),
    /// Start from the layer and draw the rest.
    Reuse,
    /// Draw everything, as [`Plan::Plain`], but resolve only the box of pixels drawn
    /// ([`Renderer::render_covered`](super::Renderer::render_covered)); no layer.
    Covered,
}

/// The per-camera memory of one renderer.
#[derive(Default)]
pub(super) struct Layers {
    entries: Vec<Entry>,
    /// The entry of the frame being drawn.
    current: Option<usize>,
    clock: u64,
    /// The buffers of the last layer dropped, for the next one.
    spare: Option<Layer>,
}

impl Layers {
    /// Finds (or makes) the entry of `camera` and `scene`'s lights, compares the instances with
    /// those of its last frame, and says how to draw this frame.
    pub(super) fn plan(&mut self, scene: &Scene, camera: &Camera) -> Plan {
        self.current = None;
        if camera.width as usize * camera.height as usize > MAX_PIXELS {
            return Plan::Plain;
        }
        self.clock += 1;
        let key = Key::of(scene, camera);
        let slot = match self.entries.iter().position(|e| e.key == key) {
            Some(k) => k,
            None if self.entries.len() < ENTRIES => {
                self.entries.push(Entry::new(key));
                self.entries.len() - 1
            }
            None => {
                let k = (0..self.entries.len()).min_by_key(|&k| self.entries[k].used).unwrap_or(0);
                let old = std::mem::replace(&mut self.entries[k], Entry::new(key));
                self.spare = old.layer.or(self.spare.take());
                k
            }
        };
        self.current = Some(slot);
        let entry = &mut self.entries[slot];
        entry.used = self.clock;
        entry.remember(&scene.instances);
        let still = &entry.still;
        if let Some(layer) = &entry.layer {
            let statics = &layer.statics;
            let holds = statics.len() <= still.len() && statics.iter().zip(still).all(|(&s, &n)| !s || n > 0);
            let settled = still.iter().enumerate().any(|(k, &n)| n == SETTLED && statics.get(k) != Some(&true));
            if holds && !settled {
                return Plan::Reuse;
            }
        }
        if let Some(old) = entry.layer.take() {
            self.spare = Some(old);
        }
        if still.iter().any(|&n| n > 0) {
            Plan::Rebuild(still.iter().map(|&n| n > 0).collect())
        } else {
            Plan::Plain
        }
    }

    /// The layer of the frame being drawn (after [`Layers::plan`] said `Reuse` or after
    /// [`Layers::store`]).
    pub(super) fn layer(&self) -> Option<&Layer> {
        self.entries.get(self.current?)?.layer.as_ref()
    }

    pub(super) fn layer_mut(&mut self) -> Option<&mut Layer> {
        self.entries.get_mut(self.current?)?.layer.as_mut()
    }

    /// Keeps `layer` for the frame being drawn's camera.
    pub(super) fn store(&mut self, layer: Layer) {
        if let Some(k) = self.current {
            self.entries[k].layer = Some(layer);
        }
    }

    /// A layer's buffers to refill, taken from the evicted or outdated one where there is one,
    /// so that rebuilding allocates nothing after the first frames.
    pub(super) fn spare(&mut self) -> Layer {
        self.spare.take().unwrap_or_default()
    }
}

/// One camera's memory.
struct Entry {
    key: Key,
    used: u64,
    /// The instances of the last frame drawn with this camera.
    last: Vec<Signature>,
    /// Per instance, the frames in a row it has stayed the same (0: it changed in this one).
    still: Vec<u32>,
    layer: Option<Layer>,
}

impl Entry {
    fn new(key: Key) -> Entry {
        Entry { key, used: 0, last: Vec::new(), still: Vec::new(), layer: None }
    }

    /// Counts which of `instances` are the same as in the last frame, then makes them the last
    /// frame's.
    fn remember(&mut self, instances: &[Instance]) {
        self.last.truncate(instances.len());
        self.still.resize(self.last.len(), 0);
        for (k, i) in instances.iter().enumerate() {
            match self.last.get_mut(k) {
                Some(s) if s.is(i) => self.still[k] = self.still[k].saturating_add(1),
                Some(s) => {
                    *s = Signature::of(i);
                    self.still[k] = 0;
                }
                None => {
                    self.last.push(Signature::of(i));
                    self.still.push(0);
                }
            }
        }
    }
}

/// The static instances of one camera, drawn.
#[derive(Default)]
pub(super) struct Layer {
    /// Per instance index, whether it is in the layer.
    pub(super) statics: Vec<bool>,
    /// Per instance index, its key in the front-to-back order (view depth of its bounding
    /// sphere's centre); set for the static ones.
    pub(super) order: Vec<f32>,
    /// The visibility buffer, records and hi-z after drawing the static instances.
    pub(super) depth: Vec<f32>,
    pub(super) tri_id: Vec<u32>,
    pub(super) records: Vec<TriRecord>,
    pub(super) hiz: HiZ,
    /// The static instances alone, resolved.
    pub(super) image: Frame,
    /// The visibility buffer of the camera's last frame, kept for its next.
    work: Work,
}

/// A camera's visibility buffer and records as its last frame left them: the layer's, changed
/// only within `dirty` by what moved (`None`: unknown). The renderer borrows them for the next
/// frame, which then restores just that box from the layer instead of copying every pixel (at
/// 256², 0.5 MB per frame; the robot covers a small part of agentview).
#[derive(Default)]
struct Work {
    depth: Vec<f32>,
    tri_id: Vec<u32>,
    records: Vec<TriRecord>,
    dirty: Option<PixelBox>,
}

/// The renderer's visibility buffer and records, as the layer lends them out and takes them back.
pub(super) struct Buffers<'a> {
    pub(super) depth: &'a mut Vec<f32>,
    pub(super) tri_id: &'a mut Vec<u32>,
    pub(super) records: &'a mut Vec<TriRecord>,
}

impl Buffers<'_> {
    fn swap(&mut self, work: &mut Work) {
        std::mem::swap(self.depth, &mut work.depth);
        std::mem::swap(self.tri_id, &mut work.tri_id);
        std::mem::swap(self.records, &mut work.records);
    }
}

impl Layer {
    /// Makes `buffers` this layer's visibility buffer and records, for a frame drawn over it:
    /// the camera's last frame's buffers, with the box it changed restored from the layer, or
    /// a whole copy of the layer where those are not known.
    pub(super) fn lend(&mut self, mut buffers: Buffers, width: u32) {
        buffers.swap(&mut self.work);
        match self.work.dirty.take() {
            Some(dirty) if buffers.depth.len() == self.depth.len() && buffers.records.len() >= self.records.len() => {
                let w = width as usize;
                for j in dirty.y0..=dirty.y1 {
                    let row = j as usize * w + dirty.x0 as usize..j as usize * w + dirty.x1 as usize + 1;
                    buffers.depth[row.clone()].copy_from_slice(&self.depth[row.clone()]);
                    buffers.tri_id[row.clone()].copy_from_slice(&self.tri_id[row]);
                }
                buffers.records.truncate(self.records.len());
            }
            _ => {
                buffers.depth.clone_from(&self.depth);
                buffers.tri_id.clone_from(&self.tri_id);
                buffers.records.clone_from(&self.records);
            }
        }
    }

    /// Keeps `buffers` as the camera's last frame's, changed from the layer only within `dirty`
    /// (`None`: anywhere), and gives the renderer back the ones it lent.
    pub(super) fn take_back(&mut self, mut buffers: Buffers, dirty: Option<PixelBox>) {
        buffers.swap(&mut self.work);
        self.work.dirty = dirty;
    }

    /// Whether a triangle of instance `index` at order key `depth`, tying in `1/z` with the
    /// layer's record `id` at some pixel, takes the pixel: it does where a whole frame would
    /// have drawn it first (nearer bounding sphere, then lower index).
    #[inline]
    pub(super) fn wins_tie(&self, id: u32, depth: f32, index: u32) -> bool {
        let other = self.records[id as usize].instance;
        depth.total_cmp(&self.order[other as usize]).then(index.cmp(&other)).is_lt()
    }
}

/// An inclusive rectangle of pixels that grows to hold the spans added to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PixelBox {
    pub(super) x0: u32,
    pub(super) y0: u32,
    pub(super) x1: u32,
    pub(super) y1: u32,
}

impl Default for PixelBox {
    fn default() -> Self {
        PixelBox::EMPTY
    }
}

impl PixelBox {
    pub(super) const EMPTY: PixelBox = PixelBox { x0: u32::MAX, y0: u32::MAX, x1: 0, y1: 0 };

    pub(super) fn is_empty(&self) -> bool {
        self.x0 > self.x1 || self.y0 > self.y1
    }

    /// Every pixel of a `width × height` image.
    pub(super) fn all(width: u32, height: u32) -> PixelBox {
        PixelBox { x0: 0, y0: 0, x1: width.saturating_sub(1), y1: height.saturating_sub(1) }
    }

    /// Grows to hold pixels `first..=last` of row `j`.
    #[inline]
    pub(super) fn add(&mut self, j: u32, first: u32, last: u32) {
        self.x0 = self.x0.min(first);
        self.x1 = self.x1.max(last);
        self.y0 = self.y0.min(j);
        self.y1 = self.y1.max(j);
    }
}

/// An instance as the layer saw it. Holding its mesh and texture keeps their addresses from
/// being reused by other meshes while the signature lives, so pointer equality is identity.
struct Signature {
    mesh: Arc<Mesh>,
    texture: Option<Arc<Texture>>,
    /// Pose, material numbers and flags, and segment, as bits.
    words: [u32; 25],
}

impl Signature {
    fn of(i: &Instance) -> Signature {
        Signature { mesh: i.mesh.clone(), texture: i.material.texture.clone(), words: words(i) }
    }

    fn is(&self, i: &Instance) -> bool {
        Arc::ptr_eq(&self.mesh, &i.mesh)
            && match (&self.texture, &i.material.texture) {
                (None, None) => true,
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                _ => false,
            }
            && self.words == words(i)
    }
}

fn words(i: &Instance) -> [u32; 25] {
    let (t, m) = (&i.transform, &i.material);
    let mut w = [0u32; 25];
    let floats = t.linear.to_cols_array().into_iter().chain(t.translation.to_array()).chain(m.rgba).chain([m.specular, m.shininess, m.emission]);
    let floats = floats.chain(m.uv_scale.to_array()).chain(m.uv_offset.to_array());
    for (w, f) in w.iter_mut().zip(floats) {
        *w = f.to_bits();
    }
    w[23] = i.segment;
    w[24] = m.double_sided as u32 | (m.unlit as u32) << 1;
    w
}

/// A camera and everything else of a scene that colours every pixel (lights, headlight,
/// background, mirror), as bits: a layer is only reused under the same.
#[derive(PartialEq)]
struct Key(Vec<u32>);

impl Key {
    fn of(scene: &Scene, c: &Camera) -> Key {
        let mut f: Vec<f32> = c.position.to_array().into_iter().chain(c.rotation.to_cols_array()).chain([c.fovy_deg, c.near, c.far]).collect();
        for l in &scene.lights {
            match l.kind {
                LightKind::Directional { direction } => f.extend([0.0].into_iter().chain(direction.to_array())),
                LightKind::Spot { position, direction, cutoff_deg, exponent, attenuation } => {
                    f.extend([1.0].into_iter().chain(position.to_array()).chain(direction.to_array()).chain([cutoff_deg, exponent]).chain(attenuation))
                }
            }
            f.extend(l.ambient.into_iter().chain(l.diffuse).chain(l.specular).chain([if l.cast_shadow { 1.0 } else { 0.0 }]));
        }
        let h = &scene.headlight;
        f.extend([if h.active { 1.0 } else { 0.0 }].into_iter().chain(h.ambient).chain(h.diffuse).chain(h.specular));
        match scene.background {
            Background::Solid(c) => f.extend(c),
            Background::Gradient { up, down } => f.extend([f32::NAN].into_iter().chain(up).chain(down)),
        }
        if let Some(m) = &scene.mirror {
            f.extend([m.instance as f32, m.face_z, m.reflectance]);
        }
        let mut bits: Vec<u32> = vec![c.width, c.height, scene.lights.len() as u32, scene.mirror.is_some() as u32];
        bits.extend(f.into_iter().map(f32::to_bits));
        Key(bits)
    }
}
