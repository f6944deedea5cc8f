//! Pinhole cameras with MuJoCo's pose convention and the paper's pixel convention.
//!
//! Pose: a world position and a camera-to-world rotation (MuJoCo quaternion `w, x, y, z` or
//! `xmat`); the camera looks along its local −z with +y up and +x right.
//!
//! Pixels (paper appendix, "Scene-Anchored Placement"): `u` is the column and `v` the row from
//! the top of the upright image; pixel centres are at integer `(u, v)`;
//! `f_x = f_y = H / (2 tan(fovy / 2))`, `c_x = (W − 1) / 2`, `c_y = (H − 1) / 2`;
//! `u = f_x x_c / z_c + c_x`, `v = f_y y_c / z_c + c_y` with camera coordinates `x_c` right,
//! `y_c` down, `z_c` forward. The rasterizer samples coverage at exactly these pixel centres, so
//! a point projected here lands on the pixel the renderer draws it in.

use glam::{Mat3, Vec3};

use crate::transform::{cross, dot, mat3_from_mj_xmat, mul_mat3, normalize, quat_wxyz_to_mat3};

/// Focal lengths and principal point in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    pub fx: f32,
    pub fy: f32,
    pub cx: f32,
    pub cy: f32,
}

/// A projected point: pixel coordinates and distance along the view axis (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    pub u: f32,
    pub v: f32,
    pub depth: f32,
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Camera centre in world coordinates.
    pub position: Vec3,
    /// Camera-to-world rotation; columns are the camera's x (right), y (up) and z (backwards)
    /// axes in world coordinates.
    pub rotation: Mat3,
    /// Vertical field of view in degrees (MuJoCo `fovy`, default 45).
    pub fovy_deg: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Near clipping distance in metres: surfaces closer than this along the view axis are cut
    /// away.
    pub near: f32,
    /// Far distance in metres: instances entirely beyond it are skipped.
    pub far: f32,
}

/// Default near distance (m): close enough for a wrist camera a few centimetres from objects.
pub const DEFAULT_NEAR: f32 = 0.005;
/// Default far distance (m).
pub const DEFAULT_FAR: f32 = 100.0;

impl Camera {
    /// A camera at `position` with MuJoCo orientation `quat_wxyz` (camera to world).
    pub fn new(position: Vec3, quat_wxyz: [f32; 4], fovy_deg: f32, width: u32, height: u32) -> Camera {
        Camera::from_rotation(position, quat_wxyz_to_mat3(quat_wxyz), fovy_deg, width, height)
    }

    /// A camera from MuJoCo's world position and row-major `cam_xmat`.
    pub fn from_mj_xmat(position: Vec3, xmat: [f32; 9], fovy_deg: f32, width: u32, height: u32) -> Camera {
        Camera::from_rotation(position, mat3_from_mj_xmat(xmat), fovy_deg, width, height)
    }

    /// A camera from a camera-to-world rotation matrix.
    pub fn from_rotation(position: Vec3, rotation: Mat3, fovy_deg: f32, width: u32, height: u32) -> Camera {
        Camera { position, rotation, fovy_deg, width, height, near: DEFAULT_NEAR, far: DEFAULT_FAR }
    }

