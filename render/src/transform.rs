//! Rigid-plus-scale transforms and MuJoCo quaternion conversion.
//!
//! Everything is plain scalar `f32` arithmetic in a fixed order (no FMA, no SIMD reductions), so
//! results are the same bits natively and in wasm.

use glam::{Mat3, Mat4, Vec3};

/// Rotation matrix of a MuJoCo quaternion `(w, x, y, z)`.
///
/// The quaternion is normalised first, as MuJoCo does; a zero quaternion gives the identity.
pub fn quat_wxyz_to_mat3(q: [f32; 4]) -> Mat3 {
    let [w, x, y, z] = q;
    let n = (w * w + x * x + y * y + z * z).sqrt();
    if !(n > 0.0) || !n.is_finite() {
        return Mat3::IDENTITY;
    }
    let (w, x, y, z) = (w / n, x / n, y / n, z / n);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    // Columns are the images of the basis vectors.
    Mat3::from_cols(
        Vec3::new(1.0 - 2.0 * (yy + zz), 2.0 * (xy + wz), 2.0 * (xz - wy)),
        Vec3::new(2.0 * (xy - wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz + wx)),
        Vec3::new(2.0 * (xz + wy), 2.0 * (yz - wx), 1.0 - 2.0 * (xx + yy)),
    )
}

/// Rotation matrix from MuJoCo's row-major `xmat` (as `model_facts.json` and `mjData.xmat` give it).
pub fn mat3_from_mj_xmat(m: [f32; 9]) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(m[0], m[3], m[6]),
        Vec3::new(m[1], m[4], m[7]),
        Vec3::new(m[2], m[5], m[8]),
    )
}

/// `m * v` with a fixed evaluation order.
#[inline]
pub(crate) fn mul_mat3(m: &Mat3, v: Vec3) -> Vec3 {
    Vec3::new(
        m.x_axis.x * v.x + m.y_axis.x * v.y + m.z_axis.x * v.z,
        m.x_axis.y * v.x + m.y_axis.y * v.y + m.z_axis.y * v.z,
        m.x_axis.z * v.x + m.y_axis.z * v.y + m.z_axis.z * v.z,
    )
}

/// `a * b` with a fixed evaluation order.
pub(crate) fn mul_mat3_mat3(a: &Mat3, b: &Mat3) -> Mat3 {
    Mat3::from_cols(mul_mat3(a, b.x_axis), mul_mat3(a, b.y_axis), mul_mat3(a, b.z_axis))
}

