//! MuJoCo's soft constraints, for the constraints our own code adds to rapier's step: the joint
//! limits and dry friction ([`crate::limits`]) and the arm touching itself
//! ([`crate::soft_contact`]).
//!
//! Each constraint is a row: a generalized direction `J`, a reference acceleration that is a
//! spring-damper on the violation, `aref = -b·v - k·d(r)·r` (`solref` gives k and b, `solimp` the
//! impedance d), and a regularizer `R = (1 - d)/d · diagApprox` that lets it give. The forces are
//! solved as MuJoCo's Newton solver does for these rows alone, from the state at the start of the
//! physics step, and applied as a generalized force `Jᵀf`.

use nalgebra::SMatrix;

use crate::spatial::Coords;

/// MuJoCo's bounds on the impedance and smallest regularizer (`mjMINIMP`, `mjMAXIMP`, `mjMINVAL`).
const MIN_IMP: f64 = 0.0001;
const MAX_IMP: f64 = 0.9999;
const MIN_VAL: f64 = 1e-15;

/// A constraint's `solref`, `solimp` and `margin` (MJCF `solreflimit`/`solimplimit` of a joint,
/// `solref`/`solimp` of a contact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Softness {
    /// `(timeconst, dampratio)`.
    pub solref: [f64; 2],
    /// `(d0, dwidth, width, midpoint, power)`.
    pub solimp: [f64; 5],
    /// The constraint engages this far before the violation starts.
    pub margin: f64,
}

impl Softness {
    /// MuJoCo's defaults, which robosuite's Panda and gripper keep (but for the finger pads).
    pub const MUJOCO_DEFAULT: Softness = Softness { solref: [0.02, 1.0], solimp: [0.9, 0.95, 0.001, 0.5, 2.0], margin: 0.0 };

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

    /// MuJoCo's mix of two geoms' parameters for their contact (equal `solmix`: the mean).
    pub fn mixed(&self, other: &Softness) -> Softness {
        let mean = |a: f64, b: f64| 0.5 * a + 0.5 * b;
        Softness {
            solref: std::array::from_fn(|i| mean(self.solref[i], other.solref[i])),
            solimp: std::array::from_fn(|i| mean(self.solimp[i], other.solimp[i])),
            margin: self.margin.max(other.margin),
        }
    }

    /// The row of a constraint along `jacobian`, `r` from engaging (negative inside), moving at
    /// `v = J·q̇`, for a physics step `dt`; `weight` is MuJoCo's `diagApprox` of the row.
    pub fn row<const N: usize>(&self, jacobian: Coords<N>, r: f64, v: f64, weight: f64, dt: f64) -> Row<N> {
        let imp = self.impedance(r);
        let (k, b) = self.stiffness_damping(dt);
        Row { jacobian, regularizer: ((1.0 - imp) * weight / imp).max(MIN_VAL), aref: -b * v - k * imp * r }
    }
}

/// One constraint row (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row<const N: usize> {
    pub jacobian: Coords<N>,
    pub regularizer: f64,
    pub aref: f64,
}

impl<const N: usize> Row<N> {
    /// `J·a - aref`: how far acceleration `a` falls short of the reference (negative: too little).
    fn shortfall(&self, a: &Coords<N>) -> f64 {
        self.jacobian.dot(a) - self.aref
    }

    /// The one coordinate the Jacobian has, where it has just one (a joint's own row).
    fn axis(&self) -> Option<usize> {
        let mut nonzero = self.jacobian.iter().enumerate().filter(|(_, j)| **j != 0.0);
        let (k, _) = nonzero.next()?;
        nonzero.next().is_none().then_some(k)
    }
}

