//! Reading the MuJoCo reference recordings (`<suite>_task0_init0.json`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use serde::Deserialize;
use vifo_robots::action::Action;
use vifo_scenes::sim::check_robot_joints;

/// One recording: the task it ran and one record per control step (t = 0 is the initial state).
#[derive(Debug, Deserialize)]
pub struct Recording {
    pub meta: Meta,
    pub steps: Vec<Record>,
}

#[derive(Debug, Deserialize)]
pub struct Meta {
    pub suite: String,
    pub task_id: usize,
    pub task_name: String,
    pub problem_class: String,
    /// `[time, qpos, qvel]` of the initial state, in LIBERO's layout.
    pub init_state_flat: Vec<f64>,
    /// `[name, first record, last record]` of each phase of the action sequence; absent in the
    /// reference set, whose one sequence has [`REFERENCE_PHASES`].
    #[serde(default)]
    pub phases: Option<Vec<(String, usize, usize)>>,
}

/// Phases of the reference action sequence (settle, phase-shifted sinusoids, close, open).
pub const REFERENCE_PHASES: [(&str, usize, usize); 4] = [("settle", 1, 10), ("sinusoid", 11, 50), ("close", 51, 70), ("open", 71, 90)];

/// Pose of an object's or fixture's root body.
#[derive(Debug, Deserialize)]
pub struct BodyPose {
    /// `object` (free joint) or `fixture`.
    pub kind: String,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
}

#[derive(Debug, Deserialize)]
pub struct Record {
    pub t: usize,
    pub action_applied_before: Option<Vec<f64>>,
    pub joint_qpos: [f64; 7],
    pub joint_qvel: [f64; 7],
    pub gripper_qpos: [f64; 2],
    pub objects: std::collections::BTreeMap<String, BodyPose>,
}

impl Record {
    /// The action that led to this record (validated); record 0 has none.
    pub fn action(&self) -> Result<Action> {
        let values = self.action_applied_before.as_deref().ok_or_else(|| anyhow!("record {} has no action_applied_before", self.t))?;
        Ok(Action::new(values)?)
    }
}

impl Recording {
    /// The phases records are reported by: the recording's own, or the reference sequence's.
    pub fn phases(&self) -> Vec<(String, usize, usize)> {
        self.meta.phases.clone().unwrap_or_else(|| REFERENCE_PHASES.iter().map(|&(n, lo, hi)| (n.to_string(), lo, hi)).collect())
    }

    /// The built-in task the recording ran (its suite, index and name must agree).
    pub fn task(&self) -> Result<&'static vifo_scenes::Task> {
        let (suite, index) = (&self.meta.suite, self.meta.task_id);
        let task = vifo_scenes::task(suite, index).ok_or_else(|| anyhow!("no built-in task {suite}[{index}]"))?;
        if task.name != self.meta.task_name {
            bail!("{suite}[{index}] is {}, but the recording is of {}", task.name, self.meta.task_name);
        }
        Ok(task)
    }

    pub fn load(path: &Path) -> Result<Recording> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let rec: Recording =
            serde_json::from_str(&text).with_context(|| format!("{}: not a LIBERO reference recording", path.display()))?;
        if rec.steps.is_empty() {
            bail!("{}: the recording has no steps", path.display());
        }
        for (name, lo, hi) in rec.meta.phases.iter().flatten() {
            if *lo < 1 || lo > hi {
                bail!("{}: phase {name} runs from record {lo} to {hi}; phases need 1 <= first <= last", path.display());
            }
        }
        rec.task().with_context(|| path.display().to_string())?;
        // Each record's joints are set on the one-step replay and drive the wrist camera's
        // projection: nonsense there (a joint far out of its range, a huge speed) would fling
        // the arm into NaN and the controller would panic.
        let panda = vifo_robots::panda::model(vifo_robots::panda::Mount::Ground);
        for (i, step) in rec.steps.iter().enumerate() {
            check_robot_joints(&panda, &step.joint_qpos, &step.gripper_qpos, &step.joint_qvel, &[0.0; 2])
                .with_context(|| format!("{}: record {i}", path.display()))?;
            if step.t != i {
                bail!("{}: record {i} has t = {}; records must be consecutive from t = 0", path.display(), step.t);
            }
            if i > 0 && step.action_applied_before.is_none() {
                bail!("{}: record {i} has no action_applied_before", path.display());
            }
            for (name, body) in &step.objects {
                let finite = body.pos.iter().chain(&body.quat_wxyz).all(|v| v.is_finite() && v.abs() < 1e3);
                if !finite || body.quat_wxyz == [0.0; 4] {
                    bail!("{}: record {i}: {name} has pos {:?} and quat_wxyz {:?}, not a pose in the arena", path.display(), body.pos, body.quat_wxyz);
                }
            }
        }
        Ok(rec)
    }
}

