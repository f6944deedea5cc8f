//! Our file format for a suite's initial states (`scenes/init_states/<suite>.json`).
//!
//! ```text
//! {"format": "libero-vifo-init-states/1", "suite": "libero_10", "tasks": [
//! {"index": 0, "name": "...", "objects": ["alphabet_soup_1", ...],
//!  "joints": [["flat_stove_1", "button"], ...], "fixtures": ["flat_stove_1", ...], "states": [
//! {"arm": [7 joints], "gripper": [2 fingers], "objects": [[x, y, z, qw, qx, qy, qz], ...],
//!  "joints": [one value per named joint], "fixtures": [[x, y, z, qw, qx, qy, qz], ...]},
//! ...]}, ...]}
//! ```
//!
//! Names are given once per task; each state is one line of numbers in that order. Velocities
//! are zero and not stored. Numbers are rounded to [`DECIMALS`] places (a micrometre, a
//! micro-radian) so the files stay small and diff well; generation rounds before it validates, so
//! what is validated is what is stored.

use serde::Deserialize;

use super::{EpisodeStart, FixturePose};
use crate::init_file::{InitState, JointState, ObjectState};

/// The format tag of the files.
pub const FORMAT: &str = "libero-vifo-init-states/1";
/// Decimal places kept.
const DECIMALS: usize = 6;

/// A suite's states as stored.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteStates {
    pub suite: String,
    pub tasks: Vec<TaskStates>,
}

/// One task's states.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskStates {
    pub index: usize,
    pub name: String,
    pub starts: Vec<EpisodeStart>,
}

