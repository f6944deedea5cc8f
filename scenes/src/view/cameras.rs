//! The two cameras LIBERO's policies see through, as [`vifo_render::Camera`]s.
//!
//! - `agentview`: fixed in the world where the scene class puts it, fovy 45° (MuJoCo's default,
//!   which LIBERO never changes).
//! - `robot0_eye_in_hand`: robosuite's wrist camera, the Panda's `eye_in_hand` site on the hand
//!   body, fovy 75°. Its pose follows the arm's kinematics, so it can be computed from the
//!   simulation or from any joint vector (recorded states, planned futures). On the PiPER
//!   (§4.4 study) the wrist camera sits on the gripper's flange, 6 cm off the finger axis,
//!   looking along the fingers ([`PIPER_WRIST_CAMERA`]).

use std::fmt;
use std::str::FromStr;

use vifo_render::glam::{Mat3, Vec3};
use vifo_render::{Camera, Frame};
use vifo_robots::dynamics::BodyPoses;
use vifo_robots::panda::EYE_IN_HAND;
use vifo_robots::spatial::{self, Pose};

use crate::scene_class::SceneClass;
use crate::sim::{Robot, Sim};

/// robosuite's field of view of the wrist camera (degrees).
pub const EYE_IN_HAND_FOVY_DEG: f32 = 75.0;

/// The PiPER's wrist camera in its flange (`link6`) frame: 10 cm out along the approach axis
/// and 6 cm to the side of the fingers, looking along the fingers tilted 14° toward them (the
/// camera's x is the finger axis), as a wrist camera clamped to the gripper housing.
pub fn piper_wrist_camera() -> Pose {
    let (c, s) = (0.970_142_500_145_332, 0.242_535_625_036_333);
    let rot = spatial::Mat3::new(1.0, 0.0, 0.0, 0.0, -c, s, 0.0, -s, -c);
    Pose::new(spatial::Vec3::new(0.0, 0.06, 0.10), rot)
}

/// The PiPER's flange body, which carries the wrist camera.
const PIPER_FLANGE: usize = 6;

/// A camera by its LIBERO name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraName {
    AgentView,
    EyeInHand,
}

impl CameraName {
    pub const ALL: [CameraName; 2] = [CameraName::AgentView, CameraName::EyeInHand];

    /// The name LIBERO's observations use (`<name>_image`).
    pub fn as_str(self) -> &'static str {
        match self {
            CameraName::AgentView => "agentview",
            CameraName::EyeInHand => "robot0_eye_in_hand",
        }
    }
}

impl fmt::Display for CameraName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A camera name that is neither `agentview` nor `robot0_eye_in_hand`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown camera '{0}'; expected agentview or robot0_eye_in_hand")]
pub struct UnknownCamera(pub String);

impl FromStr for CameraName {
    type Err = UnknownCamera;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        CameraName::ALL.into_iter().find(|c| c.as_str() == s).ok_or_else(|| UnknownCamera(s.to_string()))
    }
}

/// Row order of delivered images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ImageOrder {
    /// Row 0 is the top of the picture (PNG files, the paper's pixel convention).
    #[default]
    Upright,
    /// Row 0 is the bottom (robosuite's OpenGL convention, what LIBERO's datasets store).
    BottomUp,
}

impl ImageOrder {
    /// Puts an upright frame (what the renderer produces) into this order.
    pub fn apply(self, frame: &mut Frame) {
        if self == ImageOrder::BottomUp {
            frame.flip_vertical();
        }
    }

    /// The row of upright row `v` in an image of `height` rows in this order.
    pub fn row(self, v: f32, height: u32) -> f32 {
        match self {
            ImageOrder::Upright => v,
            ImageOrder::BottomUp => (height as f32 - 1.0) - v,
        }
    }
}

/// A render camera at a world pose (MuJoCo convention: looks along local −z, +y up).
pub fn camera_at(pose: &Pose, fovy_deg: f32, width: u32, height: u32) -> Camera {
    let r = &pose.rot;
    let col = |c: usize| Vec3::new(r[(0, c)] as f32, r[(1, c)] as f32, r[(2, c)] as f32);
    let position = Vec3::new(pose.pos.x as f32, pose.pos.y as f32, pose.pos.z as f32);
    Camera::from_rotation(position, Mat3::from_cols(col(0), col(1), col(2)), fovy_deg, width, height)
}

/// Image size for both cameras, and the constructors for each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cameras {
    pub width: u32,
    pub height: u32,
}

impl Cameras {
    pub fn new(width: u32, height: u32) -> Cameras {
        Cameras { width, height }
    }

    /// The scene class's fixed `agentview` camera.
    pub fn agentview(&self, class: &SceneClass) -> Camera {
        let view = &class.agentview;
        let pose = Pose::from_wxyz(view.pose.pos, view.pose.quat_wxyz);
        camera_at(&pose, view.fovy_deg as f32, self.width, self.height)
    }

    /// The wrist camera for the arm's body poses (`poses` from the robot's forward kinematics).
    pub fn eye_in_hand_at(&self, robot: &Robot, poses: &BodyPoses) -> Camera {
        let pose = match robot {
            Robot::Panda(panda) => {
                let site = panda.arm().model().site(EYE_IN_HAND).expect("the Panda model has an eye_in_hand site");
                panda.arm().dynamics().frame_pose(poses, site.body, &site.local)
            }
            Robot::Piper(_) => poses.poses[PIPER_FLANGE].mul(&piper_wrist_camera()),
        };
        camera_at(&pose, EYE_IN_HAND_FOVY_DEG, self.width, self.height)
    }

    /// The wrist camera at the simulation's current joint state.
    pub fn eye_in_hand(&self, sim: &Sim) -> Camera {
        let robot = &sim.model().robot;
        self.eye_in_hand_at(robot, &robot.body_poses(sim.world()))
    }

    /// The named camera at the simulation's current state.
    pub fn get(&self, name: CameraName, sim: &Sim) -> Camera {
        match name {
            CameraName::AgentView => self.agentview(sim.model().class),
            CameraName::EyeInHand => self.eye_in_hand(sim),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_class::scene_class;
    use crate::task::ProblemClass;

    #[test]
    fn names_round_trip_and_bad_names_are_explained() {
        for c in CameraName::ALL {
            assert_eq!(c.as_str().parse::<CameraName>(), Ok(c));
        }
        let err = "frontview".parse::<CameraName>().unwrap_err();
        assert!(err.to_string().contains("frontview") && err.to_string().contains("agentview"), "{err}");
    }

    #[test]
    fn agentview_looks_down_at_the_table_from_the_front() {
        let class = scene_class(ProblemClass::Tabletop).unwrap();
        let cam = Cameras::new(256, 256).agentview(class);
        // LIBERO's research notes: view direction (−0.778, 0, −0.628).
        assert!((cam.forward() - Vec3::new(-0.778, 0.0, -0.628)).length() < 2e-3, "{}", cam.forward());
        assert_eq!(cam.fovy_deg, 45.0);
        // The table centre is in the lower middle of the image.
        let p = cam.project(Vec3::new(0.0, 0.0, 0.9)).unwrap();
        assert!((p.u - 127.5).abs() < 0.5 && p.v > 128.0 && p.v < 256.0, "{p:?}");
    }

    #[test]
    fn bottom_up_rows_mirror_upright_rows() {
        assert_eq!(ImageOrder::Upright.row(10.0, 256), 10.0);
        assert_eq!(ImageOrder::BottomUp.row(10.0, 256), 245.0);
        assert_eq!(ImageOrder::BottomUp.row(127.5, 256), 127.5);
    }
}
