//! robosuite 1.4's `OSC_POSE` operational-space controller, reproduced term by term.
//!
//! The goal is set once per control step from a delta action (0.05 m / 0.5 rad per unit, world
//! frame, relative to the current end-effector pose). Torques are recomputed every physics
//! substep from fresh state: decoupled position and orientation impedance through the
//! operational-space inertias, full bias-force compensation, and a nullspace pull toward the
//! reset configuration, clipped to the motor limits.

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, DimDiff, DimSub, SMatrix, SVector, U1};
use serde::{Deserialize, Serialize};

use crate::spatial::{Mat3, Vec3, rotation_from_axis_angle_vector};

/// Controller gains and limits (robosuite's `osc_pose.json` defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OscParams {
    pub kp: f64,
    pub damping_ratio: f64,
    /// Metres per unit of translation action.
    pub max_translation: f64,
    /// Radians per unit of rotation action.
    pub max_rotation: f64,
    /// Nullspace joint stiffness (critically damped).
    pub nullspace_kp: f64,
}

impl OscParams {
    pub const ROBOSUITE: OscParams =
        OscParams { kp: 150.0, damping_ratio: 1.0, max_translation: 0.05, max_rotation: 0.5, nullspace_kp: 10.0 };

    pub fn kd(&self) -> f64 {
        2.0 * self.kp.sqrt() * self.damping_ratio
    }
}

/// The pose the controller drives the end effector to (world frame).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OscGoal {
    pub pos: [f64; 3],
    /// Rotation matrix, row-major.
    pub ori: [[f64; 3]; 3],
}

impl OscGoal {
    pub fn new(pos: Vec3, ori: Mat3) -> Self {
        OscGoal { pos: pos.into(), ori: [0, 1, 2].map(|r| [ori[(r, 0)], ori[(r, 1)], ori[(r, 2)]]) }
    }

    pub fn pos(&self) -> Vec3 {
        Vec3::from(self.pos)
    }

    pub fn ori(&self) -> Mat3 {
        Mat3::from_fn(|r, c| self.ori[r][c])
    }

    /// `set_goal` for a clipped delta action: the position goal is always the current position
    /// plus the scaled delta; the orientation goal is only replaced when some rotation component
    /// is non-zero (robosuite keeps the previous goal otherwise).
    pub fn updated(&self, params: &OscParams, ee_pos: &Vec3, ee_ori: &Mat3, translation: [f64; 3], rotation: [f64; 3]) -> Self {
        let pos = ee_pos + Vec3::from(translation) * params.max_translation;
        let ori = if rotation.iter().any(|&r| r != 0.0) {
            rotation_from_axis_angle_vector(&(Vec3::from(rotation) * params.max_rotation)) * ee_ori
        } else {
            self.ori()
        };
        OscGoal::new(pos, ori)
    }
}

/// What the controller reads from the simulation at each substep (`A` arm joints).
pub struct OscInput<'a, const A: usize> {
    pub q: &'a SVector<f64, A>,
    pub qd: &'a SVector<f64, A>,
    /// Joint-space mass matrix of the arm joints, armature included.
    pub mass: &'a SMatrix<f64, A, A>,
    /// `qfrc_bias` of the arm joints.
    pub bias: &'a SVector<f64, A>,
    /// End-effector site Jacobian (world frame; rows 0–2 linear, 3–5 angular).
    pub jacobian: &'a SMatrix<f64, 6, A>,
    pub ee_pos: &'a Vec3,
    pub ee_ori: &'a Mat3,
    /// The nullspace target (`initial_joint`).
    pub q0: &'a SVector<f64, A>,
}

/// robosuite's `orientation_error`: half the sum of the cross products of matching columns.
pub fn orientation_error(desired: &Mat3, current: &Mat3) -> Vec3 {
    (0..3).map(|c| current.column(c).cross(&desired.column(c))).fold(Vec3::zeros(), |a, b| a + b) * 0.5
}

