//! Conversions between our nalgebra poses and rapier's glam poses.

use vifo_physics::rapier::math::{Pose as RPose, Rotation, Vector};
use vifo_physics::rapier::glamx::DMat3;

use crate::spatial::{Mat3, Pose, Vec3};

pub fn vector(v: &Vec3) -> Vector {
    Vector::new(v.x, v.y, v.z)
}


pub fn rotation(m: &Mat3) -> Rotation {
    let cols = DMat3::from_cols(
        Vector::new(m[(0, 0)], m[(1, 0)], m[(2, 0)]),
        Vector::new(m[(0, 1)], m[(1, 1)], m[(2, 1)]),
        Vector::new(m[(0, 2)], m[(1, 2)], m[(2, 2)]),
    );
    Rotation::from_mat3(&cols).normalize()
}

pub fn rapier_pose(p: &Pose) -> RPose {
    RPose::from_parts(vector(&p.pos), rotation(&p.rot))
}