/// A world placement: `p_world = linear * p_local + translation`.
///
/// `linear` is rotation times (possibly non-uniform) scale. It must be invertible for lighting
/// to be right (normals use its inverse transpose).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Rotation and scale (columns are the local axes in world coordinates).
    pub linear: Mat3,
    /// Position of the local origin in world coordinates.
    pub translation: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// No rotation, no scale, at the origin.
    pub const IDENTITY: Transform = Transform { linear: Mat3::IDENTITY, translation: Vec3::ZERO };

    /// A pure translation.
    pub fn from_translation(t: Vec3) -> Self {
        Transform { linear: Mat3::IDENTITY, translation: t }
    }

    /// Position plus MuJoCo quaternion `(w, x, y, z)`, unit scale.
    pub fn from_pos_quat(pos: Vec3, quat_wxyz: [f32; 4]) -> Self {
        Transform { linear: quat_wxyz_to_mat3(quat_wxyz), translation: pos }
    }

    /// Position, MuJoCo quaternion `(w, x, y, z)` and per-axis scale (applied first, in the
    /// local frame).
    pub fn from_pos_quat_scale(pos: Vec3, quat_wxyz: [f32; 4], scale: Vec3) -> Self {
        let r = quat_wxyz_to_mat3(quat_wxyz);
        Transform {
            linear: Mat3::from_cols(r.x_axis * scale.x, r.y_axis * scale.y, r.z_axis * scale.z),
            translation: pos,
        }
    }

    /// Position plus a rotation matrix.
    pub fn from_pos_mat3(pos: Vec3, linear: Mat3) -> Self {
        Transform { linear, translation: pos }
    }

    /// The affine part of a column-major 4×4 matrix (the projective row is ignored).
    pub fn from_mat4(m: Mat4) -> Self {
        Transform {
            linear: Mat3::from_cols(m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate()),
            translation: m.w_axis.truncate(),
        }
    }

    /// As a column-major 4×4 matrix.
    pub fn to_mat4(&self) -> Mat4 {
        Mat4::from_cols(
            self.linear.x_axis.extend(0.0),
            self.linear.y_axis.extend(0.0),
            self.linear.z_axis.extend(0.0),
            self.translation.extend(1.0),
        )
    }

    /// `self ∘ inner`: applies `inner` first, then `self` (like `self_mat * inner_mat`).
    pub fn compose(&self, inner: &Transform) -> Transform {
        Transform {
            linear: mul_mat3_mat3(&self.linear, &inner.linear),
            translation: self.transform_point(inner.translation),
        }
    }

    /// Maps a local point to world coordinates.
    #[inline]
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        mul_mat3(&self.linear, p) + self.translation
    }

    /// Maps a local direction (no translation).
    #[inline]
    pub fn transform_vector(&self, v: Vec3) -> Vec3 {
        mul_mat3(&self.linear, v)
    }

    /// The matrix that maps local normals to world normals (inverse transpose of `linear`), up
    /// to a positive factor; callers normalise. Uses the cofactor matrix, which exists even for
    /// degenerate scales.
    pub fn normal_matrix(&self) -> Mat3 {
        let m = &self.linear;
        let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
        // cofactor(M) = [b×c, c×a, a×b] as columns equals det(M)·M^{-T}.
        let cof = Mat3::from_cols(cross(b, c), cross(c, a), cross(a, b));
        let det = a.x * cof.x_axis.x + a.y * cof.x_axis.y + a.z * cof.x_axis.z;
        if det < 0.0 { -cof } else { cof }
    }

    /// Largest factor by which this transform stretches any length (the largest column norm is
    /// used, which is exact for rotation times axis scale).
    pub fn max_scale(&self) -> f32 {
        let m = &self.linear;
        let l = |v: Vec3| (v.x * v.x + v.y * v.y + v.z * v.z).sqrt();
        l(m.x_axis).max(l(m.y_axis)).max(l(m.z_axis))
    }
}

#[inline]
pub(crate) fn cross(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)
}

#[inline]
pub(crate) fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// `v / |v|`, or zero for a zero vector (one division, three multiplications).
#[inline]
pub(crate) fn normalize(v: Vec3) -> Vec3 {
    let n = dot(v, v).sqrt();
    if n > 0.0 { v * (1.0 / n) } else { Vec3::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn quaternion_matches_axis_angle() {
        // 90° about z: x -> y.
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let r = quat_wxyz_to_mat3([h, 0.0, 0.0, h]);
        assert!(close(mul_mat3(&r, Vec3::X), Vec3::Y));
        assert!(close(mul_mat3(&r, Vec3::Y), -Vec3::X));
        // Unnormalised input gives the same rotation.
        let r2 = quat_wxyz_to_mat3([2.0 * h, 0.0, 0.0, 2.0 * h]);
        assert!(close(mul_mat3(&r2, Vec3::X), Vec3::Y));
    }

    #[test]
    fn xmat_is_row_major() {
        // Rotation of 90° about z in row-major form.
        let m = mat3_from_mj_xmat([0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        assert!(close(mul_mat3(&m, Vec3::X), Vec3::Y));
    }

    #[test]
    fn normal_matrix_keeps_normals_perpendicular_under_nonuniform_scale() {
        let t = Transform::from_pos_quat_scale(Vec3::ZERO, [0.9, 0.1, 0.3, -0.2], Vec3::new(3.0, 0.5, 1.0));
        let tangent = Vec3::new(1.0, 1.0, 0.0);
        let normal = Vec3::new(1.0, -1.0, 0.0);
        let tw = t.transform_vector(tangent);
        let nw = mul_mat3(&t.normal_matrix(), normal);
        assert!(dot(tw, nw).abs() < 1e-5);
        // Orientation is kept (not flipped) for positive determinants.
        assert!(dot(nw, t.transform_vector(normal)) > 0.0);
    }

    #[test]
    fn composition_applies_right_then_left() {
        let a = Transform::from_translation(Vec3::new(1.0, 0.0, 0.0));
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let b = Transform::from_pos_quat(Vec3::ZERO, [h, 0.0, 0.0, h]);
        let ab = a.compose(&b);
        assert!(close(ab.transform_point(Vec3::X), Vec3::new(1.0, 1.0, 0.0)));
        let m = Transform::from_mat4(ab.to_mat4());
        assert_eq!(m, ab);
    }
}
