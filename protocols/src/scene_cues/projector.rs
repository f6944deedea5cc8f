//! The renderer's camera as the cue library's [`Projector`].

use vifo_cues::Projector;
use vifo_render::Camera;
use vifo_render::glam::Vec3;

/// Projects world points with [`Camera::project`]: the paper's equations, the same pixels the
/// rasterizer draws (checked against MuJoCo's cameras by `vifo xval --projection`).
pub struct CameraProjector<'a>(pub &'a Camera);

impl Projector for CameraProjector<'_> {
    fn project(&self, world: [f64; 3]) -> Option<[f64; 3]> {
        let p = self.0.project(Vec3::new(world[0] as f32, world[1] as f32, world[2] as f32))?;
        Some([p.u as f64, p.v as f64, p.depth as f64])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vifo_cues::PinholeCamera;

    #[test]
    fn agrees_with_the_cue_library_pinhole_camera() {
        let camera = Camera::look_at(Vec3::new(1.0, 0.2, 1.5), Vec3::new(0.0, 0.0, 0.9), Vec3::Z, 45.0, 256, 200);
        let r = camera.rotation;
        let pinhole = PinholeCamera {
            position: camera.position.to_array().map(f64::from),
            rotation: [0, 1, 2].map(|i| [r.x_axis[i], r.y_axis[i], r.z_axis[i]].map(f64::from)),
            fovy_deg: 45.0,
            width: 256,
            height: 200,
        };
        for p in [[0.0, 0.0, 0.9], [0.2, -0.3, 1.0], [-0.4, 0.5, 0.8]] {
            let a = CameraProjector(&camera).project(p).unwrap();
            let b = pinhole.project(p).unwrap();
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-3), "{a:?} vs {b:?}");
        }
        // Behind the camera: no projection.
        assert!(CameraProjector(&camera).project([2.0, 0.4, 2.1]).is_none());
    }
}
