//! Immutable description of an arm: a kinematic tree of bodies in MuJoCo's conventions.
//!
//! Bodies are listed parent-first. Each body has a pose relative to its parent and at most one
//! joint, located at the body origin with its axis in the body frame (as every joint of the
//! Panda and the PiPER is). Inertial properties, contact geometry and simple visual shapes hang
//! off the bodies. An `ArmModel` is shared (read-only) by every episode that uses the arm.

use serde::{Deserialize, Serialize};

use crate::spatial::{Mat3, Pose, Vec3};

/// Hinge (revolute) or slide (prismatic), as MuJoCo names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum JointKind {
    Hinge,
    Slide,
}

/// A one-degree-of-freedom joint with MuJoCo's passive parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    pub name: &'static str,
    pub kind: JointKind,
    /// Unit axis in the body frame.
    pub axis: Vec3,
    /// Position limits (rad or m).
    pub range: [f64; 2],
    /// Viscous damping (N·m·s/rad or N·s/m), integrated implicitly as MuJoCo's Euler does.
    pub damping: f64,
    /// Reflected rotor inertia added to the mass matrix diagonal.
    pub armature: f64,
    /// Dry friction (N·m or N).
    pub frictionloss: f64,
    /// MuJoCo's soft constraints of the joint's limit and dry friction (robosuite keeps
    /// `solreflimit`/`solimplimit` and `solreffriction`/`solimpfriction` at the same defaults),
    /// applied by the arm's controller ([`crate::limits`]); `None` leaves both to rapier's
    /// joint constraint and dof friction.
    pub soft: Option<crate::soft::Softness>,
}

/// Mass properties of a body about its centre of mass, in the body frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Inertial {
    pub mass: f64,
    pub com: Vec3,
    /// Inertia tensor about the COM, body axes.
    pub inertia: Mat3,
}

impl Inertial {
    /// MuJoCo's `<inertial pos quat mass diaginertia>`.
    pub fn new(mass: f64, com: [f64; 3], diag: [f64; 3], quat_wxyz: [f64; 4]) -> Self {
        let r = Pose::from_wxyz([0.0; 3], quat_wxyz).rot;
        let d = Mat3::from_diagonal(&Vec3::from(diag));
        Inertial { mass, com: Vec3::from(com), inertia: r * d * r.transpose() }
    }

    /// URDF's `<inertia ixx iyy izz ixy ixz iyz>` about the COM, body axes.
    pub fn full(mass: f64, com: [f64; 3], [ixx, iyy, izz, ixy, ixz, iyz]: [f64; 6]) -> Self {
        Inertial { mass, com: Vec3::from(com), inertia: Mat3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz) }
    }

    pub fn diag(mass: f64, com: [f64; 3], diag: [f64; 3]) -> Self {
        Self::new(mass, com, diag, [1.0, 0.0, 0.0, 0.0])
    }

    /// The combined mass properties of `self` and `other` (given in a frame placed at `pose`
    /// relative to `self`'s frame), expressed in `self`'s frame.
    pub fn merged(&self, other: &Inertial, pose: &Pose) -> Inertial {
        let m = self.mass + other.mass;
        let c_other = pose.transform_point(&other.com);
        let com = if m > 0.0 { (self.com * self.mass + c_other * other.mass) / m } else { self.com };
        let shift = |i: &Mat3, mass: f64, c: &Vec3| -> Mat3 {
            let d = c - com;
            i + (Mat3::identity() * d.dot(&d) - d * d.transpose()) * mass
        };
        let i_other = pose.rot * other.inertia * pose.rot.transpose();
        Inertial {
            mass: m,
            com,
            inertia: shift(&self.inertia, self.mass, &self.com) + shift(&i_other, other.mass, &c_other),
        }
    }
}

/// Primitive shapes for contact and for visuals (no mesh files ship with the project).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    Box { half: [f64; 3] },
    /// Axis along local z.
    Capsule { radius: f64, half_height: f64 },
    /// Axis along local z.
    Cylinder { radius: f64, half_height: f64 },
    Sphere { radius: f64 },
}

