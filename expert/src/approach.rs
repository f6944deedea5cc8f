//! The approach-and-grasp that skills taking a thing from above open with: up to cruise height,
//! across and over the grasp, down onto it, fingers closed. A skill embeds [`Approach`] as one
//! of its stages and says, in an [`ApproachPlan`], the grasp and how carefully to come in.

use vifo_robots::spatial::Vec3;
use vifo_scenes::sim::Sim;

use crate::arm;
use crate::geometry::horizontal;
use crate::motion::{Servo, Waypoint};
use crate::stages::{self, Leg, Move, Pace, Tol};

/// The group's stages, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Approach {
    Rise,
    Above,
    Descend,
    Grip,
}

/// How the hand comes down from the stand-off onto the grasp.
#[derive(Clone, Copy, Debug)]
pub enum Descent {
    /// Straight at it, at fine pace.
    Direct,
    /// In steps of `step` (m), each taken only while within `within` of the grasp sideways: for a
    /// grasp with little room around the fingers, where the joints lag a fast arm.
    Stepped { step: f64, within: f64 },
}

/// One skill's approach: where it grasps and how it comes in.
#[derive(Clone, Copy, Debug)]
pub struct ApproachPlan {
    /// The grip site's pose when the fingers close; the hand turns to its orientation on the
    /// way up and keeps it.
    pub grasp: Waypoint,
    /// The height the hand travels at (see [`crate::geometry::cruise_height`]).
    pub cruise_z: f64,
    /// The stand-off over the grasp the descent starts from.
    pub low: f64,
    /// Pace and tolerance of the leg over the grasp.
    pub above: (Pace, Tol),
    pub descent: Descent,
    /// Gripper command on the way in.
    pub grip: f64,
}

/// Steps the fingers take to close: the gripper's ramp takes about that long to pinch.
const GRIP_STEPS: usize = 12;
/// Within this of the grasp (m) the descent is over.
const ARRIVED: f64 = 0.004;

impl Approach {
    /// One control step of this stage (run `steps` steps so far): its leg, and the stage after
    /// it, `None` after the grip (the skill's own stages follow).
    pub fn leg(self, sim: &Sim, steps: usize, plan: &ApproachPlan) -> (Leg, Option<Approach>) {
        let ee = arm::of(sim).grip_site().pos;
        let at = plan.grasp.pos;
        match self {
            Approach::Rise => (stages::rise(sim, plan.cruise_z, plan.grasp.rot, plan.grip), Some(Approach::Above)),
            Approach::Above => {
                let wp = Waypoint { pos: stages::over(&ee, &at, plan.cruise_z, plan.low), rot: plan.grasp.rot };
                let (pace, tol) = plan.above;
                (stages::reach(sim, wp, pace, tol, plan.grip), Some(Approach::Descend))
            }
            Approach::Descend => {
                let z = match plan.descent {
                    Descent::Direct => at.z,
                    Descent::Stepped { within, .. } if horizontal(&ee, &at) > within => ee.z,
                    Descent::Stepped { step, .. } => (ee.z - step).max(at.z),
                };
                let to = Waypoint { pos: Vec3::new(at.x, at.y, z), rot: plan.grasp.rot };
                let arrived = (ee - at).norm() < ARRIVED;
                (Leg::until(Move { to, servo: Servo::FINE, grip: plan.grip }, arrived), Some(Approach::Grip))
            }
            Approach::Grip => (stages::grasp(steps, GRIP_STEPS, plan.grasp), None),
        }
    }
}
