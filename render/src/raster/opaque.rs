//! The opaque pass: triangles depth-tested into the visibility buffer span by span, and the
//! records of those that won pixels.

use super::assemble::{Corners, Deferred, Frontend, Sink};
use super::hiz::HiZ;
use super::layer::{self, PixelBox};
use super::resolve::build_record;
use super::triangle::{Plane, Planes, Setup};
use super::view::{PlaneTest, View};
use super::{Renderer, ScreenVert, TriRecord, Visible};
use crate::scene::{Instance, Scene};

impl Renderer {
    /// Draws one opaque instance into the visibility buffer. With `layer_records`, the buffer
    /// starts from the camera's static layer, whose records are the first `layer_records`.
    pub(super) fn draw_opaque(&mut self, scene: &Scene, visible: &Visible, view: &View, layer_records: Option<u32>) {
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
