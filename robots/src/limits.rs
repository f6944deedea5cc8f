//! Joint limits and dry friction as MuJoCo enforces them: soft constraints, not a hard stop or a
//! hard stick.
//!
//! A joint past `range` (less `margin`) gets a row of MuJoCo's soft constraint ([`crate::soft`])
//! whose regularizer is scaled by the dof's inverse mass at `qpos0` (`dof_invweight0`): pushed
//! with 80 N·m, the Panda's joints sink milliradians past their range, and come back like a
//! critically damped 8 Hz spring. rapier's limits act like a hard stop instead, which put the
//! end-effector up to 18 cm away from MuJoCo's once a joint was held at its limit.

use crate::dynamics::ArmDynamics;
use crate::soft::{DryFriction, Row, Softness};
use crate::spatial::{Coords, Pose};

/// The soft limits of an arm's joints, with MuJoCo's per-dof `invweight0`.
#[derive(Clone, Debug)]
pub struct JointLimits<const N: usize> {
    /// Range and softness of each dof whose limit is soft.
    soft: [Option<([f64; 2], Softness)>; N],
    /// Dry friction (`frictionloss`) of each such dof.
    frictionloss: Coords<N>,
    /// Diagonal of the inverse mass matrix at `q = 0` (MuJoCo's `dof_invweight0`).
    invweight0: Coords<N>,
}

impl<const N: usize> JointLimits<N> {
    /// The soft limits and dry friction of `dynamics`' model (joints with `soft`).
    pub fn new(dynamics: &ArmDynamics<N>) -> Self {
        let model = dynamics.model();
        let soft = std::array::from_fn(|i| model.joint(i).soft.map(|s| (model.joint(i).range, s)));
        let frictionloss = Coords::<N>::from_fn(|i, _| if soft[i].is_some() { model.joint(i).frictionloss } else { 0.0 });
        let mass = dynamics.mass_matrix(&dynamics.forward(&Pose::IDENTITY, &Coords::<N>::zeros()));
        let inverse = mass.cholesky().expect("an arm's mass matrix is positive definite").inverse();
        JointLimits { soft, frictionloss, invweight0: inverse.diagonal() }
    }

    pub fn invweight0(&self) -> &Coords<N> {
        &self.invweight0
    }

    /// Direction of the constraint on each dof (+1 past the lower end, -1 past the upper one) and
    /// its distance to the engaging point (negative inside the constraint).
    fn engaged(&self, q: &Coords<N>) -> [Option<(f64, f64, Softness)>; N] {
        std::array::from_fn(|i| {
            let ([lo, hi], s) = self.soft[i]?;
            let (below, above) = (q[i] - lo, hi - q[i]);
            if below < s.margin {
                Some((1.0, below - s.margin, s))
            } else if above < s.margin {
                Some((-1.0, above - s.margin, s))
            } else {
                None
            }
        })
    }

    /// Adds a row for each joint in its limit constraint at `q`, for a physics step `dt`.
    pub fn rows(&self, q: &Coords<N>, qd: &Coords<N>, dt: f64, rows: &mut Vec<Row<N>>) {
        for (i, e) in self.engaged(q).iter().enumerate() {
            if let Some((s, r, limit)) = *e {
                let mut jacobian = Coords::<N>::zeros();
                jacobian[i] = s;
                rows.push(limit.row(jacobian, r, s * qd[i], self.invweight0[i], dt));
            }
        }
    }

    /// Adds a dry-friction row for each soft dof with `frictionloss`, moving at `qd`.
    pub fn friction(&self, qd: &Coords<N>, dt: f64, friction: &mut Vec<DryFriction<N>>) {
        for (i, soft) in self.soft.iter().enumerate() {
            let Some((_, s)) = soft else { continue };
            if self.frictionloss[i] > 0.0 {
                let mut jacobian = Coords::<N>::zeros();
                jacobian[i] = 1.0;
                friction.push(s.dry_friction(jacobian, qd[i], self.frictionloss[i], self.invweight0[i], dt));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panda::{self, Mount};
    use crate::soft::Constraints;

    /// MuJoCo 2.3.7's `dof_invweight0` of robosuite's Panda in a LIBERO scene.
    #[test]
    fn invweight0_matches_mujoco() {
        let dynamics = ArmDynamics::<9>::new(panda::model(Mount::Pedestal), [0.0, 0.0, -9.81]);
        let limits = JointLimits::new(&dynamics);
        let golden = [0.163754, 0.203778, 0.432717, 0.515898, 0.730018, 0.853256, 1.137181, 0.901362, 0.901362];
        for (i, g) in golden.into_iter().enumerate() {
            assert!((limits.invweight0()[i] - g).abs() < 1e-5, "invweight0[{i}] = {}", limits.invweight0()[i]);
        }
    }

    #[test]
    fn no_force_inside_the_range_and_a_push_back_past_it() {
        let dynamics = ArmDynamics::<9>::new(panda::model(Mount::Pedestal), [0.0, 0.0, -9.81]);
        let limits = JointLimits::new(&dynamics);
        let mut q = Coords::<9>::from_column_slice(&[0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0, 0.02, -0.02]);
        let mass = dynamics.mass_matrix(&dynamics.forward(&Pose::IDENTITY, &q));
        let smooth = Coords::<9>::zeros();
        let forces = |q: &Coords<9>, qd: &Coords<9>, smooth: &Coords<9>| {
            let mut constraints = Constraints::default();
            limits.rows(q, qd, 0.002, &mut constraints.rows);
            (constraints.rows.len(), constraints.forces(&mass, smooth))
        };
        assert_eq!(forces(&q, &Coords::zeros(), &smooth), (0, Coords::<9>::zeros()));
        q[6] = 2.8973 + 0.003;
        let mut push = smooth;
        push[6] = 10.0;
        let (n, f) = forces(&q, &Coords::zeros(), &push);
        assert_eq!(n, 1);
        assert!(f[6] < 0.0, "{f:?}");
        assert!(f.iter().enumerate().all(|(i, &x)| i == 6 || x == 0.0), "{f:?}");
        // Moving out fast, the damper would pull; a soft limit never does.
        let mut qd = Coords::<9>::zeros();
        qd[6] = -5.0;
        let (_, f) = forces(&q, &qd, &smooth);
        assert_eq!(f[6], 0.0, "{f:?}");
    }
}
