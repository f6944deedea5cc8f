//! Joint limits as MuJoCo enforces them: a soft one-sided constraint, not a hard stop.
//!
//! A joint past `range` (less `margin`) gets a constraint whose reference acceleration is a
//! spring-damper on the violation, `aref = -b·v - k·d(r)·r` (`solref` gives k and b, `solimp` the
//! impedance d), and whose regularizer `R = (1 - d)/d · invweight0` (the dof's inverse mass at
//! `qpos0`) lets it give: pushed with 80 N·m, the Panda's joints sink milliradians past their
//! range, and come back like a critically damped 8 Hz spring. rapier's limits act like a hard
//! stop instead, which put the end-effector up to 18 cm away from MuJoCo's once a joint was held
//! at its limit. The force is solved as MuJoCo's Newton solver does for the limit rows alone,
//! from the state at the start of the physics step, and applied as a generalized force.

use nalgebra::SMatrix;

use crate::dynamics::{ArmDynamics, Coords};
use crate::spatial::Pose;

/// MuJoCo's bounds on the impedance and smallest regularizer (`mjMINIMP`, `mjMAXIMP`, `mjMINVAL`).
const MIN_IMP: f64 = 0.0001;
const MAX_IMP: f64 = 0.9999;
const MIN_VAL: f64 = 1e-15;

/// A joint limit's `solref`, `solimp` and `margin` (MJCF `solreflimit`, `solimplimit`, `margin`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftLimit {
    /// `(timeconst, dampratio)`.
    pub solref: [f64; 2],
    /// `(d0, dwidth, width, midpoint, power)`.
    pub solimp: [f64; 5],
    /// The limit engages this far inside the range.
    pub margin: f64,
}

impl SoftLimit {
    /// MuJoCo's defaults, which robosuite's Panda and gripper keep.
    pub const MUJOCO_DEFAULT: SoftLimit = SoftLimit { solref: [0.02, 1.0], solimp: [0.9, 0.95, 0.001, 0.5, 2.0], margin: 0.0 };

    /// The impedance at violation `x` (≥ 0) past the margin (MuJoCo's `getimpedance`).
    pub fn impedance(&self, x: f64) -> f64 {
        let [d0, dwidth, width, mid, power] = self.solimp;
        let (d0, dwidth) = (d0.clamp(MIN_IMP, MAX_IMP), dwidth.clamp(MIN_IMP, MAX_IMP));
        let (mid, power) = (mid.clamp(MIN_IMP, MAX_IMP), power.max(1.0));
        let x = x.abs() / width;
        if width <= MIN_VAL || x >= 1.0 {
            return dwidth;
        }
        let y = if power == 1.0 {
            x
        } else if x <= mid {
            libm::pow(x, power) / libm::pow(mid, power - 1.0)
        } else {
            1.0 - libm::pow(1.0 - x, power) / libm::pow(1.0 - mid, power - 1.0)
        };
        (d0 + y * (dwidth - d0)).clamp(MIN_IMP, MAX_IMP)
    }

    /// Stiffness and damping of the reference acceleration (`refsafe`: the time constant is at
    /// least two physics steps `dt`).
    pub fn stiffness_damping(&self, dt: f64) -> (f64, f64) {
        let dmax = self.solimp[1].clamp(MIN_IMP, MAX_IMP);
        let [timeconst, dampratio] = self.solref;
        if timeconst <= 0.0 {
            return (-timeconst / (dmax * dmax), -dampratio / dmax);
        }
        let tc = timeconst.max(2.0 * dt);
        (1.0 / (dmax * dmax * tc * tc * dampratio * dampratio), 2.0 / (dmax * tc))
    }
}

/// The soft limits of an arm's joints, with MuJoCo's per-dof `invweight0`.
#[derive(Clone, Debug)]
pub struct JointLimits<const N: usize> {
    /// Range and softness of each dof whose limit is soft.
    soft: [Option<([f64; 2], SoftLimit)>; N],
    /// Diagonal of the inverse mass matrix at `q = 0` (MuJoCo's `dof_invweight0`).
    invweight0: Coords<N>,
}

impl<const N: usize> JointLimits<N> {
    /// The soft limits of `dynamics`' model (joints with `soft_limit`).
    pub fn new(dynamics: &ArmDynamics<N>) -> Self {
        let model = dynamics.model();
        let soft = std::array::from_fn(|i| model.joint(i).soft_limit.map(|s| (model.joint(i).range, s)));
        let mass = dynamics.mass_matrix(&dynamics.forward(&Pose::IDENTITY, &Coords::<N>::zeros()));
        let inverse = mass.cholesky().expect("an arm's mass matrix is positive definite").inverse();
        JointLimits { soft, invweight0: inverse.diagonal() }
    }

    pub fn invweight0(&self) -> &Coords<N> {
        &self.invweight0
    }

