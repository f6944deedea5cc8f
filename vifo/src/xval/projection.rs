//! `vifo xval <dir> --projection`: where our camera model puts recorded objects, against MuJoCo.
//!
//! For records 0 and 50 of each recording, every object's and fixture's RECORDED world position
//! is projected with our cameras: `agentview` from our scene class, the wrist camera from our
//! forward kinematics at the RECORDED joint state. MuJoCo's pixel for the same point is computed
//! independently, in `f64`, from `model_facts.json`:
//!
//! - `agentview`: the camera's compiled world pose (`world_pos_at_init`, `world_xmat_at_init`).
//!   This is the real check: our scene-class pose, quaternion conversion, intrinsics and pixel
//!   convention against MuJoCo's compiled camera.
//! - `robot0_eye_in_hand`: the hand pose from our kinematics of the recorded joints composed with
//!   the camera mount of `model_facts.json` (robosuite logs no hand pose at the state's instant).
//!   This checks our mount, field of view and camera maths, not the kinematics.
//!
//! Pixels follow the paper: `u` column, `v` row from the top of the upright image, pixel centres
//! at integers, `f = H / (2 tan(fovy/2))`, principal point `((W−1)/2, (H−1)/2)`. A MuJoCo camera
//! looks along its local −z with +y up.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Context, Result, anyhow};
use serde::{Deserialize, Serialize};
use vifo_robots::spatial::Coords;
use vifo_robots::panda::HAND_BODY;
use vifo_robots::spatial::{Mat3, Pose, Vec3};
use vifo_render::glam::Vec3 as RVec3;
use vifo_scenes::view::{CameraName, Cameras};

use super::images::{IMAGE_SIZE, IMAGE_STEPS};
use super::reference::{Record, Recording};
use super::replay::start;

/// A camera as `model_facts.json` describes it.
#[derive(Clone, Debug, Deserialize)]
pub struct CameraFacts {
    pub pos_in_parent: [f64; 3],
    pub quat_in_parent_wxyz: [f64; 4],
    pub fovy_deg: f64,
    pub world_pos_at_init: [f64; 3],
    /// Row-major camera-to-world rotation.
    pub world_xmat_at_init: [f64; 9],
}

#[derive(Clone, Debug, Deserialize)]
struct SceneFacts {
    problem_class: String,
    cameras: BTreeMap<String, CameraFacts>,
}

/// The parts of `model_facts.json` the projection check reads.
#[derive(Clone, Debug, Deserialize)]
pub struct ModelFacts {
    scenes: BTreeMap<String, SceneFacts>,
}

impl ModelFacts {
    pub fn load(path: &Path) -> Result<ModelFacts> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| format!("{}: not a model_facts.json with scenes and cameras", path.display()))
    }

    /// A camera of the scene of `problem_class` (matched case-insensitively, as LIBERO does).
    pub fn camera(&self, problem_class: &str, camera: &str) -> Result<&CameraFacts> {
        let scene = self
            .scenes
            .values()
            .find(|s| s.problem_class.eq_ignore_ascii_case(problem_class))
            .ok_or_else(|| anyhow!("model facts have no scene for problem class {problem_class}"))?;
        let facts = scene.cameras.get(camera).ok_or_else(|| anyhow!("model facts of {problem_class} have no camera {camera}"))?;
        facts.check().with_context(|| format!("model facts of {problem_class}, camera {camera}"))?;
        Ok(facts)
    }
}

