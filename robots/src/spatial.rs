//! Small fixed-size spatial algebra in f64 (nalgebra statics only, so results never depend on
//! FMA or SIMD kernel choice, natively or in wasm).

use nalgebra::{Matrix3, Quaternion, SVector, UnitQuaternion, Vector3};

pub type Vec3 = Vector3<f64>;
pub type Mat3 = Matrix3<f64>;
pub type Quat = UnitQuaternion<f64>;
/// Generalized vector of an arm with `N` degrees of freedom (joint positions, velocities, forces).
pub type Coords<const N: usize> = SVector<f64, N>;

/// A rigid transform: `x_world = rot * x_local + pos`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub pos: Vec3,
    pub rot: Mat3,
}

impl Pose {
    pub const IDENTITY: Pose = Pose { pos: Vec3::new(0.0, 0.0, 0.0), rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0) };

    pub fn new(pos: Vec3, rot: Mat3) -> Self {
        Pose { pos, rot }
    }

    /// From a position and a MuJoCo-order quaternion (w, x, y, z), normalised as MuJoCo's
    /// compiler does (robosuite writes rounded values such as (0.924, 0, 0, -0.383)).
    pub fn from_wxyz(pos: [f64; 3], wxyz: [f64; 4]) -> Self {
        Pose { pos: Vec3::from(pos), rot: quat_wxyz(wxyz).to_rotation_matrix().into_inner() }
    }

    /// From a URDF origin: `xyz` and fixed-axis roll-pitch-yaw, R = Rz(yaw)·Ry(pitch)·Rx(roll).
    pub fn from_urdf(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        let r = axis_angle(&Vec3::z(), rpy[2]) * axis_angle(&Vec3::y(), rpy[1]) * axis_angle(&Vec3::x(), rpy[0]);
        Pose { pos: Vec3::from(xyz), rot: r }
    }

    /// `self * other`: `other` expressed in `self`'s frame, composed.
    pub fn mul(&self, other: &Pose) -> Pose {
        Pose { pos: self.rot * other.pos + self.pos, rot: self.rot * other.rot }
    }

    pub fn transform_point(&self, p: &Vec3) -> Vec3 {
        self.rot * p + self.pos
    }

    pub fn inverse(&self) -> Pose {
        let rt = self.rot.transpose();
        Pose { pos: -(rt * self.pos), rot: rt }
    }

    /// Orientation as a MuJoCo-order quaternion (w, x, y, z) with w ≥ 0.
    pub fn quat_wxyz(&self) -> [f64; 4] {
        mat_to_wxyz(&self.rot)
    }
}

/// A unit quaternion from MuJoCo order (w, x, y, z), normalised.
pub fn quat_wxyz(q: [f64; 4]) -> Quat {
    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]))
}

/// Rotation matrix to (w, x, y, z), sign chosen so that w ≥ 0.
pub fn mat_to_wxyz(m: &Mat3) -> [f64; 4] {
    let q = UnitQuaternion::from_matrix_eps(m, 1e-15, 100, UnitQuaternion::identity());
    let q = q.into_inner();
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.w, s * q.i, s * q.j, s * q.k]
}

/// Rotation by `angle` about the unit vector `axis` (Rodrigues), using libm so the bits are the
/// same on every platform.
pub fn axis_angle(axis: &Vec3, angle: f64) -> Mat3 {
    let (s, c) = (libm::sin(angle), libm::cos(angle));
    let t = 1.0 - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    Mat3::new(
        t * x * x + c,
        t * x * y - s * z,
        t * x * z + s * y,
        t * x * y + s * z,
        t * y * y + c,
        t * y * z - s * x,
        t * x * z - s * y,
        t * y * z + s * x,
        t * z * z + c,
    )
}

/// robosuite's `quat2mat(axisangle2quat(v))`: the rotation for an axis-angle vector, identity
/// when the vector is exactly zero.
pub fn rotation_from_axis_angle_vector(v: &Vec3) -> Mat3 {
    let angle = v.norm();
    if angle == 0.0 {
        return Mat3::identity();
    }
    axis_angle(&(v / angle), angle)
}

/// The rotation vector (axis × angle) of a rotation matrix, angle in [0, π].
pub fn rotation_vector(m: &Mat3) -> Vec3 {
    let q = quat_wxyz(mat_to_wxyz(m));
    let v = Vec3::new(q.i, q.j, q.k);
    let sin_half = v.norm();
    if sin_half < 1e-300 {
        return Vec3::zeros();
    }
    let angle = 2.0 * libm::atan2(sin_half, q.w);
    v * (angle / sin_half)
}

/// Angle in radians between two orientations.
pub fn angle_between(a: &Mat3, b: &Mat3) -> f64 {
    rotation_vector(&(a.transpose() * b)).norm()
}

/// Skew-symmetric cross-product matrix `[v]×`.
pub fn skew(v: &Vec3) -> Mat3 {
    Mat3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_angle_matches_quaternion_rotation() {
        let axis = Vec3::new(1.0, 2.0, -0.5).normalize();
        let m = axis_angle(&axis, 0.7);
        let q = UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), 0.7);
        assert!((m - q.to_rotation_matrix().into_inner()).norm() < 1e-14);
        let back = rotation_vector(&m);
        assert!((back - axis * 0.7).norm() < 1e-12);
    }

    #[test]
    fn wxyz_round_trip_normalises() {
        let p = Pose::from_wxyz([0.0; 3], [0.924, 0.0, 0.0, -0.383]);
        let q = p.quat_wxyz();
        let n = (q[0] * q[0] + q[3] * q[3]).sqrt();
        assert!((n - 1.0).abs() < 1e-12);
        assert!((q[0] - 0.924 / (0.924f64.powi(2) + 0.383f64.powi(2)).sqrt()).abs() < 1e-12);
    }
}
