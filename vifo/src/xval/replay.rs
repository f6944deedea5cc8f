//! Replaying a recording in the full scene and comparing motion.
//!
//! The scene is built from our task definition, fixtures are put where the recording's reset
//! put them (fixture placement is not part of LIBERO's state vector), and the recorded initial
//! state is loaded. Then the recorded actions are applied.
//!
//! MuJoCo logs end-effector poses 4 ms before the joint state of the same record (see the
//! reference README). To compare like with like, both end-effector poses are computed with our
//! kinematics (which matches MuJoCo's to micrometres) from the joint states at the end of each
//! control step: ours, and the recorded one. Objects are compared by root-body pose.
//!
//! Where a sequence amplifies small differences (a whirl near a singular pose, a stick-slip
//! contact), the free replay's error says little about the model. So a second replay restarts
//! every control step from MuJoCo's recorded arm state (joint positions and velocities; the
//! fingers' positions, at rest, as their velocities are not recorded) and reports how far one
//! step lands from MuJoCo's next record: the error of a single step, which does not accumulate.

use anyhow::{Context, Result, anyhow};
use serde::Serialize;
use vifo_robots::spatial::Coords;
use vifo_robots::panda::{self, Panda};
use vifo_robots::spatial::{Pose, angle_between};
use vifo_scenes::sim::{SceneModel, Sim};

use super::reference::{Record, Recording};


/// Arm error statistics over a set of records.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ErrorStats {
    pub eef_pos_max_m: f64,
    pub eef_pos_rms_m: f64,
    pub eef_rot_max_deg: f64,
    pub joint_max_rad: f64,
    pub finger_max_m: f64,
    /// Largest joint difference after one control step from MuJoCo's recorded state.
    pub step_joint_max_rad: f64,
    pub records: usize,
    #[serde(skip)]
    sum_sq: f64,
}

