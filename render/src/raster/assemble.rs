//! The geometry stage: an instance's clusters culled, its vertices transformed (see
//! [`super::vertex`]), its triangles culled, clipped and set up, and the [`Sink`] each pass
//! gives it to send them to; vertices are lit only for triangles the sink keeps.

use glam::{Mat3, Vec2, Vec3};

use super::clip::{ClipVert, Polygon, SphereClass, MUST_CLIP, REJECT};
use super::lighting::{self, LightRig, Lit, VERTEX_LANES};
use super::triangle::{box_holds_centre, orientation, Planes, Setup};
use super::vertex::{ToScreen, Verts};
use super::view::View;
use super::ScreenVert;
use crate::cluster::Cluster;
use crate::scene::Instance;
use crate::transform::{cross, dot, mul_mat3, mul_mat3_mat3, normalize};

/// Borrowed per-instance state for geometry processing.
pub(super) struct Frontend<'a> {
    pub(super) verts: &'a mut Verts,
    pub(super) lit: &'a mut LitCache,
    pub(super) poly: &'a mut Polygon,
    pub(super) rig: &'a LightRig,
}

impl Frontend<'_> {
    /// Transforms, culls, clips and lights one instance, sending `sink` each screen triangle
    /// that covers a pixel centre (vertices are lit only when the sink asks).
    pub(super) fn assemble(&mut self, inst: &Instance, inside: bool, view: &View, sink: &mut impl Sink) -> Assembled {
        let mesh = &*inst.mesh;
        let t = &inst.transform;
        let linear = mul_mat3_mat3(&view.rot, &t.linear);
        let trans = mul_mat3(&view.rot, t.translation - view.position);
        let to_screen = ToScreen::new(linear, trans, inside, view);
        let uvs = inst.material.texture.as_ref().and(mesh.uvs());
        let points = mesh.points();
        let placed = Placed {
            point_of: &points.of_vertex,
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
        if sphere_hidden(view, sink, mul_mat3(&linear, b.center) + trans, b.radius * scale) {
            done.hidden += 1;
            return done;
        }
        self.lit.begin(mesh.vertex_count());
        let clusters = mesh.clusters();
        if clusters.list.is_empty() {
            self.verts.fill(&points.list, &to_screen);
            placed.draw(mesh.triangles(), &points.triangles, &*self.verts, &mut *self.lit, &mut *self.poly, view, sink);
        } else {
            self.verts.begin(points.list.len());
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
                if sphere_hidden(view, sink, centre, c.radius * scale) {
                    done.hidden += 1;
                    continue;
                }
                let used = &clusters.points[c.first_point as usize..(c.first_point + c.point_count) as usize];
                self.verts.ensure(used, &points.list, &to_screen);
                let range = c.first as usize..(c.first + c.count) as usize;
                placed.draw(&mesh.triangles()[range.clone()], &points.triangles[range], &*self.verts, &mut *self.lit, &mut *self.poly, view, sink);
            }
        }
        done.lit = self.lit.count;
        done
    }
}

/// What [`Frontend::assemble`] did with one instance, for [`RenderStats`](super::RenderStats).
#[derive(Clone, Copy, Default)]
pub(super) struct Assembled {
    pub(super) lit: usize,
    pub(super) culled: usize,
    pub(super) hidden: usize,
}

/// Where the geometry stage sends what it assembled.
pub(super) trait Sink {
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
pub(super) struct Corners {
    pub(super) ids: [u32; 3],
    pub(super) back: bool,
}

/// A triangle that won pixels and waits for its corners' colours.
pub(super) struct Deferred {
    pub(super) planes: Planes,
    pub(super) corners: Corners,
}

/// Whether `sink` says a camera-space sphere is hidden behind what is drawn: it must lie in
/// front of the eye, and its nearest point behind every pixel its projection can cover.
fn sphere_hidden(view: &View, sink: &mut impl Sink, centre: Vec3, radius: f32) -> bool {
    view.sphere_cover(centre, radius).is_some_and(|(rect, nearest)| sink.hidden(rect, nearest))
}

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
    /// Each vertex's position in [`Verts`].
    point_of: &'a [u32],
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
    /// Culls, clips and emits `tris`, whose positions are in `verts`.
    // The per-frame buffers are borrowed separately, as the callers hold them.
    #[allow(clippy::too_many_arguments)]
    fn draw(&self, tris: &[[u32; 3]], tri_points: &[[u32; 3]], verts: &Verts, lit: &mut LitCache, poly: &mut Polygon, view: &View, sink: &mut impl Sink) {
        let (w, h) = (view.width, view.height);
        let uv_of = |i: usize| self.uv(i);
        let cam = |i: usize| verts.cam[self.point_of[i] as usize];
        let light = |i: usize, back: bool| {
            let nrm = mul_mat3(&self.normal_m, self.normals[i]);
            self.rig.shade(&self.surface, cam(i), if back { -nrm } else { nrm })
        };
        let double_sided = self.double_sided;

        for (tri, points) in tris.iter().zip(tri_points) {
            let [a, b, c] = tri.map(|i| i as usize);
            let [pa, pb, pc] = points.map(|p| p as usize);
            let (ca, cb, cc) = (verts.code[pa], verts.code[pb], verts.code[pc]);
            if ca & cb & cc & REJECT != 0 {
                continue;
            }
            let clip_bits = (ca | cb | cc) & MUST_CLIP;
            if clip_bits == 0 {
                if !box_holds_centre([verts.xy[pa], verts.xy[pb], verts.xy[pc]]) {
                    continue;
                }
                let xy = |p: usize| verts.screen(p);
                let o = orientation([xy(pa), xy(pb), xy(pc)]);
                // Counter-clockwise front faces have negative orientation on screen (y down);
                // setup wants positive, so front faces swap their last two vertices.
                let back = o > 0;
                if o == 0 || (back && !double_sided) {
                    continue;
                }
                let ((b, pb), (c, pc)) = if back { ((b, pb), (c, pc)) } else { ((c, pc), (b, pb)) };
                let Some(setup) = &Setup::new([xy(pa), xy(pb), xy(pc)], w, h) else { continue };
                let sv = |i: usize, lit: Lit| self.screen_vert(verts, i, lit);
                let lit = &mut *lit;
                let corners = Corners { ids: [a as u32, b as u32, c as u32], back };
                sink.triangle(setup, [verts.iz[pa], verts.iz[pb], verts.iz[pc]], Some(corners), &mut || {
                    let (la, lb, lc) = (lit.get(a, back, &light), lit.get(b, back, &light), lit.get(c, back, &light));
                    [sv(a, la), sv(b, lb), sv(c, lc)]
                });
            } else {
                // Facing from camera space: the eye is at the origin.
                let [qa, qb, qc] = [a, b, c].map(cam);
                let facing = dot(cross(qb - qa, qc - qa), qa);
                let back = facing > 0.0;
                if !(facing != 0.0) || (back && !double_sided) {
                    continue;
                }
                self.commit(verts, lit, sink);
                let cv = |i: usize, lit: Lit| ClipVert { p: cam(i), lit, uv: uv_of(i) };
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
                let cam = verts.cam[self.point_of[v] as usize];
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
        let p = self.point_of[i] as usize;
        ScreenVert { xy: verts.screen(p), iz: verts.iz[p], lit, uv: self.uv(i) }
    }
}

/// Lit vertex colours of the current instance, computed on first use. Two slots per vertex
/// (front and back side); a slot is valid when its stamp equals the instance's, so starting a
/// new instance costs nothing per vertex.
#[derive(Default)]
pub(super) struct LitCache {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
