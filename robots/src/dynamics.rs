//! Kinematics and rigid-body dynamics of an [`ArmModel`], written out with fixed-size maths.
//!
//! Everything the operational-space controller needs, computed the way MuJoCo does for the same
//! tree: body poses, site Jacobians (world frame), the joint-space mass matrix with armature
//! (`qM`), and the bias forces `c(q, q̇) + g(q)` (`qfrc_bias`). The number of degrees of freedom
//! is a const generic so all matrices live on the stack.

use nalgebra::{SMatrix, SVector};

use crate::fluid::{Fluid, InertiaBox};
use crate::model::{ArmModel, JointKind};
use crate::spatial::{Coords, Pose, Vec3, axis_angle};

/// World-frame Jacobian: rows 0–2 linear, 3–5 angular.
pub type Jacobian<const N: usize> = SMatrix<f64, 6, N>;
/// A world-frame twist `[v; ω]` or wrench `[f; τ]`, both about one origin.
type Twist = SVector<f64, 6>;

/// Kinematic state of every body for one joint configuration.
#[derive(Clone, Debug)]
pub struct BodyPoses {
    /// World pose of each body frame.
    pub poses: Vec<Pose>,
}

/// Dynamics helper bound to a model: precomputes which degrees of freedom move which body.
#[derive(Clone, Debug)]
pub struct ArmDynamics<const N: usize> {
    model: std::sync::Arc<ArmModel>,
    /// `support[b][i]`: does dof `i` move body `b`?
    support: Vec<[bool; N]>,
    /// Dof index of the joint on body `b`, if any.
    body_dof: Vec<Option<usize>>,
    /// Equivalent inertia box of each body (MuJoCo's fluid model), if it has mass.
    boxes: Vec<Option<InertiaBox>>,
    gravity: Vec3,
}

impl<const N: usize> ArmDynamics<N> {
    /// Binds a model whose dof count must be `N`.
    pub fn new(model: std::sync::Arc<ArmModel>, gravity: [f64; 3]) -> Self {
        assert_eq!(model.ndofs(), N, "model {} has {} dofs", model.name, model.ndofs());
        let nb = model.bodies.len();
        let mut body_dof = vec![None; nb];
        for (i, &b) in model.dofs.iter().enumerate() {
            body_dof[b] = Some(i);
        }
        let mut support = vec![[false; N]; nb];
        for b in 0..nb {
            if let Some(p) = model.bodies[b].parent {
                support[b] = support[p];
            }
            if let Some(i) = body_dof[b] {
                support[b][i] = true;
            }
        }
        let boxes = model.bodies.iter().map(|b| InertiaBox::of(&b.inertial)).collect();
        ArmDynamics { model, support, body_dof, boxes, gravity: Vec3::from(gravity) }
    }

    pub fn model(&self) -> &ArmModel {
        &self.model
    }

    /// World poses of all bodies for joint positions `q`, with the base at `base`.
    pub fn forward(&self, base: &Pose, q: &Coords<N>) -> BodyPoses {
        let bodies = &self.model.bodies;
        let mut poses: Vec<Pose> = Vec::with_capacity(bodies.len());
        for (b, body) in bodies.iter().enumerate() {
            let parent = body.parent.map_or(*base, |p| poses[p]);
            let mut pose = parent.mul(&body.local);
            if let (Some(joint), Some(i)) = (&body.joint, self.body_dof[b]) {
                match joint.kind {
                    JointKind::Hinge => pose.rot *= axis_angle(&joint.axis, q[i]),
                    JointKind::Slide => pose.pos += pose.rot * joint.axis * q[i],
                }
            }
            poses.push(pose);
        }
        BodyPoses { poses }
    }

    /// World pose of a frame fixed to `body` at `local`.
    pub fn frame_pose(&self, poses: &BodyPoses, body: usize, local: &Pose) -> Pose {
        poses.poses[body].mul(local)
    }

    /// World-frame axis and anchor of dof `i`'s joint.
    fn joint_axis(&self, poses: &BodyPoses, i: usize) -> (JointKind, Vec3, Vec3) {
        let b = self.model.dofs[i];
        let joint = self.model.joint(i);
        let pose = &poses.poses[b];
        (joint.kind, pose.rot * joint.axis, pose.pos)
    }

