//! F3 ghost layers: the manipulated object alone at K future poses, rendered from the frame's
//! camera into RGBA layers (opaque where the object is, transparent elsewhere).
//!
//! The poses are fixed for the episode, so the K one-object scenes are built once; layers only
//! need rendering again when the camera moves. The last two cameras' layers are kept, so the
//! fixed agentview costs nothing after its first frame while the wrist camera re-renders.

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
                    renderer.render_into(scene, camera, &mut self.scratch)?;
                    let mut layer = layer_of(&self.scratch);
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

/// A rendered frame as an RGBA layer: opaque where something was drawn (segment ≠ 0). The
/// object covers little of the frame, so runs of eight background pixels are skipped at once.
fn layer_of(frame: &Frame) -> RgbaImage {
    const RUN: usize = 8;
    let mut data = vec![0u8; frame.segmentation.len() * 4];
    let runs = data.chunks_mut(4 * RUN).zip(frame.color.data.chunks(3 * RUN)).zip(frame.segmentation.chunks(RUN));
    for ((out, rgb), segments) in runs.filter(|(_, segments)| segments.iter().any(|&s| s != 0)) {
        for ((out, rgb), &segment) in out.chunks_exact_mut(4).zip(rgb.chunks_exact(3)).zip(segments) {
            if segment != 0 {
                out.copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
            }
        }
    }
    RgbaImage { width: frame.width(), height: frame.height(), data }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_layer_is_opaque_exactly_where_something_was_drawn() {
        // An odd width, so runs of eight cross rows; drawn pixels alone, in a patch and at the ends.
        let (w, h) = (13, 7);
        let mut frame = Frame::new(w, h);
        for (i, px) in frame.color.data.chunks_exact_mut(3).enumerate() {
            px.copy_from_slice(&[i as u8, (3 * i) as u8, 200]);
        }
        let drawn = [0, 17, 18, 19, 30, 31, 44, 45, 46, 90];
        for &i in &drawn {
            frame.segmentation[i] = 1 + i as u32;
        }
        let layer = layer_of(&frame);
        assert_eq!((layer.width, layer.height), (w, h));
        for (i, px) in layer.data.chunks_exact(4).enumerate() {
            let want = if drawn.contains(&i) { [i as u8, (3 * i) as u8, 200, 255] } else { [0; 4] };
            assert_eq!(px, want, "pixel {i}");
        }
    }
}
