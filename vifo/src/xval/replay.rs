//! Replaying a recording and comparing joint-level motion.
//!
//! MuJoCo logs end-effector poses 4 ms before the joint state of the same record (see the
//! reference README). To compare like with like, both end-effector poses are computed with our
//! kinematics (which matches MuJoCo's to micrometres) from the joint states at the end of each
//! control step: ours, and the recorded one.

use anyhow::{Context, Result};
use serde::Serialize;
use vifo_physics::{SimParams, World};
use vifo_robots::action::Action;
use vifo_robots::dynamics::Coords;
use vifo_robots::panda::{self, Mount, Panda};
use vifo_robots::spatial::{Pose, angle_between};
use vifo_scenes::scene_class::scene_class;
use vifo_scenes::task::ProblemClass;

use super::reference::Recording;

/// Phases of the reference action sequence, by record index range (inclusive).
pub const PHASES: [(&str, usize, usize); 4] = [("settle", 1, 10), ("sinusoid", 11, 50), ("close", 51, 70), ("open", 71, 90)];

/// Error statistics over a set of records.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ErrorStats {
    pub eef_pos_max_m: f64,
    pub eef_pos_rms_m: f64,
    pub eef_rot_max_deg: f64,
    pub joint_max_rad: f64,
    pub finger_max_m: f64,
    pub records: usize,
    #[serde(skip)]
    sum_sq: f64,
}

impl ErrorStats {
    fn add(&mut self, pos: f64, rot_deg: f64, joint: f64, finger: f64) {
        self.eef_pos_max_m = self.eef_pos_max_m.max(pos);
        self.eef_rot_max_deg = self.eef_rot_max_deg.max(rot_deg);
        self.joint_max_rad = self.joint_max_rad.max(joint);
        self.finger_max_m = self.finger_max_m.max(finger);
        self.sum_sq += pos * pos;
        self.records += 1;
        self.eef_pos_rms_m = (self.sum_sq / self.records as f64).sqrt();
    }

    fn merge(&mut self, other: &ErrorStats) {
        self.eef_pos_max_m = self.eef_pos_max_m.max(other.eef_pos_max_m);
        self.eef_rot_max_deg = self.eef_rot_max_deg.max(other.eef_rot_max_deg);
        self.joint_max_rad = self.joint_max_rad.max(other.joint_max_rad);
        self.finger_max_m = self.finger_max_m.max(other.finger_max_m);
        self.sum_sq += other.sum_sq;
        self.records += other.records;
        self.eef_pos_rms_m = if self.records > 0 { (self.sum_sq / self.records as f64).sqrt() } else { 0.0 };
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct PhaseReport {
    pub phase: &'static str,
    #[serde(flatten)]
    pub stats: ErrorStats,
}

#[derive(Clone, Debug, Serialize)]
pub struct TaskReport {
    pub file: String,
    pub suite: String,
    pub task_id: usize,
    pub task_name: String,
    pub phases: Vec<PhaseReport>,
    pub all: ErrorStats,
}

#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    #[serde(flatten)]
    pub stats: ErrorStats,
    pub tasks: usize,
}

/// The robot mount and base pose of a recording's scene class.
fn robot_placement(problem_class: &str) -> Result<(Mount, Pose)> {
    let class = ProblemClass::from_name(problem_class)
        .and_then(scene_class)
        .with_context(|| format!("problem class {problem_class} is not one of the LIBERO-VIFO scene classes"))?;
    let mount = if class.robot_on_mount { Mount::Pedestal } else { Mount::Ground };
    Ok((mount, Pose::from_wxyz(class.robot_base.pos, class.robot_base.quat_wxyz)))
}

/// Replays one recording in free space (no objects) and compares every record.
pub fn replay(file: &str, rec: &Recording) -> Result<TaskReport> {
    let (mount, base) = robot_placement(&rec.meta.problem_class)?;
    let mut world = World::new(SimParams::LIBERO);
    let robot = Panda::insert(&mut world, mount, base);
    let first = &rec.steps[0];
    robot.set_joints(&mut world, &first.joint_qpos, &first.gripper_qpos, &first.joint_qvel, &[0.0; 2]);
    let mut control = robot.reset_control();

    let site = |q: &Coords<9>| -> Pose {
        let dynamics = robot.arm().dynamics();
        let s = dynamics.model().site(panda::GRIP_SITE).expect("grip site");
        dynamics.frame_pose(&dynamics.forward(robot.arm().base(), q), s.body, &s.local)
    };
    let mut phases: Vec<PhaseReport> = PHASES.iter().map(|&(phase, ..)| PhaseReport { phase, stats: ErrorStats::default() }).collect();
    for record in &rec.steps[1..] {
        let action = Action::new(record.action_applied_before.as_deref().unwrap_or(&[]))?;
        robot.control_step(&mut world, &mut control, &action);
        let ours = robot.joints(&world).q;
        let mut theirs = Coords::<9>::zeros();
        theirs.fixed_rows_mut::<7>(0).copy_from_slice(&record.joint_qpos);
        theirs[7] = record.gripper_qpos[0];
        theirs[8] = record.gripper_qpos[1];
        let (a, b) = (site(&ours), site(&theirs));
        let joint = (0..7).map(|i| (ours[i] - theirs[i]).abs()).fold(0.0, f64::max);
        let finger = (7..9).map(|i| (ours[i] - theirs[i]).abs()).fold(0.0, f64::max);
        if let Some(p) = PHASES.iter().position(|&(_, lo, hi)| (lo..=hi).contains(&record.t)) {
            phases[p].stats.add((a.pos - b.pos).norm(), angle_between(&a.rot, &b.rot).to_degrees(), joint, finger);
        }
    }
    let mut all = ErrorStats::default();
    for p in &phases {
        all.merge(&p.stats);
    }
    Ok(TaskReport { file: file.to_string(), suite: rec.meta.suite.clone(), task_id: rec.meta.task_id, task_name: rec.meta.task_name.clone(), phases, all })
}

/// Maxima and overall RMS over every task and record.
pub fn summarize(tasks: &[TaskReport]) -> Summary {
    let mut stats = ErrorStats::default();
    for t in tasks {
        stats.merge(&t.all);
    }
    Summary { stats, tasks: tasks.len() }
}