    /// Jacobian of the point `point` (world coordinates) rigidly attached to `body`:
    /// `[v; ω] = J q̇`.
    pub fn point_jacobian(&self, poses: &BodyPoses, body: usize, point: &Vec3) -> Jacobian<N> {
        let mut jac = Jacobian::<N>::zeros();
        for i in 0..N {
            if !self.support[body][i] {
                continue;
            }
            let (kind, axis, anchor) = self.joint_axis(poses, i);
            match kind {
                JointKind::Hinge => {
                    let v = axis.cross(&(point - anchor));
                    jac.fixed_view_mut::<3, 1>(0, i).copy_from(&v);
                    jac.fixed_view_mut::<3, 1>(3, i).copy_from(&axis);
                }
                JointKind::Slide => jac.fixed_view_mut::<3, 1>(0, i).copy_from(&axis),
            }
        }
        jac
    }

    /// Motion of dof `i` as a world-frame twist `[v; ω]`, `v` being the velocity of the point
    /// (moving with the dof's body) at `origin`.
    fn motion(&self, poses: &BodyPoses, i: usize, origin: &Vec3) -> Twist {
        let (kind, axis, anchor) = self.joint_axis(poses, i);
        let mut s = Twist::zeros();
        match kind {
            JointKind::Hinge => {
                s.fixed_rows_mut::<3>(0).copy_from(&axis.cross(&(origin - anchor)));
                s.fixed_rows_mut::<3>(3).copy_from(&axis);
            }
            JointKind::Slide => s.fixed_rows_mut::<3>(0).copy_from(&axis),
        }
        s
    }

    /// The motions of all dofs about `origin`.
    fn motions(&self, poses: &BodyPoses, origin: &Vec3) -> [Twist; N] {
        std::array::from_fn(|i| self.motion(poses, i, origin))
    }

    /// Spatial inertia of body `b` about `origin` (world axes), for twists `[v; ω]`:
    /// `[[m, −m[c]ₓ], [m[c]ₓ, I − m[c]ₓ[c]ₓ]]` with `c` the COM relative to `origin`.
    fn spatial_inertia(&self, poses: &BodyPoses, b: usize, origin: &Vec3) -> SMatrix<f64, 6, 6> {
        let inertial = &self.model.bodies[b].inertial;
        let pose = &poses.poses[b];
        let m = inertial.mass;
        let cx = (pose.transform_point(&inertial.com) - origin).cross_matrix();
        let mut k = SMatrix::<f64, 6, 6>::zeros();
        k.fixed_view_mut::<3, 3>(0, 0).fill_diagonal(m);
        k.fixed_view_mut::<3, 3>(0, 3).copy_from(&(cx * -m));
        k.fixed_view_mut::<3, 3>(3, 0).copy_from(&(cx * m));
        k.fixed_view_mut::<3, 3>(3, 3).copy_from(&(pose.rot * inertial.inertia * pose.rot.transpose() - cx * cx * m));
        k
    }

    /// Joint-space mass matrix including armature (MuJoCo's `qM`), by the composite-rigid-body
    /// algorithm: `M[i][j] = Sᵢᵀ I꜀ⱼ Sⱼ` with `I꜀ⱼ` the inertia of everything dof `j` moves,
    /// wherever dof `i` moves dof `j`'s body, and 0 between branches (the two fingers).
    pub fn mass_matrix(&self, poses: &BodyPoses) -> SMatrix<f64, N, N> {
        // About the arm's root: world coordinates would mix metre-sized lever arms into the
        // wrist's gram-scale terms.
        let origin = poses.poses[0].pos;
        let bodies = &self.model.bodies;
        let mut composite = vec![SMatrix::<f64, 6, 6>::zeros(); bodies.len()];
        for b in (0..bodies.len()).rev() {
            if bodies[b].inertial.mass > 0.0 {
                composite[b] += self.spatial_inertia(poses, b, &origin);
            }
            if let Some(p) = bodies[b].parent {
                let c = composite[b];
                composite[p] += c;
            }
        }
        let s = self.motions(poses, &origin);
        let mut m = SMatrix::<f64, N, N>::zeros();
        for j in 0..N {
            let body = self.model.dofs[j];
            let f = composite[body] * s[j];
            for i in (0..N).filter(|&i| self.support[body][i]) {
                m[(i, j)] = s[i].dot(&f);
                m[(j, i)] = m[(i, j)];
            }
        }
        for i in 0..N {
            m[(i, i)] += self.model.joint(i).armature;
        }
        m
    }

