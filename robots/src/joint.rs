//! One-degree-of-freedom multibody joints (hinges and slides) in MuJoCo's convention: the joint
//! sits at the child body's origin, its axis given in the child frame.

use vifo_physics::rapier::prelude::{GenericJoint, GenericJointBuilder, JointAxesMask, JointAxis};

use crate::convert::rapier_pose;
use crate::model::JointKind;
use crate::spatial::{Mat3, Pose, Vec3};

/// A rotation taking +x onto `axis` (rapier's revolute and prismatic joints move about/along x).
fn x_to(axis: &Vec3) -> Mat3 {
    nalgebra::UnitQuaternion::rotation_between(&Vec3::x(), axis)
        .unwrap_or_else(|| nalgebra::UnitQuaternion::from_axis_angle(&Vec3::z_axis(), std::f64::consts::PI))
        .to_rotation_matrix()
        .into_inner()
}

/// The rapier joint placing a child body at `child_in_parent` (its zero-position pose in the
/// parent's frame) and letting it turn about / slide along `axis` through `anchor` (both in the
/// child frame) within `range` (`None`: unlimited here, the limit is applied as a force).
/// Contacts between the two bodies are disabled, as MuJoCo excludes parent–child pairs.
pub fn one_dof(kind: JointKind, child_in_parent: &Pose, anchor: &Vec3, axis: &Vec3, range: Option<[f64; 2]>) -> GenericJoint {
    let align = Pose::new(*anchor, x_to(axis));
    let (locked, coordinate) = match kind {
        JointKind::Hinge => (JointAxesMask::LOCKED_REVOLUTE_AXES, JointAxis::AngX),
        JointKind::Slide => (JointAxesMask::LOCKED_PRISMATIC_AXES, JointAxis::LinX),
    };
    let mut builder = GenericJointBuilder::new(locked)
        .local_frame1(rapier_pose(&child_in_parent.mul(&align)))
        .local_frame2(rapier_pose(&align))
        .contacts_enabled(false);
    if let Some(range) = range {
        builder = builder.limits(coordinate, range);
    }
    builder.build()
}

/// The joint coordinate rapier stores for a one-dof joint of this kind.
pub fn coordinate(kind: JointKind, coords: &[f64; 6]) -> f64 {
    match kind {
        JointKind::Hinge => coords[3],
        JointKind::Slide => coords[0],
    }
}
