//! F3 ghost layers: the manipulated object alone at K future poses, rendered from the frame's
//! camera into RGBA layers (opaque where the object is, transparent elsewhere).
//!
//! The poses are fixed for the episode, so the K one-object scenes are built once; layers only
//! need rendering again when the camera moves. The last two cameras' layers are kept, so the
//! fixed agentview costs nothing after its first frame while the wrist camera re-renders. Each
//! render shades only the box of pixels its object covers ([`Renderer::render_covered`]).

use vifo_cues::RgbaImage;
use vifo_render::{Camera, Frame, RenderError, Renderer, Scene};
use vifo_robots::spatial::Pose;
use vifo_scenes::sim::Sim;
use vifo_scenes::view::SceneView;

/// Cameras whose layers are kept (agentview and the wrist camera, called alternately).
const KEPT: usize = 2;

pub struct Ghost {
    scenes: Vec<Scene>,
    /// Most recently used first.
    kept: Vec<(Camera, Vec<RgbaImage>)>,
    scratch: Frame,
    /// Layers are made mirrored left–right (for a cue facing the model, [`super::CueFacing`]).
    mirrored: bool,
}

impl Ghost {
    /// Ghosts of `entity` at `poses` (in time order), looking as it does in `view`.
    pub fn new(view: &SceneView, sim: &Sim, entity: usize, poses: &[Pose]) -> Ghost {
        let scenes = poses.iter().map(|p| view.entity_scene(sim, entity, p)).collect();
        Ghost { scenes, kept: Vec::new(), scratch: Frame::default(), mirrored: false }
    }

    /// Makes the layers mirrored left–right from now on (or not).
    pub fn set_mirrored(&mut self, mirrored: bool) {
        if mirrored != self.mirrored {
            self.kept.clear();
            self.mirrored = mirrored;
        }
    }

    /// Number of layers.
    pub fn len(&self) -> usize {
        self.scenes.len()
    }

    /// The layers as `camera` sees them.
    pub fn layers(&mut self, renderer: &mut Renderer, camera: &Camera) -> Result<&[RgbaImage], RenderError> {
        match self.kept.iter().position(|(c, _)| c == camera) {
            Some(i) => {
                let entry = self.kept.remove(i);
                self.kept.insert(0, entry);
            }
            None => {
                let mut layers = Vec::with_capacity(self.scenes.len());
                for scene in &self.scenes {
                    // Only the object's pixels are shaded: the rest of the layer is transparent.
                    let drawn = renderer.render_covered(scene, camera, &mut self.scratch)?;
                    let mut layer = layer_of(&self.scratch, drawn);
                    if self.mirrored {
                        layer.mirror_left_right();
                    }
                    layers.push(layer);
                }
                self.kept.insert(0, (*camera, layers));
                self.kept.truncate(KEPT);
            }
        }
        Ok(&self.kept[0].1)
    }
}

/// A rendered frame as an RGBA layer: opaque where something was drawn (segment ≠ 0) inside
/// `drawn` (inclusive `[x0, y0, x1, y1]`, the box [`Renderer::render_covered`] wrote), transparent
/// elsewhere.
fn layer_of(frame: &Frame, drawn: Option<[u32; 4]>) -> RgbaImage {
    let (w, h) = (frame.width(), frame.height());
    let mut data = vec![0u8; frame.segmentation.len() * 4];
    if let Some([x0, y0, x1, y1]) = drawn {
        let columns = x0 as usize..=x1.min(w - 1) as usize;
        for y in y0 as usize..=y1.min(h - 1) as usize {
            for x in columns.clone() {
                let p = y * w as usize + x;
                if frame.segmentation[p] != 0 {
                    let rgb = &frame.color.data[3 * p..3 * p + 3];
                    data[4 * p..4 * p + 4].copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
                }
            }
        }
    }
    RgbaImage { width: w, height: h, data }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layer_is_opaque_exactly_where_something_was_drawn_inside_the_box() {
        let (w, h) = (13, 7);
        let mut frame = Frame::new(w, h);
        for (i, px) in frame.color.data.chunks_exact_mut(3).enumerate() {
            px.copy_from_slice(&[i as u8, (3 * i) as u8, 200]);
        }
        // Drawn pixels at the box's corners and inside it, and one outside (stale: not taken).
        let drawn = [2 * 13 + 3, 2 * 13 + 9, 3 * 13 + 5, 5 * 13 + 3, 5 * 13 + 9];
        for &i in drawn.iter().chain(&[6 * 13 + 12]) {
            frame.segmentation[i] = 1 + i as u32;
        }
        let layer = layer_of(&frame, Some([3, 2, 9, 5]));
        assert_eq!((layer.width, layer.height), (w, h));
        for (i, px) in layer.data.chunks_exact(4).enumerate() {
            let want = if drawn.contains(&i) { [i as u8, (3 * i) as u8, 200, 255] } else { [0; 4] };
            assert_eq!(px, want, "pixel {i}");
        }
        assert!(layer_of(&frame, None).data.iter().all(|&b| b == 0));
    }
}