/// A contact with MuJoCo's elliptic friction cone: a normal row, two tangent rows and, for
/// `condim` 4, a torsional row (spin about the normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone<const N: usize> {
    /// The normal row, then the friction rows; only the first [`Cone::dim`] are used.
    pub rows: [Row<N>; 4],
    /// MuJoCo's `condim`: 3, or 4 with the torsional row.
    pub dim: usize,
    /// Friction coefficients of the friction rows (tangent, tangent, torsional).
    pub friction: [f64; 3],
    /// Friction coefficient of the regularized cone: `friction[0] · sqrt(R_t / R_n)`.
    pub mu: f64,
}

/// A contact's friction as MuJoCo mixes two geoms' (the larger of each): the tangent
/// coefficient, and the torsional one where the contact has `condim` 4.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    pub slide: f64,
    pub spin: Option<f64>,
}

impl Softness {
    /// A contact at distance `dist` (negative: overlapping) along `normal` with tangent rows
    /// `tangents` and the torsional row `spin` (Jacobians of the relative velocity, second body
    /// minus first; the angular one about the normal), `weight` the sum of the two bodies'
    /// translational `invweight0`. As MuJoCo makes it: the friction rows damp but do not spring
    /// (`K = 0`), the tangent ones are `impratio` times stiffer than the normal, and each row's
    /// regularizer times its coefficient squared is the tangent rows' (`mj_makeImpedance`).
    #[allow(clippy::too_many_arguments)]
    pub fn cone<const N: usize>(&self, normal: Coords<N>, tangents: [Coords<N>; 2], spin: Coords<N>, dist: f64, qd: &Coords<N>, weight: f64, friction: Friction, impratio: f64, dt: f64) -> Cone<N> {
        let n = self.row(normal, dist - self.margin, normal.dot(qd), weight, dt);
        let (_, b) = self.stiffness_damping(dt);
        let regularizer = n.regularizer / impratio.max(MIN_VAL);
        let row = |j: Coords<N>, regularizer: f64| Row { jacobian: j, regularizer, aref: -b * j.dot(qd) };
        let slide = friction.slide;
        let torsional = friction.spin.unwrap_or(0.0);
        let spin_regularizer = if torsional > 0.0 { regularizer * slide * slide / (torsional * torsional) } else { regularizer };
        Cone {
            rows: [n, row(tangents[0], regularizer), row(tangents[1], regularizer), row(spin, spin_regularizer)],
            dim: if friction.spin.is_some() { 4 } else { 3 },
            friction: [slide, slide, torsional],
            mu: slide * libm::sqrt(regularizer / n.regularizer),
        }
    }
}

/// A dof's dry friction (`frictionloss`): a two-sided row whose force is at most `limit` either
/// way. Being soft, it lets a joint under a smaller force creep (`v ≈ f·R/b`) instead of
/// sticking: robosuite's open fingers, pushed by their actuators, creep towards their range end
/// at about 0.2 mm/s in MuJoCo, where a hard friction held them a millimetre short.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DryFriction<const N: usize> {
    pub row: Row<N>,
    pub limit: f64,
}

impl Softness {
    /// The dry-friction row of the dof along `jacobian`, moving at `v = J·q̇`, as MuJoCo makes
    /// it: no spring (the violation is 0), `weight` its `dof_invweight0`.
    pub fn dry_friction<const N: usize>(&self, jacobian: Coords<N>, v: f64, limit: f64, weight: f64, dt: f64) -> DryFriction<N> {
        DryFriction { row: self.row(jacobian, 0.0, v, weight, dt), limit }
    }
}

/// The constraints of one physics step: one-sided rows (joint limits), dry friction and contact
/// cones.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Constraints<const N: usize> {
    pub rows: Vec<Row<N>>,
    pub friction: Vec<DryFriction<N>>,
    pub cones: Vec<Cone<N>>,
}

/// MuJoCo's constraint cost at one acceleration, its forces (`-ds/d(Ja)`, mapped by `Jᵀ`) and
/// its Hessian in generalized coordinates.
struct Evaluated<const N: usize> {
    cost: f64,
    force: Coords<N>,
    hessian: SMatrix<f64, N, N>,
}