    /// A camera at `eye` looking at `target`, with `up` (world) appearing upwards in the image
    /// (`up` must not be parallel to the viewing direction).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fovy_deg: f32, width: u32, height: u32) -> Camera {
        let back = normalize(eye - target);
        let right = normalize(cross(up, back));
        let cam_up = cross(back, right);
        Camera::from_rotation(eye, Mat3::from_cols(right, cam_up, back), fovy_deg, width, height)
    }

    /// The same camera with other clipping distances.
    pub fn with_clip(mut self, near: f32, far: f32) -> Camera {
        self.near = near;
        self.far = far;
        self
    }

    /// The same camera rendering `factor` times more pixels in each direction (for
    /// supersampling): pixel `(u, v)` of this camera is the centre of the `factor × factor` block
    /// starting at `(factor·u, factor·v)` of the result.
    pub fn scaled(&self, factor: u32) -> Camera {
        Camera { width: self.width * factor, height: self.height * factor, ..*self }
    }

    /// Intrinsics for this image size and field of view.
    pub fn intrinsics(&self) -> Intrinsics {
        let half = 0.5 * self.fovy_deg.to_radians();
        let f = self.height as f32 / (2.0 * libm::tanf(half));
        Intrinsics { fx: f, fy: f, cx: (self.width as f32 - 1.0) * 0.5, cy: (self.height as f32 - 1.0) * 0.5 }
    }

    /// World direction the camera looks along.
    pub fn forward(&self) -> Vec3 {
        -self.rotation.z_axis
    }

    /// World direction that appears upwards in the image.
    pub fn up(&self) -> Vec3 {
        self.rotation.y_axis
    }

    /// World direction that appears to the right in the image.
    pub fn right(&self) -> Vec3 {
        self.rotation.x_axis
    }

    /// World point in renderer camera coordinates: x right, y down, z forward (metres).
    pub fn world_to_camera(&self, p: Vec3) -> Vec3 {
        self.direction_to_camera(p - self.position)
    }

    /// A world direction in renderer camera coordinates (rotation only).
    pub fn direction_to_camera(&self, v: Vec3) -> Vec3 {
        let r = &self.rotation;
        Vec3::new(dot(r.x_axis, v), -dot(r.y_axis, v), -dot(r.z_axis, v))
    }

    /// Renderer camera coordinates back to world coordinates.
    pub fn camera_to_world(&self, c: Vec3) -> Vec3 {
        mul_mat3(&self.rotation, Vec3::new(c.x, -c.y, -c.z)) + self.position
    }

    /// Pixel position and view-axis depth of a world point, or `None` if it is not in front of
    /// the camera (`z_c ≤ 0`). Points outside the image still project; see
    /// [`Camera::contains`].
    pub fn project(&self, p: Vec3) -> Option<Projection> {
        let c = self.world_to_camera(p);
        if !(c.z > 0.0) {
            return None;
        }
        let k = self.intrinsics();
        Some(Projection { u: k.fx * (c.x / c.z) + k.cx, v: k.fy * (c.y / c.z) + k.cy, depth: c.z })
    }

    /// The world point seen at pixel `(u, v)` at view-axis depth `depth`.
    pub fn unproject(&self, u: f32, v: f32, depth: f32) -> Vec3 {
        let k = self.intrinsics();
        let c = Vec3::new((u - k.cx) / k.fx * depth, (v - k.cy) / k.fy * depth, depth);
        self.camera_to_world(c)
    }

    /// The viewing ray through pixel `(u, v)`: camera centre and unit world direction.
    pub fn ray(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let p = self.unproject(u, v, 1.0);
        (self.position, normalize(p - self.position))
    }

    /// True if `(u, v)` lies within the image (pixel centres span `[0, W − 1] × [0, H − 1]`,
    /// each pixel extends half a pixel around its centre).
    pub fn contains(&self, u: f32, v: f32) -> bool {
        u >= -0.5 && v >= -0.5 && u < self.width as f32 - 0.5 && v < self.height as f32 - 0.5
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn agentview(w: u32, h: u32) -> Camera {
        // LIBERO Tabletop agentview (model_facts.json).
        Camera::new(
            Vec3::new(0.658_613_2, 0.0, 1.610_35),
            [0.638_017_7, 0.304_849_7, 0.304_849_8, 0.638_017_7],
            45.0,
            w,
            h,
        )
    }

    #[test]
    fn intrinsics_follow_the_paper() {
        let k = agentview(256, 128).intrinsics();
        assert!((k.fy - 128.0 / (2.0 * (22.5f32).to_radians().tan())).abs() < 1e-3);
        assert_eq!(k.fx, k.fy);
        assert_eq!((k.cx, k.cy), (127.5, 63.5));
    }

    #[test]
    fn principal_point_is_on_the_axis() {
        let cam = agentview(256, 256);
        let p = cam.project(cam.position + cam.forward() * 2.0).unwrap();
        assert!((p.u - 127.5).abs() < 1e-4 && (p.v - 127.5).abs() < 1e-4);
        assert!((p.depth - 2.0).abs() < 1e-5);
        assert!(cam.project(cam.position - cam.forward()).is_none());
    }

    #[test]
    fn fovy_edge_maps_to_image_edge() {
        let cam = Camera::look_at(Vec3::ZERO, Vec3::X, Vec3::Z, 90.0, 100, 100);
        // 45° above the axis is the top edge of the image: v = c_y − f = −0.5.
        let p = cam.project(Vec3::new(1.0, 0.0, 1.0)).unwrap();
        assert!((p.v + 0.5).abs() < 1e-4, "{p:?}");
        // Up is up and right is right.
        let r = cam.project(Vec3::new(1.0, -0.5, 0.0)).unwrap();
        assert!(r.u > 49.5);
    }

    #[test]
    fn project_unproject_round_trip() {
        let cam = agentview(224, 160);
        for &p in &[Vec3::new(0.1, -0.2, 0.9), Vec3::new(-0.4, 0.3, 0.95), Vec3::new(0.0, 0.0, 0.0)] {
            let q = cam.project(p).unwrap();
            let back = cam.unproject(q.u, q.v, q.depth);
            assert!((back - p).length() < 1e-5, "{p} -> {q:?} -> {back}");
        }
        let (o, d) = cam.ray(10.0, 20.0);
        let q = cam.project(o + d * 0.7).unwrap();
        assert!((q.u - 10.0).abs() < 1e-3 && (q.v - 20.0).abs() < 1e-3);
    }

    #[test]
    fn agentview_looks_down_at_the_robot() {
        let cam = agentview(256, 256);
        let f = cam.forward();
        // model_facts: view direction about (−0.778, 0, −0.628).
        assert!((f - Vec3::new(-0.778, 0.0, -0.628)).length() < 2e-3, "{f}");
        assert!(cam.up().z > 0.0);
    }
}