impl CameraFacts {
    /// A camera the comparison can trust: a field of view in (0°, 180°), finite values, a
    /// non-zero mount quaternion and a rotation matrix that is one (a zero matrix or a zero
    /// field of view would put every point at the principal point and read as a perfect match).
    fn check(&self) -> Result<()> {
        let values = self.pos_in_parent.iter().chain(&self.quat_in_parent_wxyz).chain(&self.world_pos_at_init).chain(&self.world_xmat_at_init);
        anyhow::ensure!(values.chain([&self.fovy_deg]).all(|v| v.is_finite()), "a value is not finite");
        anyhow::ensure!(self.fovy_deg > 0.0 && self.fovy_deg < 180.0, "fovy_deg {} is not in (0, 180)", self.fovy_deg);
        let q = self.quat_in_parent_wxyz;
        anyhow::ensure!(q.iter().map(|v| v * v).sum::<f64>() > 1e-12, "quat_in_parent_wxyz {q:?} is zero, not a rotation");
        let m = row_major(&self.world_xmat_at_init);
        let off = (m.transpose() * m - Mat3::identity()).abs().max();
        anyhow::ensure!(off < 1e-6 && m.determinant() > 0.0, "world_xmat_at_init {:?} is not a rotation matrix", self.world_xmat_at_init);
        Ok(())
    }
}

/// MuJoCo's pixel of world point `p` for a camera at `pos` with row-major rotation `xmat`
/// (`None` behind the camera).
pub fn mujoco_pixel(pos: &Vec3, rot: &Mat3, fovy_deg: f64, width: u32, height: u32, p: &Vec3) -> Option<[f64; 2]> {
    // Camera frame: x right, y up, looking along −z.
    let c = rot.transpose() * (p - pos);
    let depth = -c.z;
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    let f = height as f64 / (2.0 * libm::tan(fovy_deg.to_radians() / 2.0));
    let u = (width as f64 - 1.0) / 2.0 + f * c.x / depth;
    let v = (height as f64 - 1.0) / 2.0 - f * c.y / depth;
    Some([u, v])
}

fn row_major(m: &[f64; 9]) -> Mat3 {
    Mat3::new(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8])
}

/// One record's pixels: per camera, per object, ours (`None` behind the camera).
#[derive(Clone, Debug, Serialize)]
pub struct StepProjection {
    pub t: usize,
    pub cameras: BTreeMap<&'static str, BTreeMap<String, Option<[f64; 2]>>>,
}

#[derive(Clone, Debug, Serialize)]
pub struct FileProjection {
    pub file: String,
    pub steps: Vec<StepProjection>,
}

/// Largest distance between our pixel and MuJoCo's, over points inside the image.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ProjectionSummary {
    /// Over both cameras.
    pub projection_max_px: f64,
    /// The independent check: our agentview pose and camera model against MuJoCo's compiled camera.
    pub agentview_max_px: f64,
    /// Wrist camera (same kinematics on both sides; checks the mount and camera maths).
    pub eye_in_hand_max_px: f64,
    /// Points compared (inside the image for MuJoCo's camera).
    pub points: usize,
}

impl ProjectionSummary {
    fn add(&mut self, camera: CameraName, error: f64) {
        let slot = match camera {
            CameraName::AgentView => &mut self.agentview_max_px,
            CameraName::EyeInHand => &mut self.eye_in_hand_max_px,
        };
        *slot = slot.max(error);
        self.projection_max_px = self.projection_max_px.max(error);
        self.points += 1;
    }
}

fn recorded_joints(record: &Record) -> Coords<9> {
    let mut q = Coords::<9>::zeros();
    q.fixed_rows_mut::<7>(0).copy_from_slice(&record.joint_qpos);
    q[7] = record.gripper_qpos[0];
    q[8] = record.gripper_qpos[1];
    q
}