    /// Inverse dynamics (recursive Newton–Euler): the generalized forces that produce
    /// accelerations `qdd` at velocities `qd` under gravity. With `qdd = 0` this is MuJoCo's
    /// `qfrc_bias` (Coriolis, centrifugal and gravity terms).
    pub fn inverse_dynamics(&self, poses: &BodyPoses, qd: &Coords<N>, qdd: &Coords<N>) -> Coords<N> {
        let bodies = &self.model.bodies;
        let nb = bodies.len();
        // Per body: angular velocity, angular acceleration, linear acceleration of the origin
        // (the base accelerates upward at g, which stands in for gravity on every body).
        let mut w = vec![Vec3::zeros(); nb];
        let mut dw = vec![Vec3::zeros(); nb];
        let mut a = vec![Vec3::zeros(); nb];
        // Net force and moment (about the body origin) each body needs, then accumulated upward.
        let mut f = vec![Vec3::zeros(); nb];
        let mut n = vec![Vec3::zeros(); nb];
        for (b, body) in bodies.iter().enumerate() {
            let pose = &poses.poses[b];
            let (mut wb, mut dwb, mut ab) = match body.parent {
                None => (Vec3::zeros(), Vec3::zeros(), -self.gravity),
                Some(p) => {
                    let r = pose.pos - poses.poses[p].pos;
                    let (wp, dwp) = (w[p], dw[p]);
                    (wp, dwp, a[p] + dwp.cross(&r) + wp.cross(&wp.cross(&r)))
                }
            };
            if let Some(i) = self.body_dof[b] {
                let (kind, axis, _) = self.joint_axis(poses, i);
                let wp = wb;
                match kind {
                    JointKind::Hinge => {
                        wb += axis * qd[i];
                        dwb += wp.cross(&(axis * qd[i])) + axis * qdd[i];
                    }
                    JointKind::Slide => {
                        ab += wp.cross(&(axis * qd[i])) * 2.0 + axis * qdd[i];
                    }
                }
            }
            let inertial = &body.inertial;
            let c = pose.rot * inertial.com;
            let ac = ab + dwb.cross(&c) + wb.cross(&wb.cross(&c));
            let i_world = pose.rot * inertial.inertia * pose.rot.transpose();
            let fb = ac * inertial.mass;
            f[b] = fb;
            n[b] = i_world * dwb + wb.cross(&(i_world * wb)) + c.cross(&fb);
            (w[b], dw[b], a[b]) = (wb, dwb, ab);
        }
        let mut tau = Coords::<N>::zeros();
        for b in (0..nb).rev() {
            if let Some(i) = self.body_dof[b] {
                let (kind, axis, _) = self.joint_axis(poses, i);
                tau[i] = match kind {
                    JointKind::Hinge => axis.dot(&n[b]),
                    JointKind::Slide => axis.dot(&f[b]),
                };
            }
            if let Some(p) = bodies[b].parent {
                let r = poses.poses[b].pos - poses.poses[p].pos;
                let (fb, nb_) = (f[b], n[b]);
                f[p] += fb;
                n[p] += nb_ + r.cross(&fb);
            }
        }
        tau
    }