impl ErrorStats {
    fn add(&mut self, pos: f64, rot_deg: f64, joint: f64, finger: f64, step_joint: f64) {
        self.step_joint_max_rad = self.step_joint_max_rad.max(step_joint);
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
        self.step_joint_max_rad = self.step_joint_max_rad.max(other.step_joint_max_rad);
        self.sum_sq += other.sum_sq;
        self.records += other.records;
        self.eef_pos_rms_m = if self.records > 0 { (self.sum_sq / self.records as f64).sqrt() } else { 0.0 };
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct PhaseReport {
    pub phase: String,
    #[serde(flatten)]
    pub stats: ErrorStats,
}

/// One movable object's pose error at one check point.
#[derive(Clone, Debug, Serialize)]
pub struct ObjectError {
    pub object: String,
    pub at: &'static str,
    pub t: usize,
    pub pos_m: f64,
    pub rot_deg: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct TaskReport {
    pub file: String,
    pub suite: String,
    pub task_id: usize,
    pub task_name: String,
    pub phases: Vec<PhaseReport>,
    pub all: ErrorStats,
    pub objects: Vec<ObjectError>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    #[serde(flatten)]
    pub stats: ErrorStats,
    /// Largest and median object position error after settling (record 10).
    pub obj_settle_pos_max_m: f64,
    pub obj_settle_pos_median_m: f64,
    /// Largest object position and orientation error at the end of the recording.
    pub obj_end_pos_max_m: f64,
    pub obj_end_rot_max_deg: f64,
    pub tasks: usize,
}

/// The episode a recording starts from: our scene with the recording's fixture placement and
/// initial state.
pub fn start(rec: &Recording) -> Result<Sim> {
    let task = rec.task()?;
    let model = SceneModel::build(task)?;
    let mut sim = Sim::new(model.clone());
    for (name, body) in rec.steps[0].objects.iter().filter(|(_, b)| b.kind == "fixture") {
        if let Some((i, _)) = model.entity(name) {
            sim.place_fixture(i, &Pose::from_wxyz(body.pos, body.quat_wxyz));
        }
    }
    let state = model.layout.decode(&rec.meta.init_state_flat)?;
    sim.load_state(&state).context("loading the recorded initial state")?;
    Ok(sim)
}

/// The arm's and fingers' joint positions of a record.
fn recorded(record: &Record) -> Coords<9> {
    let mut q = Coords::<9>::zeros();
    q.fixed_rows_mut::<7>(0).copy_from_slice(&record.joint_qpos);
    q[7] = record.gripper_qpos[0];
    q[8] = record.gripper_qpos[1];
    q
}

fn grip_site(robot: &Panda, q: &Coords<9>) -> Pose {
    let dynamics = robot.arm().dynamics();
    let s = dynamics.model().site(panda::GRIP_SITE).expect("grip site");
    dynamics.frame_pose(&dynamics.forward(robot.arm().base(), q), s.body, &s.local)
}

fn object_errors(sim: &Sim, record: &Record, at: &'static str) -> Vec<ObjectError> {
    record
        .objects
        .iter()
        .filter(|(_, b)| b.kind == "object")
        .filter_map(|(name, body)| {
            let (i, _) = sim.model().entity(name)?;
            let ours = sim.entity_pose(i);
            let theirs = Pose::from_wxyz(body.pos, body.quat_wxyz);
            Some(ObjectError {
                object: name.clone(),
                at,
                t: record.t,
                pos_m: (ours.pos - theirs.pos).norm(),
                rot_deg: angle_between(&ours.rot, &theirs.rot).to_degrees(),
            })
        })
        .collect()
}

/// Replays one recording and compares every record.
pub fn replay(file: &str, rec: &Recording) -> Result<TaskReport> {
    let ranges = rec.phases();
    // A recording cut short would otherwise report all its phases as a perfect match (a phase
    // it does not reach prints as "no records"; the complete-asset set records 0 to 50).
    let last = rec.steps.len() - 1;
    let compares_any = rec.steps[1..].iter().any(|r| ranges.iter().any(|&(_, lo, hi)| (lo..=hi).contains(&r.t)));
    anyhow::ensure!(compares_any, "{file}: no record to compare (it stops at record {last}, before every phase)");
    let mut sim = start(rec)?;
    let mut one = start(rec)?;
    let panda = sim.model().robot.panda().cloned().ok_or_else(|| anyhow!("{file}: xval replays recordings of the Panda; this scene has another arm"))?;
    let mut phases: Vec<PhaseReport> = ranges.iter().map(|(phase, ..)| PhaseReport { phase: phase.clone(), stats: ErrorStats::default() }).collect();
    // Objects are compared after the first phase (settling) and at the end of the last.
    // "end" is the last record there is, where the phases run past it.
    let object_checks = [("settle", ranges.first().map_or(0, |p| p.2)), ("end", ranges.iter().map(|p| p.2).max().unwrap_or(0).min(last))];
    let mut objects = Vec::new();
    for (before, record) in rec.steps.iter().zip(&rec.steps[1..]) {
        let action = record.action().with_context(|| format!("record {}", record.t))?;
        sim.step(&action);
        // Record 0 is where both replays start.
        if before.t > 0 {
            panda.set_joints(one.world_mut(), &before.joint_qpos, &before.gripper_qpos, &before.joint_qvel, &[0.0; 2]);
        }
        one.step(&action);
        let theirs = recorded(record);
        let ours = panda.joints(sim.world()).q;
        let (a, b) = (grip_site(&panda, &ours), grip_site(&panda, &theirs));
        let joint = (0..7).map(|i| (ours[i] - theirs[i]).abs()).fold(0.0, f64::max);
        let finger = (7..9).map(|i| (ours[i] - theirs[i]).abs()).fold(0.0, f64::max);
        let stepped = panda.joints(one.world()).q;
        let step_joint = (0..7).map(|i| (stepped[i] - theirs[i]).abs()).fold(0.0, f64::max);
        if let Some(p) = ranges.iter().position(|&(_, lo, hi)| (lo..=hi).contains(&record.t)) {
            phases[p].stats.add((a.pos - b.pos).norm(), angle_between(&a.rot, &b.rot).to_degrees(), joint, finger, step_joint);
        }
        if let Some(&(at, _)) = object_checks.iter().find(|&&(_, t)| t == record.t) {
            objects.extend(object_errors(&sim, record, at));
        }
    }
    let mut all = ErrorStats::default();
    for p in &phases {
        all.merge(&p.stats);
    }
    Ok(TaskReport { file: file.to_string(), suite: rec.meta.suite.clone(), task_id: rec.meta.task_id, task_name: rec.meta.task_name.clone(), phases, all, objects })
}

/// Maxima, overall RMS and object statistics over every task and record.
pub fn summarize(tasks: &[TaskReport]) -> Summary {
    let mut stats = ErrorStats::default();
    for t in tasks {
        stats.merge(&t.all);
    }
    let mut settle: Vec<f64> = tasks.iter().flat_map(|t| &t.objects).filter(|o| o.at == "settle").map(|o| o.pos_m).collect();
    settle.sort_by(f64::total_cmp);
    let median = match settle.len() {
        0 => 0.0,
        n if n % 2 == 1 => settle[n / 2],
        n => 0.5 * (settle[n / 2 - 1] + settle[n / 2]),
    };
    let end = tasks.iter().flat_map(|t| &t.objects).filter(|o| o.at == "end");
    Summary {
        stats,
        obj_settle_pos_max_m: settle.last().copied().unwrap_or(0.0),
        obj_settle_pos_median_m: median,
        obj_end_pos_max_m: end.clone().map(|o| o.pos_m).fold(0.0, f64::max),
        obj_end_rot_max_deg: end.map(|o| o.rot_deg).fold(0.0, f64::max),
        tasks: tasks.len(),
    }
}