/// Newton iterations are stopped here (each is exact once the constraint states settle; the cone
/// converges quadratically).
const MAX_NEWTON: usize = 50;

impl<const N: usize> Constraints<N> {
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty() && self.friction.is_empty() && self.cones.is_empty()
    }

    fn evaluate(&self, a: &Coords<N>) -> Evaluated<N> {
        let mut e = Evaluated { cost: 0.0, force: Coords::<N>::zeros(), hessian: SMatrix::<f64, N, N>::zeros() };
        let quadratic = |e: &mut Evaluated<N>, row: &Row<N>, jar: f64| {
            let d = 1.0 / row.regularizer;
            e.cost += 0.5 * d * jar * jar;
            match row.axis() {
                // A joint's limit or friction: the dense update below would add only zeros
                // elsewhere, which leave every sum as it is (none of them holds -0).
                Some(k) => {
                    let j = row.jacobian[k];
                    e.force[k] -= j * (d * jar);
                    e.hessian[(k, k)] += j * j * d;
                }
                None => {
                    e.force -= row.jacobian * (d * jar);
                    e.hessian += row.jacobian * row.jacobian.transpose() * d;
                }
            }
        };
        for row in &self.rows {
            let jar = row.shortfall(a);
            if jar < 0.0 {
                quadratic(&mut e, row, jar);
            }
        }
        // Dry friction: quadratic within `R·limit` of the reference, linear (the force at its
        // limit) beyond.
        for f in &self.friction {
            let jar = f.row.shortfall(a);
            let edge = f.row.regularizer * f.limit;
            if jar.abs() < edge {
                quadratic(&mut e, &f.row, jar);
            } else {
                e.cost += f.limit * jar.abs() - 0.5 * edge * f.limit;
                e.force -= f.row.jacobian * (f.limit * jar.signum());
            }
        }
        for cone in &self.cones {
            let dim = cone.dim;
            let rows = &cone.rows[..dim];
            let jar: [f64; 4] = std::array::from_fn(|j| if j < dim { rows[j].shortfall(a) } else { 0.0 });
            let mu = cone.mu;
            // u = (jar₀·mu, jarⱼ·frictionⱼ): the cone's coordinates, N along the normal, T the
            // length of the friction part.
            let scale: [f64; 4] = [mu, cone.friction[0], cone.friction[1], cone.friction[2]];
            let u: [f64; 4] = std::array::from_fn(|j| if j < dim { jar[j] * scale[j] } else { 0.0 });
            let (n, t) = (u[0], libm::hypot(libm::hypot(u[1], u[2]), u[3]));
            if n >= mu * t || (t <= 0.0 && n >= 0.0) {
                continue;
            }
            if mu * n + t <= 0.0 || (t <= 0.0 && n < 0.0) {
                for (row, &jar) in rows.iter().zip(&jar) {
                    quadratic(&mut e, row, jar);
                }
                continue;
            }
            // Middle zone: 0.5·Dm·(N - mu·T)², Dm = D0 / (mu²(1 + mu²)).
            let dm = 1.0 / cone.rows[0].regularizer / (mu * mu * (1.0 + mu * mu));
            let nmt = n - mu * t;
            e.cost += 0.5 * dm * nmt * nmt;
            let f0 = -dm * nmt * mu;
            let force: [f64; 4] = std::array::from_fn(|j| if j == 0 { f0 } else { -f0 / t * u[j] * scale[j] });
            let mut h = [[0.0; 4]; 4];
            h[0][0] = 1.0;
            for j in 1..dim {
                h[0][j] = -mu / t * u[j];
                h[j][0] = h[0][j];
                for k in 1..dim {
                    h[j][k] = mu * n / (t * t * t) * u[j] * u[k] + if j == k { mu * mu - mu * n / t } else { 0.0 };
                }
            }
            for j in 0..dim {
                e.force += rows[j].jacobian * force[j];
                for k in 0..dim {
                    e.hessian += rows[j].jacobian * rows[k].jacobian.transpose() * (dm * scale[j] * h[j][k] * scale[k]);
                }
            }
        }
        e
    }

    /// The generalized constraint forces for the next physics step, from the mass matrix and the
    /// smooth forces (actuators + passive - bias) at its start: the accelerations minimize
    /// MuJoCo's cost `½(a - a₀)ᵀM(a - a₀) + s(Ja - aref)`, found by Newton's method with a
    /// backtracking line search, as MuJoCo's Newton solver does.
    pub fn forces(&self, mass: &SMatrix<f64, N, N>, smooth: &Coords<N>) -> Coords<N> {
        if self.is_empty() {
            return Coords::<N>::zeros();
        }
        let a0 = mass.cholesky().expect("an arm's mass matrix is positive definite").solve(smooth);
        let total = |a: &Coords<N>, e: &Evaluated<N>| 0.5 * (a - a0).dot(&(mass * (a - a0))) + e.cost;
        let mut a = a0;
        let mut e = self.evaluate(&a);
        for _ in 0..MAX_NEWTON {
            let gradient = mass * (a - a0) - e.force;
            let step = (mass + e.hessian).cholesky().expect("the constraint Hessian is positive definite").solve(&-gradient);
            let slope = gradient.dot(&step);
            if slope >= 0.0 {
                break;
            }
            let before = total(&a, &e);
            let mut alpha = 1.0;
            let (next, evaluated) = loop {
                let trial = a + step * alpha;
                let evaluated = self.evaluate(&trial);
                if total(&trial, &evaluated) <= before + 1e-4 * alpha * slope || alpha < 1e-10 {
                    break (trial, evaluated);
                }
                alpha *= 0.5;
            };
            let moved = (next - a).norm();
            (a, e) = (next, evaluated);
            if moved <= 1e-14 * (1.0 + a.norm()) {
                break;
            }
        }
        e.force
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impedance_ramps_from_d0_to_dwidth_over_width() {
        let s = Softness::MUJOCO_DEFAULT;
        assert!((s.impedance(0.0) - 0.9).abs() < 1e-15);
        assert!((s.impedance(0.0005) - 0.925).abs() < 1e-12);
        assert!((s.impedance(0.00025) - (0.9 + 0.05 * 0.125)).abs() < 1e-12);
        assert_eq!(s.impedance(0.01), 0.95);
        let (k, b) = s.stiffness_damping(0.002);
        assert!((k - 1.0 / (0.95 * 0.95 * 0.0004)).abs() < 1e-9 && (b - 2.0 / (0.95 * 0.02)).abs() < 1e-12);
    }

    #[test]
    fn two_geoms_mix_to_the_mean_as_mujoco_mixes_equal_solmix() {
        let pad = Softness { solref: [0.01, 0.5], ..Softness::MUJOCO_DEFAULT };
        let m = Softness::MUJOCO_DEFAULT.mixed(&pad);
        assert_eq!(m.solref, [0.015, 0.75]);
        assert_eq!(m.solimp, Softness::MUJOCO_DEFAULT.solimp);
    }

    /// A puck pressed into a floor (dof 0 along the normal) and twisted about the normal (dof 1).
    /// With `condim` 3 nothing resists the twist. With 4 the torsional row is regularized as
    /// MuJoCo's (`R · spin² = R_t · slide²`, so 40,000 times softer than a tangent row at 0.005):
    /// a small twist is damped as that row alone would (`f = -τ / (1 + I·R)`), and a large one
    /// slips at the cone's edge, `spin · f_n`.
    #[test]
    fn the_torsional_row_resists_a_twist_up_to_its_friction() {
        let inertia = 0.01;
        let mass = SMatrix::<f64, 2, 2>::from_diagonal(&Coords::<2>::new(1.0, inertia));
        let s = Softness::MUJOCO_DEFAULT;
        let qd = Coords::<2>::zeros();
        let cone = |spin: Option<f64>| {
            let (normal, twist) = (Coords::<2>::new(1.0, 0.0), Coords::<2>::new(0.0, 1.0));
            s.cone(normal, [Coords::<2>::zeros(); 2], twist, -0.001, &qd, 1.0, Friction { slide: 1.0, spin }, 20.0, 0.002)
        };
        let forces = |spin: Option<f64>, torque: f64| Constraints { cones: vec![cone(spin)], ..Constraints::default() }.forces(&mass, &Coords::<2>::new(-9.81, torque));
        assert_eq!(cone(None).dim, 3);
        assert_eq!(forces(None, 0.01)[1], 0.0);
        let c = cone(Some(0.005));
        assert_eq!(c.dim, 4);
        let r = c.rows[3].regularizer;
        assert!((r / c.rows[1].regularizer - 40_000.0).abs() < 1e-6, "{r}");
        let held = forces(Some(0.005), 0.01);
        let expected = -0.01 / (1.0 + inertia * r);
        assert!((held[1] - expected).abs() < 1e-9 * expected.abs(), "{held:?} against {expected}");
        let slipping = forces(Some(0.005), 1.0);
        let limit = 0.005 * slipping[0];
        assert!(slipping[0] > 9.81, "{slipping:?}");
        assert!(slipping[1] < 0.0 && -slipping[1] <= limit * (1.0 + 1e-9) && -slipping[1] >= 0.9 * limit, "{slipping:?}, limit {limit}");
    }

    /// A unit mass with dry friction 1 N: a 0.5 N push is mostly held but creeps (the soft row
    /// gives `a = F / (M + 1/R)`, no hard stick); a 5 N push slips against exactly 1 N.
    #[test]
    fn dry_friction_lets_a_small_push_creep_and_a_large_one_slip() {
        let mass = SMatrix::<f64, 1, 1>::identity();
        let s = Softness::MUJOCO_DEFAULT;
        let friction = s.dry_friction(Coords::<1>::new(1.0), 0.0, 1.0, 1.0, 0.002);
        let r = friction.row.regularizer;
        assert!((r - 0.1 / 0.9).abs() < 1e-12, "{r}");
        let forces = |push: f64| Constraints { friction: vec![friction], ..Constraints::default() }.forces(&mass, &Coords::<1>::new(push))[0];
        let creep = 0.5 + forces(0.5);
        assert!((creep - 0.5 / (1.0 + 1.0 / r)).abs() < 1e-12 && creep > 0.0, "{creep}");
        assert!((forces(5.0) + 1.0).abs() < 1e-12 && (forces(-5.0) - 1.0).abs() < 1e-12);
    }

    /// Two rows on one unit mass, one of them pulled out of its constraint: only the other pushes.
    #[test]
    fn a_row_that_would_pull_is_dropped() {
        let mass = SMatrix::<f64, 2, 2>::identity();
        let s = Softness::MUJOCO_DEFAULT;
        let pushed = s.row(Coords::<2>::new(1.0, 0.0), -0.001, 0.0, 1.0, 0.002);
        let leaving = s.row(Coords::<2>::new(0.0, 1.0), -0.001, 50.0, 1.0, 0.002);
        let f = Constraints { rows: vec![pushed, leaving], ..Constraints::default() }.forces(&mass, &Coords::<2>::new(-1.0, 0.0));
        assert!(f[0] > 1.0, "{f:?}");
        assert_eq!(f[1], 0.0, "{f:?}");
        // The pushing row's acceleration is MuJoCo's mix of the free one (-1) and aref:
        // -1 + f = (1 - d)·(-1) + d·aref.
        let d = s.impedance(0.001);
        assert!((f[0] - d * (pushed.aref + 1.0)).abs() < 1e-9, "{f:?}");
    }
}