/// Every `*_init0.json` recording in `dir`, sorted by name.
pub fn recordings_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).with_context(|| format!("reading directory {}", dir.display()))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.ends_with("_init0.json")))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no *_init0.json recordings in {}", dir.display());
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A recording of `records` records of task `index` of `suite`, named `name`.
    fn recording(dir: &Path, suite: &str, index: usize, name: &str, records: usize) -> PathBuf {
        let steps: Vec<serde_json::Value> = (0..records)
            .map(|t| {
                let zeros = |n: usize| vec![0.0; n];
                serde_json::json!({"t": t, "action_applied_before": (t > 0).then(|| zeros(7)), "joint_qpos": zeros(7),
                    "joint_qvel": zeros(7), "gripper_qpos": zeros(2), "objects": {}})
            })
            .collect();
        let meta = serde_json::json!({"suite": suite, "task_id": index, "task_name": name, "problem_class": "x", "init_state_flat": []});
        let path = dir.join(format!("{suite}_task{index}_init0.json"));
        std::fs::write(&path, serde_json::json!({"meta": meta, "steps": steps}).to_string()).unwrap();
        path
    }

    #[test]
    fn a_recording_of_an_unknown_task_is_refused_with_its_file() {
        let dir = tempfile::tempdir().unwrap();
        let name = &vifo_scenes::task("libero_goal", 0).unwrap().name;
        assert!(Recording::load(&recording(dir.path(), "libero_goal", 0, name, 91)).is_ok());
        for (suite, index, task, says) in [("bogus", 0, name.as_str(), "no built-in task bogus[0]"), ("libero_goal", 0, "other", "but the recording is of other")] {
            let path = recording(dir.path(), suite, index, task, 91);
            let err = format!("{:#}", Recording::load(&path).unwrap_err());
            assert!(err.contains(&path.display().to_string()) && err.contains(says), "{err}");
        }
    }

    #[test]
    fn a_recording_without_a_record_in_any_phase_is_refused_not_read_as_a_perfect_match() {
        let dir = tempfile::tempdir().unwrap();
        let name = &vifo_scenes::task("libero_goal", 0).unwrap().name;
        let short = Recording::load(&recording(dir.path(), "libero_goal", 0, name, 1)).unwrap();
        let err = format!("{:#}", super::super::replay::replay("short.json", &short).unwrap_err());
        assert!(err.contains("short.json: no record to compare"), "{err}");
    }

    /// Joints far out of range or too fast (which made the replay's controller panic) and body
    /// poses outside the arena are refused, naming the file and record.
    #[test]
    fn a_record_that_no_arm_or_arena_could_be_in_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let name = &vifo_scenes::task("libero_goal", 0).unwrap().name;
        let path = recording(dir.path(), "libero_goal", 0, name, 3);
        let good: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let pose = serde_json::json!({"kind": "object", "pos": [0.0, 0.0, 1.0], "quat_wxyz": [1.0, 0.0, 0.0, 0.0]});
        let cases = [
            ("/steps/1/gripper_qpos", serde_json::json!([10.0, 10.0]), "record 1: state value 10 of robot joint"),
            ("/steps/2/joint_qpos", serde_json::json!([100.0, 0, 0, -1.0, 0, 1.0, 0]), "far outside its range"),
            ("/steps/1/joint_qvel", serde_json::json!([1e300, 0, 0, 0, 0, 0, 0]), "past the physics guard"),
            ("/steps/2/objects", serde_json::json!({"bowl": {"pos": [1e300, 0.0, 0.0], "quat_wxyz": [1.0, 0.0, 0.0, 0.0], "kind": "object"}}), "record 2: bowl has pos"),
            ("/steps/0/objects", serde_json::json!({"stove": {"pos": [0.0, 0.0, 1.0], "quat_wxyz": [0.0, 0.0, 0.0, 0.0], "kind": "fixture"}}), "not a pose in the arena"),
            ("/steps/0/objects", serde_json::json!({"bowl": pose}), ""),
        ];
        for (at, value, says) in cases {
            let mut spoilt = good.clone();
            *spoilt.pointer_mut(at).unwrap() = value;
            std::fs::write(&path, spoilt.to_string()).unwrap();
            match Recording::load(&path) {
                Ok(_) => assert!(says.is_empty(), "{at} was accepted"),
                Err(e) => {
                    let e = format!("{e:#}");
                    assert!(!says.is_empty() && e.contains(says) && e.contains(&path.display().to_string()), "{at}: {e}");
                }
            }
        }
    }
}