/// Projects every recorded object at [`IMAGE_STEPS`] with both cameras; adds the differences to
/// MuJoCo's pixels into `summary`.
pub fn project(file: &str, rec: &Recording, facts: &ModelFacts, summary: &mut ProjectionSummary) -> Result<FileProjection> {
    let sim = start(rec)?;
    let model = sim.model();
    let robot = &model.robot;
    let panda = robot.panda().ok_or_else(|| anyhow!("{file}: xval projects recordings of the Panda; this scene has another arm"))?;
    let hand = panda.arm().model().body_index(HAND_BODY).expect("the Panda has a hand body");
    let cameras = Cameras::new(IMAGE_SIZE, IMAGE_SIZE);
    let agent = facts.camera(&rec.meta.problem_class, CameraName::AgentView.as_str())?;
    let wrist = facts.camera(&rec.meta.problem_class, CameraName::EyeInHand.as_str())?;
    let mut steps = Vec::new();
    for &t in &IMAGE_STEPS {
        let record = rec.steps.get(t).ok_or_else(|| anyhow!("{file}: no record {t}"))?;
        let poses = panda.arm().dynamics().forward(panda.arm().base(), &recorded_joints(record));
        let mount = Pose::from_wxyz(wrist.pos_in_parent, wrist.quat_in_parent_wxyz);
        let wrist_pose = poses.poses[hand].mul(&mount);
        let views = [
            (CameraName::AgentView, cameras.agentview(model.class), Vec3::from(agent.world_pos_at_init), row_major(&agent.world_xmat_at_init), agent.fovy_deg),
            (CameraName::EyeInHand, cameras.eye_in_hand_at(robot, &poses), wrist_pose.pos, wrist_pose.rot, wrist.fovy_deg),
        ];
        let mut by_camera = BTreeMap::new();
        for (name, ours, pos, rot, fovy) in views {
            let mut pixels = BTreeMap::new();
            for (object, body) in &record.objects {
                let p = Vec3::from(body.pos);
                let mine = ours.project(RVec3::new(p.x as f32, p.y as f32, p.z as f32)).map(|q| [q.u as f64, q.v as f64]);
                let theirs = mujoco_pixel(&pos, &rot, fovy, IMAGE_SIZE, IMAGE_SIZE, &p);
                if let (Some(a), Some(b)) = (mine, theirs)
                    && ours.contains(b[0] as f32, b[1] as f32)
                {
                    summary.add(name, ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt());
                }
                pixels.insert(object.clone(), mine);
            }
            by_camera.insert(name.as_str(), pixels);
        }
        steps.push(StepProjection { t, cameras: by_camera });
    }
    Ok(FileProjection { file: file.to_string(), steps })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_facts_that_are_no_camera_are_refused() {
        let good = CameraFacts {
            pos_in_parent: [0.0; 3],
            quat_in_parent_wxyz: [1.0, 0.0, 0.0, 0.0],
            fovy_deg: 45.0,
            world_pos_at_init: [1.0, 0.0, 1.5],
            world_xmat_at_init: [0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        };
        assert!(good.check().is_ok());
        type Spoil = fn(&mut CameraFacts);
        let broken: [(&str, Spoil); 5] = [
            ("fovy_deg 0", |c| c.fovy_deg = 0.0),
            ("not finite", |c| c.world_pos_at_init[0] = f64::NAN),
            ("is zero", |c| c.quat_in_parent_wxyz = [0.0; 4]),
            ("not a rotation matrix", |c| c.world_xmat_at_init = [0.0; 9]),
            ("not a rotation matrix", |c| c.world_xmat_at_init[0] = 2.0),
        ];
        for (says, spoil) in broken {
            let mut c = good.clone();
            spoil(&mut c);
            let e = c.check().unwrap_err().to_string();
            assert!(e.contains(says), "{says}: {e}");
        }
    }

    #[test]
    fn mujoco_pixel_follows_the_camera_conventions() {
        // A camera at the origin looking along world +x (its −z), up = world +z.
        let rot = Mat3::new(0.0, 0.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let centre = mujoco_pixel(&Vec3::zeros(), &rot, 90.0, 101, 51, &Vec3::new(2.0, 0.0, 0.0)).unwrap();
        assert_eq!(centre, [50.0, 25.0]);
        // 45° up is the top edge (v = c_y − f = −0.5); world −y is to the right.
        let top = mujoco_pixel(&Vec3::zeros(), &rot, 90.0, 101, 51, &Vec3::new(1.0, 0.0, 1.0)).unwrap();
        assert!((top[1] + 0.5).abs() < 1e-12, "{top:?}");
        let right = mujoco_pixel(&Vec3::zeros(), &rot, 90.0, 101, 51, &Vec3::new(1.0, -0.1, 0.0)).unwrap();
        assert!(right[0] > 50.0);
        assert!(mujoco_pixel(&Vec3::zeros(), &rot, 90.0, 101, 51, &Vec3::new(-1.0, 0.0, 0.0)).is_none());
    }
}