/// A file that is not a readable init-state file: which file, where, what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}: {problem}")]
pub struct FormatError {
    pub file: String,
    pub problem: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSuite {
    format: String,
    suite: String,
    tasks: Vec<RawTask>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTask {
    index: usize,
    name: String,
    objects: Vec<String>,
    joints: Vec<(String, String)>,
    fixtures: Vec<String>,
    states: Vec<RawState>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawState {
    arm: Vec<f64>,
    gripper: Vec<f64>,
    objects: Vec<Vec<f64>>,
    joints: Vec<f64>,
    fixtures: Vec<Vec<f64>>,
}

/// Reads a suite file; `file` names it in errors.
pub fn parse(text: &str, file: &str) -> Result<SuiteStates, FormatError> {
    let fail = |problem: String| FormatError { file: file.to_string(), problem };
    let raw: RawSuite = serde_json::from_str(text).map_err(|e| fail(e.to_string()))?;
    if raw.format != FORMAT {
        return Err(fail(format!("format is '{}', expected '{FORMAT}'", raw.format)));
    }
    let mut tasks: Vec<TaskStates> = Vec::with_capacity(raw.tasks.len());
    for t in raw.tasks {
        // Only the first would be read; a merged or hand-edited file is ambiguous.
        if tasks.iter().any(|seen| seen.index == t.index) {
            return Err(fail(format!("task {} ({}) is listed twice", t.index, t.name)));
        }
        let mut starts = Vec::with_capacity(t.states.len());
        for (k, s) in t.states.iter().enumerate() {
            let at = format!("task {} ({}) state {k}", t.index, t.name);
            starts.push(start_of(&t, s).map_err(|p| fail(format!("{at}: {p}")))?);
        }
        tasks.push(TaskStates { index: t.index, name: t.name, starts });
    }
    Ok(SuiteStates { suite: raw.suite, tasks })
}

fn numbers<const N: usize>(values: &[f64], what: &str, layout: &str) -> Result<[f64; N], String> {
    if let Some(v) = values.iter().find(|v| !v.is_finite()) {
        return Err(format!("{what} holds {v}"));
    }
    values.try_into().map_err(|_| format!("{what} has {} numbers, expected {N} ({layout})", values.len()))
}

fn counted<'a, T>(values: &'a [T], names: usize, what: &str) -> Result<&'a [T], String> {
    if values.len() == names {
        Ok(values)
    } else {
        Err(format!("{} {what}, but the task names {names}", values.len()))
    }
}

fn start_of(t: &RawTask, s: &RawState) -> Result<EpisodeStart, String> {
    const POSE: &str = "x y z qw qx qy qz";
    let mut objects = Vec::with_capacity(t.objects.len());
    for (name, v) in t.objects.iter().zip(counted(&s.objects, t.objects.len(), "object poses")?) {
        let p: [f64; 7] = numbers(v, &format!("object {name}"), POSE)?;
        objects.push(ObjectState { name: name.clone(), pos: [p[0], p[1], p[2]], quat_wxyz: [p[3], p[4], p[5], p[6]], lin_vel: [0.0; 3], ang_vel: [0.0; 3] });
    }
    let joints = t
        .joints
        .iter()
        .zip(counted(&s.joints, t.joints.len(), "joint values")?)
        .map(|((owner, joint), &qpos)| JointState { owner: owner.clone(), joint: joint.clone(), qpos, qvel: 0.0 })
        .collect();
    if let Some(v) = s.joints.iter().find(|v| !v.is_finite()) {
        return Err(format!("a joint value is {v}"));
    }
    let mut fixtures = Vec::with_capacity(t.fixtures.len());
    for (name, v) in t.fixtures.iter().zip(counted(&s.fixtures, t.fixtures.len(), "fixture poses")?) {
        let p: [f64; 7] = numbers(v, &format!("fixture {name}"), POSE)?;
        fixtures.push(FixturePose { name: name.clone(), pos: [p[0], p[1], p[2]], quat_wxyz: [p[3], p[4], p[5], p[6]] });
    }
    let state = InitState {
        time: 0.0,
        arm_qpos: numbers(&s.arm, "arm", "7 joint angles")?,
        arm_qvel: [0.0; 7],
        gripper_qpos: numbers(&s.gripper, "gripper", "2 finger positions")?,
        gripper_qvel: [0.0; 2],
        objects,
        joints,
    };
    Ok(EpisodeStart { state, fixtures })
}

/// The file text of a suite. Every state of a task must name the same objects, joints and
/// fixtures as its first (as [`sample`](super::sample) makes them).
pub fn write(suite: &SuiteStates) -> String {
    let mut out = format!("{{\"format\": {}, \"suite\": {}, \"tasks\": [\n", quoted(FORMAT), quoted(&suite.suite));
    for (i, t) in suite.tasks.iter().enumerate() {
        let first = t.starts.first();
        let objects: Vec<String> = first.map(|s| s.state.objects.iter().map(|o| quoted(&o.name)).collect()).unwrap_or_default();
        let joints: Vec<String> = first
            .map(|s| s.state.joints.iter().map(|j| format!("[{}, {}]", quoted(&j.owner), quoted(&j.joint))).collect())
            .unwrap_or_default();
        let fixtures: Vec<String> = first.map(|s| s.fixtures.iter().map(|f| quoted(&f.name)).collect()).unwrap_or_default();
        out += &format!(
            "{{\"index\": {}, \"name\": {}, \"objects\": [{}], \"joints\": [{}], \"fixtures\": [{}], \"states\": [\n",
            t.index,
            quoted(&t.name),
            objects.join(", "),
            joints.join(", "),
            fixtures.join(", ")
        );
        for (k, s) in t.starts.iter().enumerate() {
            let poses = |it: &mut dyn Iterator<Item = ([f64; 3], [f64; 4])>| -> String {
                it.map(|(p, q)| list(p.iter().chain(&q))).collect::<Vec<_>>().join(",")
            };
            out += &format!(
                "{{\"arm\":{},\"gripper\":{},\"objects\":[{}],\"joints\":{},\"fixtures\":[{}]}}{}\n",
                list(&s.state.arm_qpos),
                list(&s.state.gripper_qpos),
                poses(&mut s.state.objects.iter().map(|o| (o.pos, o.quat_wxyz))),
                list(s.state.joints.iter().map(|j| &j.qpos)),
                poses(&mut s.fixtures.iter().map(|f| (f.pos, f.quat_wxyz))),
                if k + 1 < t.starts.len() { "," } else { "" }
            );
        }
        out += if i + 1 < suite.tasks.len() { "]},\n" } else { "]}\n" };
    }
    out + "]}\n"
}

fn quoted(s: &str) -> String {
    serde_json::to_string(s).expect("strings always serialize")
}

fn list<'a>(values: impl IntoIterator<Item = &'a f64>) -> String {
    let items: Vec<String> = values.into_iter().map(|v| number(*v)).collect();
    format!("[{}]", items.join(","))
}

/// The shortest text that reads back as `v` (which [`round`] has already rounded).
fn number(v: f64) -> String {
    if v == 0.0 { "0".to_string() } else { v.to_string() }
}

/// `v` rounded to [`DECIMALS`] places (through decimal text, so the result is exactly what a
/// reader of the file gets back).
fn round(v: f64) -> f64 {
    let r: f64 = format!("{v:.DECIMALS$}").parse().expect("formatted floats parse");
    if r == 0.0 { 0.0 } else { r }
}