    /// Generalized forces of MuJoCo's inertia-box fluid model on every moving body: each body's
    /// twist accumulated outward from the root, its drag wrench moved to a common origin, and
    /// the wrenches summed back inward onto the dofs.
    pub fn fluid_forces(&self, fluid: &Fluid, poses: &BodyPoses, qd: &Coords<N>) -> Coords<N> {
        let origin = poses.poses[0].pos;
        let bodies = &self.model.bodies;
        let s = self.motions(poses, &origin);
        let mut twist = vec![Twist::zeros(); bodies.len()];
        let mut wrench = vec![Twist::zeros(); bodies.len()];
        for (b, body) in bodies.iter().enumerate() {
            let mut t = body.parent.map_or(Twist::zeros(), |p| twist[p]);
            if let Some(i) = self.body_dof[b] {
                t += s[i] * qd[i];
            }
            twist[b] = t;
            let Some(ibox) = &self.boxes[b] else { continue };
            if !self.support[b].iter().any(|&s| s) {
                continue;
            }
            let pose = &poses.poses[b];
            let c = pose.transform_point(&body.inertial.com) - origin;
            let w = t.fixed_rows::<3>(3).into_owned();
            let v = t.fixed_rows::<3>(0) + w.cross(&c);
            let (force, torque) = ibox.forces(fluid, &(pose.rot * ibox.axes), &v, &w);
            wrench[b].fixed_rows_mut::<3>(0).copy_from(&force);
            wrench[b].fixed_rows_mut::<3>(3).copy_from(&(torque + c.cross(&force)));
        }
        let mut tau = Coords::<N>::zeros();
        for b in (0..bodies.len()).rev() {
            if let Some(i) = self.body_dof[b] {
                tau[i] = s[i].dot(&wrench[b]);
            }
            if let Some(p) = bodies[b].parent {
                let w = wrench[b];
                wrench[p] += w;
            }
        }
        tau
    }

    /// `qfrc_bias`: Coriolis, centrifugal and gravity generalized forces at rest acceleration.
    pub fn bias_forces(&self, poses: &BodyPoses, qd: &Coords<N>) -> Coords<N> {
        self.inverse_dynamics(poses, qd, &Coords::<N>::zeros())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panda::{Mount, model};

    fn config() -> (ArmDynamics<9>, BodyPoses, Coords<9>) {
        let dynamics = ArmDynamics::<9>::new(model(Mount::Pedestal), [0.0, 0.0, -9.81]);
        let q = Coords::<9>::from_column_slice(&[0.3, -0.7, 0.2, -2.1, 0.4, 1.9, -0.6, 0.03, -0.02]);
        let qd = Coords::<9>::from_column_slice(&[0.9, -1.2, 2.0, 0.7, -2.5, 1.1, 3.0, 0.2, -0.3]);
        let poses = dynamics.forward(&Pose { pos: Vec3::new(-0.66, 0.1, 0.9), rot: axis_angle(&Vec3::z(), 0.3) }, &q);
        (dynamics, poses, qd)
    }

    /// The definitions: kinetic energy `½ q̇ᵀ M q̇` summed body by body through each COM's
    /// Jacobian, and the fluid wrench at each COM mapped back through the same Jacobian.
    #[test]
    fn composite_rigid_body_mass_matrix_and_fluid_forces_match_the_per_body_jacobians() {
        let (dynamics, poses, qd) = config();
        let mut mass = SMatrix::<f64, 9, 9>::zeros();
        let mut fluid = Coords::<9>::zeros();
        for (b, body) in dynamics.model().bodies.iter().enumerate() {
            let inertial = &body.inertial;
            if inertial.mass == 0.0 || !dynamics.support[b].iter().any(|&s| s) {
                continue;
            }
            let pose = &poses.poses[b];
            let j = dynamics.point_jacobian(&poses, b, &pose.transform_point(&inertial.com));
            let (jv, jw) = (j.fixed_rows::<3>(0), j.fixed_rows::<3>(3));
            mass += jv.transpose() * jv * inertial.mass + jw.transpose() * (pose.rot * inertial.inertia * pose.rot.transpose()) * jw;
            let ibox = dynamics.boxes[b].as_ref().unwrap();
            let t = j * qd;
            let (f, tq) = ibox.forces(&Fluid::ROBOSUITE_AIR, &(pose.rot * ibox.axes), &t.fixed_rows::<3>(0).into(), &t.fixed_rows::<3>(3).into());
            fluid += jv.transpose() * f + jw.transpose() * tq;
        }
        for i in 0..9 {
            mass[(i, i)] += dynamics.model().joint(i).armature;
        }
        let crba = dynamics.mass_matrix(&poses);
        assert!((crba - mass).amax() < 1e-13, "{crba} vs {mass}");
        assert_eq!(crba[(7, 8)], 0.0, "the fingers are separate branches");
        let ours = dynamics.fluid_forces(&Fluid::ROBOSUITE_AIR, &poses, &qd);
        assert!((ours - fluid).amax() < 1e-13 * fluid.amax().max(1.0), "{ours} vs {fluid}");
        assert!(fluid.amax() > 1e-3, "the test moves fast enough to feel the air: {fluid}");
    }
}
