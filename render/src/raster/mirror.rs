//! MuJoCo's one reflective surface: the scene drawn again from the mirrored camera and added
//! to the pixels that show the mirror's face.

use glam::{Mat3, Vec3};

use super::layer::Plan;
use super::view::{PlaneTest, View};
use super::{Renderer, NO_TRIANGLE};
use crate::camera::Camera;
use crate::frame::Frame;
use crate::scene::{Background, Instance, Light, LightKind, Mirror, Scene};
use crate::transform::{cross, dot, mul_mat3, normalize};

impl Renderer {
    /// Adds what `mirror` reflects to the pixels of `out` that show its face, as MuJoCo does:
    /// the other instances, colours scaled by the reflectance, drawn from the camera mirrored in
    /// the face's plane and clipped to the plane's outer side, over black. The mirrored camera
    /// is turned right-handed again by flipping its x axis, so its image is read mirrored
    /// (column `W − 1 − i`). Lighting is unchanged by the mirroring, except MuJoCo's headlight,
    /// which keeps shining along the real camera's view axis.
    pub(super) fn reflect(&mut self, scene: &Scene, camera: &Camera, mirror: &Mirror, out: &mut Frame) {
        let Some(face) = scene.instances.get(mirror.instance) else { return };
        let t = &face.transform;
        let point = t.transform_point(Vec3::new(0.0, 0.0, mirror.face_z));
        let normal = normalize(cross(t.linear.x_axis, t.linear.y_axis));
        let height = dot(normal, camera.position - point);
        if !(height > 0.0 && mirror.reflectance > 0.0) {
            return;
        }
        // The face's pixels: the mirror's own triangles lying in its plane (within 1 mm).
        // They lie where the mirror's bounding sphere projects (all pixels where it reaches
        // behind the eye): a stove's top covers a few hundred of agentview's 65,536.
        let view = View::new(camera);
        let b = face.mesh.bounds();
        let centre = mul_mat3(&view.rot, t.transform_point(b.center) - view.position);
        let w = camera.width as usize;
        let [x0, y0, x1, y1] = view.sphere_cover(centre, b.radius * t.max_scale()).map_or([0, 0, camera.width - 1, camera.height - 1], |(rect, _)| rect);
        let on_plane = PlaneTest::new(&view, point, normal);
        let mut pixels = std::mem::take(&mut self.mirror_pixels);
        pixels.clear();
        let on_face = |id: u32| id != NO_TRIANGLE && self.records[id as usize].instance as usize == mirror.instance;
        let (mut last_id, mut last_on) = (NO_TRIANGLE, false);
        for j in y0 as usize..=y1 as usize {
            for p in j * w + x0 as usize..=j * w + x1 as usize {
                let id = self.tri_id[p];
                if id != last_id {
                    (last_id, last_on) = (id, on_face(id));
                }
                if last_on {
                    let iz = self.depth[p];
                    if (on_plane.at((p % w) as f32, j as f32, iz) / iz).abs() < 1e-3 {
                        pixels.push(p as u32);
                    }
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
}

/// Bounding box `(x0, y0, x1, y1)` of pixel indices in an image `width` wide.
fn bounds(pixels: &[u32], width: usize) -> Option<(u32, u32, u32, u32)> {
    let w = width as u32;
    let (first, last) = (*pixels.first()?, *pixels.last()?);
    let (x0, x1) = pixels.iter().fold((u32::MAX, 0), |(lo, hi), &p| (lo.min(p % w), hi.max(p % w)));
    Some((x0, first / w, x1, last / w))
}