/// `start` with every number rounded as the file stores it.
pub(super) fn rounded(start: &EpisodeStart) -> EpisodeStart {
    let mut s = start.clone();
    let st = &mut s.state;
    for v in st.arm_qpos.iter_mut().chain(&mut st.gripper_qpos) {
        *v = round(*v);
    }
    for o in &mut st.objects {
        for v in o.pos.iter_mut().chain(&mut o.quat_wxyz) {
            *v = round(*v);
        }
    }
    for j in &mut st.joints {
        j.qpos = round(j.qpos);
    }
    for f in &mut s.fixtures {
        for v in f.pos.iter_mut().chain(&mut f.quat_wxyz) {
            *v = round(*v);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> EpisodeStart {
        EpisodeStart {
            state: InitState {
                time: 0.0,
                arm_qpos: [0.01, -0.16, 0.0, -2.44, 0.0, 2.22, 0.78],
                arm_qvel: [0.0; 7],
                gripper_qpos: [0.020833, -0.020833],
                gripper_qvel: [0.0; 2],
                objects: vec![ObjectState {
                    name: "cup_1".into(),
                    pos: [0.1234567891, -0.2, 0.9],
                    quat_wxyz: [0.6000000004, 0.0, -0.0, 0.7999999997],
                    lin_vel: [0.0; 3],
                    ang_vel: [0.0; 3],
                }],
                joints: vec![JointState { owner: "stove_1".into(), joint: "button".into(), qpos: 1.23456789, qvel: 0.0 }],
            },
            fixtures: vec![FixturePose { name: "stove_1".into(), pos: [-0.4, 0.2, 0.9], quat_wxyz: [1.0, 0.0, 0.0, 0.0] }],
        }
    }

    fn suite_of(starts: Vec<EpisodeStart>) -> SuiteStates {
        SuiteStates { suite: "s".into(), tasks: vec![TaskStates { index: 0, name: "t".into(), starts }] }
    }

    #[test]
    fn rounded_states_read_back_bit_for_bit() {
        let r = rounded(&start());
        assert_eq!(r.state.objects[0].pos[0], 0.123457);
        assert_eq!(r.state.joints[0].qpos, 1.234568);
        let suite = suite_of(vec![r.clone(), r]);
        let text = write(&suite);
        assert!(!text.contains("-0,") && text.lines().count() == 6, "{text}");
        assert_eq!(parse(&text, "s.json").unwrap(), suite);
    }

    #[test]
    fn wrong_lengths_and_names_are_reported_with_their_place() {
        let text = write(&suite_of(vec![rounded(&start())]));
        let short = text.replace("[0.123457,-0.2,0.9,", "[0.123457,-0.2,");
        let err = parse(&short, "s.json").unwrap_err().to_string();
        assert_eq!(err, "s.json: task 0 (t) state 0: object cup_1 has 6 numbers, expected 7 (x y z qw qx qy qz)");
        let extra = text.replace("\"objects\": [\"cup_1\"]", "\"objects\": [\"cup_1\", \"cup_2\"]");
        let err = parse(&extra, "s.json").unwrap_err().to_string();
        assert_eq!(err, "s.json: task 0 (t) state 0: 1 object poses, but the task names 2");
        let arm = text.replace("[0.01,-0.16,", "[-0.16,");
        assert!(parse(&arm, "s.json").unwrap_err().problem.contains("arm has 6 numbers, expected 7"));
        let broken = &text[..text.len() / 2];
        let err = parse(broken, "s.json").unwrap_err().to_string();
        assert!(err.starts_with("s.json: ") && err.contains("line"), "{err}");
        let other = text.replace(FORMAT, "something-else/2");
        assert!(parse(&other, "s.json").unwrap_err().problem.contains("expected 'libero-vifo-init-states/1'"));
        let mut twice = suite_of(vec![rounded(&start())]);
        twice.tasks.push(twice.tasks[0].clone());
        assert_eq!(parse(&write(&twice), "s.json").unwrap_err().to_string(), "s.json: task 0 (t) is listed twice");
    }

    #[test]
    fn never_panics_on_damaged_files() {
        let text = write(&suite_of(vec![rounded(&start())]));
        for cut in 0..text.len() {
            let _ = parse(&text[..cut], "cut");
        }
        for (i, _) in text.char_indices() {
            for replacement in ["9", "]", "\"", "-", "e999"] {
                let damaged = format!("{}{}{}", &text[..i], replacement, &text[i + 1..]);
                let _ = parse(&damaged, "flip");
            }
        }
    }
}
