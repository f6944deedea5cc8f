//! MuJoCo's inertia-box fluid model (`mj_inertiaBoxFluidModel`), which robosuite switches on for
//! every scene (`density="1.2" viscosity="2e-5"`).
//!
//! MuJoCo replaces each body by the uniform box with the same mass and principal inertia and
//! applies quadratic drag and viscous resistance to it. For the Panda's placeholder inertials the
//! boxes are absurdly large (a fingertip of 10 g with 0.01 kg·m² becomes a 2.4 m cube), so air
//! drag visibly slows fast wrist rotations in LIBERO; reproducing robosuite's motion needs it.

use crate::model::Inertial;
use crate::spatial::{Mat3, Vec3};

/// Air as robosuite's `base.xml` declares it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fluid {
    pub density: f64,
    pub viscosity: f64,
}

impl Fluid {
    pub const ROBOSUITE_AIR: Fluid = Fluid { density: 1.2, viscosity: 2e-5 };
}

/// A body's equivalent inertia box: principal axes (columns, body frame) and side lengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InertiaBox {
    pub axes: Mat3,
    pub sides: Vec3,
}

impl InertiaBox {
    /// `None` for massless bodies, which MuJoCo skips.
    pub fn of(inertial: &Inertial) -> Option<InertiaBox> {
        const MIN: f64 = 1e-15;
        if inertial.mass < MIN {
            return None;
        }
        let eigen = nalgebra::SymmetricEigen::new(inertial.inertia);
        let i = eigen.eigenvalues;
        let side = |a: f64, b: f64, c: f64| ((b + c - a).max(MIN) / inertial.mass * 6.0).sqrt();
        Some(InertiaBox { axes: eigen.eigenvectors, sides: Vec3::new(side(i[0], i[1], i[2]), side(i[1], i[0], i[2]), side(i[2], i[0], i[1])) })
    }

    /// Force and torque (world frame, at the centre of mass) on a box whose principal axes are
    /// `axes_world`, moving with COM velocity `v` and angular velocity `w` (world frame).
    pub fn forces(&self, fluid: &Fluid, axes_world: &Mat3, v: &Vec3, w: &Vec3) -> (Vec3, Vec3) {
        let (lw, lv) = (axes_world.transpose() * w, axes_world.transpose() * v);
        let b = self.sides;
        let diam = (b.x + b.y + b.z) / 3.0;
        let pi = std::f64::consts::PI;
        let mut torque = lw * (-pi * diam * diam * diam * fluid.viscosity);
        let mut force = lv * (-3.0 * pi * diam * fluid.viscosity);
        let rho = fluid.density;
        let p4 = |x: f64| x * x * x * x;
        force.x -= 0.5 * rho * b.y * b.z * lv.x.abs() * lv.x;
        force.y -= 0.5 * rho * b.x * b.z * lv.y.abs() * lv.y;
        force.z -= 0.5 * rho * b.x * b.y * lv.z.abs() * lv.z;
        torque.x -= rho * b.x * (p4(b.y) + p4(b.z)) * lw.x.abs() * lw.x / 64.0;
        torque.y -= rho * b.y * (p4(b.x) + p4(b.z)) * lw.y.abs() * lw.y / 64.0;
        torque.z -= rho * b.z * (p4(b.x) + p4(b.y)) * lw.z.abs() * lw.z / 64.0;
        (axes_world * force, axes_world * torque)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholder_fingertip_is_a_huge_box() {
        let tip = Inertial::diag(0.01, [0.0; 3], [0.01, 0.01, 0.01]);
        let b = InertiaBox::of(&tip).unwrap();
        for s in b.sides.iter() {
            assert!((s - 6f64.sqrt()).abs() < 1e-12);
        }
        // Spinning at 2 rad/s about z: ρ b (b⁴ + b⁴) ω² / 64 plus the viscous term.
        let (_, t) = b.forces(&Fluid::ROBOSUITE_AIR, &Mat3::identity(), &Vec3::zeros(), &Vec3::new(0.0, 0.0, 2.0));
        let s = 6f64.sqrt();
        let expected = 1.2 * s * 2.0 * s.powi(4) * 4.0 / 64.0 + std::f64::consts::PI * s.powi(3) * 2e-5 * 2.0;
        assert!((t.z + expected).abs() < 1e-12, "{t:?}");
    }

    #[test]
    fn massless_bodies_feel_nothing() {
        assert!(InertiaBox::of(&Inertial::diag(0.0, [0.0; 3], [0.0; 3])).is_none());
    }
}