/// numpy's `pinv` (singular values below 1e-15·σ_max dropped) of a symmetric positive
/// semi-definite matrix, the only kind the controller inverts (`J M⁻¹ Jᵀ`). Away from
/// singularities that is the plain inverse, taken by Cholesky; where the Cholesky pivots span
/// more than [`PIVOT_SPREAD`] (near a singular arm pose) it takes numpy's route: the singular
/// values of such a matrix are its eigenvalues, and the small ones are dropped.
fn pinv_psd<const D: usize>(m: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D>
where
    Const<D>: DimSub<U1>,
    DefaultAllocator: Allocator<DimDiff<Const<D>, U1>>,
{
    if let Some(c) = m.cholesky() {
        let pivots = c.l_dirty().diagonal().map(|l| l * l);
        if pivots.min() > pivots.max() / PIVOT_SPREAD {
            return c.inverse();
        }
    }
    let eigen = m.symmetric_eigen();
    let cutoff = 1e-15 * eigen.eigenvalues.amax();
    let inverted = eigen.eigenvalues.map(|l| if l.abs() > cutoff { 1.0 / l } else { 0.0 });
    let v = &eigen.eigenvectors;
    v * SMatrix::<f64, D, D>::from_diagonal(&inverted) * v.transpose()
}

/// Largest ratio of Cholesky pivots for which [`pinv_psd`] trusts the plain inverse: the
/// condition number is then far below numpy's 1e15 cutoff, so no singular value is dropped.
const PIVOT_SPREAD: f64 = 1e10;

/// The OSC torques (before clipping to the motor limits).
pub fn torques<const A: usize>(params: &OscParams, goal: &OscGoal, s: &OscInput<'_, A>) -> SVector<f64, A> {
    let (kp, kd) = (params.kp, params.kd());
    let j_pos: SMatrix<f64, 3, A> = s.jacobian.fixed_rows::<3>(0).into_owned();
    let j_ori: SMatrix<f64, 3, A> = s.jacobian.fixed_rows::<3>(3).into_owned();
    let vel = j_pos * s.qd;
    let ang_vel = j_ori * s.qd;

    let force = (goal.pos() - s.ee_pos) * kp - vel * kd;
    let torque = orientation_error(&goal.ori(), s.ee_ori) * kp - ang_vel * kd;

    // M⁻¹ Jᵀ by a Cholesky solve (M is symmetric positive definite); its column blocks give
    // the position and orientation halves.
    let m_inv_jt = s.mass.cholesky().expect("the mass matrix is positive definite").solve(&s.jacobian.transpose());
    let lambda_full = pinv_psd(&(s.jacobian * m_inv_jt));
    let lambda_pos = pinv_psd(&(j_pos * m_inv_jt.fixed_columns::<3>(0)));
    let lambda_ori = pinv_psd(&(j_ori * m_inv_jt.fixed_columns::<3>(3)));

    let mut wrench = SVector::<f64, 6>::zeros();
    wrench.fixed_rows_mut::<3>(0).copy_from(&(lambda_pos * force));
    wrench.fixed_rows_mut::<3>(3).copy_from(&(lambda_ori * torque));
    let mut tau = s.jacobian.transpose() * wrench + s.bias;

    // Nullspace: N = I − J̄ J with J̄ = M⁻¹ Jᵀ Λ, torque Nᵀ M (kp (q0 − q) − kv q̇).
    let j_bar = m_inv_jt * lambda_full;
    let nullspace = SMatrix::<f64, A, A>::identity() - j_bar * s.jacobian;
    let kv = 2.0 * params.nullspace_kp.sqrt();
    let pose_torque = s.mass * ((s.q0 - s.q) * params.nullspace_kp - s.qd * kv);
    tau += nullspace.transpose() * pose_torque;
    tau
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::axis_angle;

    #[test]
    fn orientation_error_is_the_small_rotation_vector() {
        let current = axis_angle(&Vec3::new(0.3, -0.2, 0.9).normalize(), 0.4);
        let delta = Vec3::new(0.001, -0.002, 0.0015);
        let desired = rotation_from_axis_angle_vector(&delta) * current;
        let err = orientation_error(&desired, &current);
        assert!((err - delta).norm() < 1e-8, "{err:?}");
    }

    #[test]
    fn pinv_of_a_psd_matrix_is_numpys_svd_pinv_and_drops_a_null_direction() {
        let a = SMatrix::<f64, 6, 4>::from_fn(|r, c| ((r * 7 + c * 3) % 5) as f64 - 1.7 + 0.1 * r as f64);
        // Rank 4 of 6: two zero singular values, which numpy's pinv drops.
        let m = a * a.transpose();
        let svd = m.svd(true, true);
        let numpy = svd.pseudo_inverse(1e-15 * svd.singular_values.max()).unwrap();
        let ours = pinv_psd(&m);
        assert!((ours - numpy).amax() < 1e-9 * numpy.amax(), "{ours} vs {numpy}");
        // Full rank: the Cholesky inverse, equal to numpy's pinv within rounding.
        let full = m + SMatrix::<f64, 6, 6>::identity();
        let svd = full.svd(true, true);
        let numpy = svd.pseudo_inverse(1e-15 * svd.singular_values.max()).unwrap();
        assert!((pinv_psd(&full) - numpy).amax() < 1e-12 * numpy.amax());
    }

    #[test]
    fn goal_keeps_orientation_without_rotation_input() {
        let p = OscParams::ROBOSUITE;
        let start = OscGoal::new(Vec3::new(0.1, 0.2, 0.3), axis_angle(&Vec3::z(), 0.2));
        let ee_ori = axis_angle(&Vec3::x(), 0.5);
        let next = start.updated(&p, &Vec3::new(1.0, 1.0, 1.0), &ee_ori, [1.0, 0.0, -0.5], [0.0; 3]);
        assert_eq!(next.ori, start.ori);
        assert!((next.pos() - Vec3::new(1.05, 1.0, 0.975)).norm() < 1e-15);
        let turned = start.updated(&p, &Vec3::zeros(), &ee_ori, [0.0; 3], [0.0, 0.0, 1.0]);
        assert!((turned.ori() - axis_angle(&Vec3::z(), 0.5) * ee_ori).norm() < 1e-12);
    }
}
