//! What a policy sees, and the trait every policy implements.

use thiserror::Error;
use vifo_cues::RgbImage;
use vifo_scenes::sim::Sim;
use vifo_scenes::task::Atom;
use vifo_scenes::view::CameraName;

/// One observation, as LIBERO provides it (plus the instruction of the episode).
#[derive(Clone, Debug, PartialEq)]
pub struct Observation {
    /// `agentview` camera, cue inserted, upright (row 0 at the top).
    pub agentview: RgbImage,
    /// `robot0_eye_in_hand` camera, cue inserted, upright.
    pub wrist: RgbImage,
    /// Grip site position (robosuite `robot0_eef_pos`), world frame.
    pub eef_pos: [f64; 3],
    /// Hand orientation (robosuite `robot0_eef_quat`), (x, y, z, w).
    pub eef_quat_xyzw: [f64; 4],
    /// Finger joint positions (robosuite `robot0_gripper_qpos`).
    pub gripper_qpos: [f64; 2],
    /// Arm joint positions.
    pub joint_pos: [f64; 7],
    /// The instruction the policy receives this episode (may be empty).
    pub instruction: String,
    /// Control steps since the end of the settle phase.
    pub step: usize,
}

impl Observation {
    /// The image of `camera` (empty when the environment does not draw it).
    pub fn image(&self, camera: CameraName) -> &RgbImage {
        match camera {
            CameraName::AgentView => &self.agentview,
            CameraName::EyeInHand => &self.wrist,
        }
    }

    /// [`Observation::image`], for the environment to draw into.
    pub fn image_mut(&mut self, camera: CameraName) -> &mut RgbImage {
        match camera {
            CameraName::AgentView => &mut self.agentview,
            CameraName::EyeInHand => &mut self.wrist,
        }
    }

    /// openpi's 8-D LIBERO state: eef position, axis-angle of the eef quaternion (robosuite's
    /// `quat2axisangle`), finger positions.
    pub fn state8(&self) -> [f64; 8] {
        let [x, y, z, w] = self.eef_quat_xyzw;
        let w = w.clamp(-1.0, 1.0);
        let den = (1.0 - w * w).sqrt();
        let aa = if den.abs() < 1e-12 {
            [0.0; 3]
        } else {
            let s = 2.0 * libm::acos(w) / den;
            [x * s, y * s, z * s]
        };
        let p = self.eef_pos;
        [p[0], p[1], p[2], aa[0], aa[1], aa[2], self.gripper_qpos[0], self.gripper_qpos[1]]
    }
}

/// Why a policy could not produce an action. The episode is then recorded as an error (not a
/// failure) and can be retried.
#[derive(Debug, Error)]
pub enum PolicyError {
    #[error("policy connection: {0}")]
    Connection(String),
    #[error("policy sent a malformed reply: {0}")]
    Malformed(String),
    #[error("policy timed out after {0:.1} s")]
    Timeout(f64),
    #[error("{0}")]
    Other(String),
}

/// What the environment knows beyond the observation. Scripted reference policies read it
/// (the experts plan from the simulator; `random` seeds itself from the episode); learned and
/// remote policies never see it, because they implement only [`Policy::act`].
pub struct EpisodeState<'a> {
    /// The running simulation (privileged: exact poses, contacts, joint states).
    pub sim: &'a Sim,
    /// The goal of the task the episode's cue shows, when it shows one (privileged).
    pub cue_goal: Option<&'a [Atom]>,
    /// The episode's seed ([`crate::runner::seed_for`]).
    pub seed: u64,
}

/// A policy: turns observations into 7-D actions `[dx, dy, dz, dax, day, daz, gripper]`.
pub trait Policy: Send {
    /// Name used in results files and reports.
    fn name(&self) -> String;
    /// Called at the start of every episode (after the settle steps).
    fn reset(&mut self) -> Result<(), PolicyError> {
        Ok(())
    }
    /// The next action.
    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError>;
    /// The next action, given also what only the environment knows. The environment always
    /// calls this; the default forwards to [`Policy::act`], so the state stays invisible to
    /// every policy that does not ask for it.
    fn act_with_state(&mut self, obs: &Observation, state: &EpisodeState<'_>) -> Result<[f64; 7], PolicyError> {
        let _ = state;
        self.act(obs)
    }
    /// Whether the policy looks at the camera images. Scripted policies that do not let the
    /// environment skip rendering.
    fn uses_images(&self) -> bool {
        true
    }
    /// Whether the next [`Policy::act`] looks at the camera images. A policy that plays out an
    /// action chunk between requests does not, and the rollout then does not draw the cameras
    /// for that observation (its images stay the last drawn ones, which such a policy ignores).
    /// Defaults to [`Policy::uses_images`]; a policy that answers `false` and then reads the
    /// images gets stale ones.
    fn sees_images_next(&self) -> bool {
        self.uses_images()
    }
    /// True once the policy will send the same action at every remaining step of the episode
    /// (a reference policy with nothing left to do). The environment may then fast-forward a
    /// world at rest to the step budget.
    fn holding_still(&self) -> bool {
        false
    }
}
