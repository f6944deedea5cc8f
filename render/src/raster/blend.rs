//! The transparency pass: instances with alpha < 1, back to front, blended over the resolved
//! opaque pixels (each triangle shaded as it is drawn; nothing is written to the visibility
//! buffer).

use super::assemble::Frontend;
use super::resolve::{build_record, shade, texture_of, to_u8};
use super::triangle::Setup;
use super::view::View;
use super::{Renderer, ScreenVert, Visible};
use crate::frame::Frame;
use crate::scene::Scene;

impl Renderer {
    /// Draws one transparent instance over `out`, where it lies in front of the opaque pixels.
    pub(super) fn draw_blended(&mut self, scene: &Scene, visible: &Visible, view: &View, out: &mut Frame) {
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
}
