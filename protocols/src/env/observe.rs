//! The robot's part of an observation, as robosuite reports it.

use vifo_scenes::sim::Sim;

use crate::policy::Observation;

/// Writes eef pose, finger and arm joint positions of the current state into `obs` (the
/// PiPER's: its tool point, its two finger slides, its six joints and a 0).
///
/// `robot0_eef_quat` is MuJoCo's `xquat` of the hand body, which MuJoCo composes along the
/// kinematic chain and never flips. From LIBERO's start pose (hand pointing down, x ≈ +1) that
/// keeps x > 0 for every hand rotation of less than 180° away from it, so the sign is chosen
/// with x ≥ 0 instead of the usual w ≥ 0. The sign matters: openpi's 8-D state takes the
/// axis-angle of this quaternion, which differs between q and −q near w = 0.
pub fn proprio(sim: &Sim, obs: &mut Observation) {
    let robot = &sim.model().robot;
    let world = sim.world();
    let eef = robot.grip_site_pose(world).pos;
    let [w, x, y, z] = robot.hand_pose(world).quat_wxyz();
    let s = if x < 0.0 { -1.0 } else { 1.0 };
    let (q, fingers) = robot.joint_positions(world);
    obs.eef_pos = [eef.x, eef.y, eef.z];
    obs.eef_quat_xyzw = [s * x, s * y, s * z, s * w];
    obs.gripper_qpos = fingers;
    obs.joint_pos = q;
}