/// What a collider touches with: a primitive shape, or the convex hull of a few points in the
/// collider's frame (MuJoCo collides a mesh as its convex hull; the Panda's links are such hulls,
/// fitted by `xval/fit_link_hulls.py` with a few corners, as rapier bounds every collider from all
/// its corners at each step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactShape {
    Primitive(Shape),
    Hull(&'static [[f64; 3]]),
}

/// What a collision geometry is for; decides which pairs may touch (MuJoCo's contype/conaffinity).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactRole {
    /// Arm links, hand and mount: touch the scene and, with [`ArmModel::self_contact`], the arm.
    Link,
    /// Finger bodies (robosuite: contype 0, conaffinity 1): touch objects, not the other finger.
    Finger,
    /// Finger pads: the high-friction boxes that hold objects; they also touch each other.
    Pad,
}

/// A contact shape fixed to a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Collider {
    pub name: &'static str,
    pub shape: ContactShape,
    pub local: Pose,
    pub friction: f64,
    pub role: ContactRole,
}

/// A coloured shape drawn for a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    pub shape: Shape,
    pub local: Pose,
    pub rgba: [f32; 4],
}

/// One body of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: &'static str,
    /// Index of the parent body; `None` only for the root (the robot base).
    pub parent: Option<usize>,
    /// Pose relative to the parent at zero joint position.
    pub local: Pose,
    pub joint: Option<JointSpec>,
    pub inertial: Inertial,
    pub colliders: Vec<Collider>,
    /// The convex hull (body frame) this body touches the rest of the arm and the scene's fixed
    /// bodies with, as MuJoCo collides its collision mesh ([`crate::soft_contact`]); `None`: its
    /// colliders.
    pub self_hull: Option<&'static [[f64; 3]]>,
    pub visuals: Vec<Visual>,
}

/// A named frame on a body (MuJoCo site or camera mount).
#[derive(Clone, Debug, PartialEq)]
pub struct Site {
    pub name: &'static str,
    pub body: usize,
    pub local: Pose,
}

/// The immutable description of an arm with its gripper.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmModel {
    pub name: &'static str,
    /// Parent-first list; body 0 is the base, fixed to the world.
    pub bodies: Vec<Body>,
    /// Body index of every degree of freedom, in generalized-coordinate order.
    pub dofs: Vec<usize>,
    /// Number of arm joints (the first `arm_dofs` coordinates); the rest are gripper fingers.
    pub arm_dofs: usize,
    pub sites: Vec<Site>,
    /// Whether the arm touches itself ([`crate::soft_contact`]): links, hand and mount touch
    /// every other part but their parent and child, as robosuite's contype/conaffinity make the
    /// Panda's (a hand folded back onto the forearm stops there).
    pub self_contact: bool,
}

impl ArmModel {
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    pub fn site(&self, name: &str) -> Option<&Site> {
        self.sites.iter().find(|s| s.name == name)
    }

    /// The joint of degree of freedom `i`.
    pub fn joint(&self, i: usize) -> &JointSpec {
        self.bodies[self.dofs[i]].joint.as_ref().expect("every dof body has a joint")
    }

    /// Number of degrees of freedom (arm plus fingers).
    pub fn ndofs(&self) -> usize {
        self.dofs.len()
    }

    /// Checks the invariants the kinematics relies on; models are built in code, so a failure is
    /// a programming error reported at construction.
    pub(crate) fn validated(self) -> Self {
        for (i, body) in self.bodies.iter().enumerate() {
            match body.parent {
                None => assert_eq!(i, 0, "only the first body may be the root"),
                Some(p) => assert!(p < i, "body {} listed before its parent", body.name),
            }
        }
        let with_joint: Vec<usize> =
            (0..self.bodies.len()).filter(|&i| self.bodies[i].joint.is_some()).collect();
        assert_eq!(with_joint, self.dofs, "dofs must list the jointed bodies in order");
        assert!(self.arm_dofs <= self.dofs.len());
        self
    }
}