    /// Direction of the constraint on each dof (+1 past the lower end, -1 past the upper one) and
    /// its distance to the engaging point (negative inside the constraint).
    fn engaged(&self, q: &Coords<N>) -> [Option<(f64, f64, SoftLimit)>; N] {
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

    /// Whether any joint is in its limit constraint at `q` (nothing else need be computed if not).
    pub fn any_engaged(&self, q: &Coords<N>) -> bool {
        self.engaged(q).iter().any(Option::is_some)
    }

    /// The generalized limit forces for the next physics step of length `dt`, from the joint
    /// state, the mass matrix and the smooth forces (actuators + passive - bias) at its start.
    pub fn forces(&self, q: &Coords<N>, qd: &Coords<N>, mass: &SMatrix<f64, N, N>, smooth: &Coords<N>, dt: f64) -> Coords<N> {
        let engaged = self.engaged(q);
        if engaged.iter().all(Option::is_none) {
            return Coords::<N>::zeros();
        }
        let inverse = mass.cholesky().expect("an arm's mass matrix is positive definite").inverse();
        let a0 = inverse * smooth;
        // Per engaged dof: direction s, regularizer R and reference acceleration aref.
        let mut rows: [Option<(f64, f64, f64)>; N] = [None; N];
        for (i, e) in engaged.iter().enumerate() {
            if let Some((s, r, limit)) = *e {
                let imp = limit.impedance(r);
                let (k, b) = limit.stiffness_damping(dt);
                let reg = ((1.0 - imp) * self.invweight0[i] / imp).max(MIN_VAL);
                rows[i] = Some((s, reg, -b * s * qd[i] - k * imp * r));
            }
        }
        // The rows' forces f ≥ 0 minimize MuJoCo's cost: solve the active ones, drop those that
        // would pull, take back those whose constraint acceleration falls below aref.
        let mut active: [bool; N] = std::array::from_fn(|i| rows[i].is_some());
        let mut f = Coords::<N>::zeros();
        for _ in 0..=N {
            let mut lhs = SMatrix::<f64, N, N>::identity();
            let mut rhs = Coords::<N>::zeros();
            for i in (0..N).filter(|&i| active[i]) {
                let (si, reg, aref) = rows[i].expect("active rows are engaged");
                for j in (0..N).filter(|&j| active[j]) {
                    let sj = rows[j].expect("active rows are engaged").0;
                    lhs[(i, j)] = si * sj * inverse[(i, j)];
                }
                lhs[(i, i)] += reg;
                rhs[i] = aref - si * a0[i];
            }
            f = lhs.cholesky().expect("the limit system is positive definite").solve(&rhs);
            let tau = Coords::<N>::from_fn(|i, _| rows[i].map_or(0.0, |(s, ..)| s * f[i]));
            let a = a0 + inverse * tau;
            let mut changed = false;
            for i in 0..N {
                let Some((s, _, aref)) = rows[i] else { continue };
                let want = if active[i] { f[i] >= 0.0 } else { s * a[i] >= aref };
                if !want {
                    active[i] = !active[i];
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        Coords::<N>::from_fn(|i, _| match rows[i] {
            Some((s, ..)) if active[i] => s * f[i],
            _ => 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panda::{self, Mount};

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
    fn impedance_ramps_from_d0_to_dwidth_over_width() {
        let s = SoftLimit::MUJOCO_DEFAULT;
        assert!((s.impedance(0.0) - 0.9).abs() < 1e-15);
        assert!((s.impedance(0.0005) - 0.925).abs() < 1e-12);
        assert!((s.impedance(0.00025) - (0.9 + 0.05 * 0.125)).abs() < 1e-12);
        assert_eq!(s.impedance(0.01), 0.95);
        let (k, b) = s.stiffness_damping(0.002);
        assert!((k - 1.0 / (0.95 * 0.95 * 0.0004)).abs() < 1e-9 && (b - 2.0 / (0.95 * 0.02)).abs() < 1e-12);
    }

    #[test]
    fn no_force_inside_the_range_and_a_push_back_past_it() {
        let dynamics = ArmDynamics::<9>::new(panda::model(Mount::Pedestal), [0.0, 0.0, -9.81]);
        let limits = JointLimits::new(&dynamics);
        let mut q = Coords::<9>::from_column_slice(&[0.0, 0.0, 0.0, -1.5, 0.0, 1.5, 0.0, 0.02, -0.02]);
        let mass = dynamics.mass_matrix(&dynamics.forward(&Pose::IDENTITY, &q));
        let smooth = Coords::<9>::zeros();
        assert!(!limits.any_engaged(&q));
        assert_eq!(limits.forces(&q, &Coords::zeros(), &mass, &smooth, 0.002), Coords::<9>::zeros());
        q[6] = 2.8973 + 0.003;
        let mut push = smooth;
        push[6] = 10.0;
        let f = limits.forces(&q, &Coords::zeros(), &mass, &push, 0.002);
        assert!(f[6] < 0.0, "{f:?}");
        assert!(f.iter().enumerate().all(|(i, &x)| i == 6 || x == 0.0), "{f:?}");
        // Moving out fast, the damper would pull; a soft limit never does.
        let mut qd = Coords::<9>::zeros();
        qd[6] = -5.0;
        let f = limits.forces(&q, &qd, &mass, &smooth, 0.002);
        assert_eq!(f[6], 0.0, "{f:?}");
    }
}
