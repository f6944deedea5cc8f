//! Conversions between our nalgebra poses and rapier's glam types.

use vifo_physics::rapier::glamx::DMat3;
use vifo_physics::rapier::math::{Pose as RPose, Rotation, Vector};

use crate::spatial::{Mat3, Pose, Vec3};

pub fn vector(v: &Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

pub fn vec3(v: Vector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

pub fn rotation(m: &Mat3) -> Rotation {
    Rotation::from_mat3(&dmat3(m)).normalize()
}

/// Column-major glam copy of a matrix.
pub fn dmat3(m: &Mat3) -> DMat3 {
    DMat3::from_cols(
        Vector::new(m[(0, 0)], m[(1, 0)], m[(2, 0)]),
        Vector::new(m[(0, 1)], m[(1, 1)], m[(2, 1)]),
        Vector::new(m[(0, 2)], m[(1, 2)], m[(2, 2)]),
    )
}

pub fn rapier_pose(p: &Pose) -> RPose {
    RPose::from_parts(vector(&p.pos), rotation(&p.rot))
}

pub fn pose(p: &RPose) -> Pose {
    let m = DMat3::from_quat(p.rotation);
    let rot = Mat3::new(
        m.x_axis.x, m.y_axis.x, m.z_axis.x, //
        m.x_axis.y, m.y_axis.y, m.z_axis.y, //
        m.x_axis.z, m.y_axis.z, m.z_axis.z,
    );
    Pose::new(vec3(p.translation), rot)
}
