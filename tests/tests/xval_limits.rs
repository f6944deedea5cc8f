//! The MuJoCo sequences that push the Panda into its joint limits, close the gripper on an object
//! while the arm moves and send far targets (`xval/record_limits.py`) replay in our scene, and
//! where MuJoCo holds a joint past its range ours holds it there too: MuJoCo's soft limit, which
//! gives a few milliradians under the OSC's push, not a stop at the range. The set lives outside
//! the repository (`VIFO_XVAL_LIMITS`, default `~/.cache/libero-vifo/xval-limits`); without it the
//! tests print why they skip. `vifo xval DIR` prints the end-effector figures.

use std::path::PathBuf;

use vifo::xval::{self, Recording};
use vifo_robots::panda::Panda;

fn limit_refs(test: &str) -> Option<PathBuf> {
    let how = "~/.cache/libero-vifo/orig-venv/bin/python xval/record_limits.py";
    vifo_tests::recorded("VIFO_XVAL_LIMITS", "xval-limits", how, test)
}

/// Also: one control step from MuJoCo's recorded arm state lands within 2 mrad of MuJoCo's next
/// record on every joint, contacts of the arm with itself included (measured largest 1.22 mrad,
/// on `j5_lo_j2_hi_j3_lo`; 2.6 mrad before the arm's contact shapes were MuJoCo's full hulls, with
/// the fingers' torsional friction and MuJoCo's soft dry friction). The free replay's figures are
/// `vifo xval`'s: where a sequence amplifies differences (`xval/sensitivity.py`), they say little
/// about one step. So the free replay's end effector is held within 1 mm of MuJoCo's only on the
/// sequences MuJoCo repeats: all but [`UNREPEATABLE`].
#[test]
fn every_limit_recording_replays_with_every_record_in_a_phase() {
    let Some(dir) = limit_refs("every_limit_recording_replays_with_every_record_in_a_phase") else { return };
    for path in xval::recordings_in(&dir).unwrap() {
        let rec = Recording::load(&path).unwrap();
        assert!(rec.meta.phases.is_some(), "{}: no phases", path.display());
        let report = xval::replay(&path.display().to_string(), &rec).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()));
        assert_eq!(report.all.records, rec.steps.len() - 1, "{}: records outside every phase", path.display());
        let step = report.all.step_joint_max_rad;
        let eef = report.all.eef_pos_max_m;
        println!("{}: end effector within {:.3} mm; one step from MuJoCo's state, largest joint difference {step:.2e} rad", path.display(), eef * 1e3);
        assert!(step <= 2e-3, "{}: one step from MuJoCo's recorded state is {step:.2e} rad off", path.display());
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        if !UNREPEATABLE.iter().any(|u| name.starts_with(&format!("{u}_"))) {
            assert!(eef <= 1e-3, "{}: end effector {:.3} mm from MuJoCo's", path.display(), eef * 1e3);
        }
    }
}

/// The sequences from which MuJoCo parts from its own run by 0.8 mm or more when the arm's start
/// is nudged by 1e-7 rad (the first three) or 1e-5 rad (`j5_hi_j2_hi`, 2.8 mm): a whirl near the
/// stretched arm, the hand sliding on link 5 (`xval/sensitivity.py`; ours differs from MuJoCo by
/// up to 1e-3 rad in one step there). Every other one MuJoCo repeats within 0.3 mm at 1e-5 rad.
const UNREPEATABLE: [&str; 4] = ["fast_j2_hi_j3_hi", "fast_j4_hi_j5_hi_j7_lo", "j5_lo_j2_hi_j3_lo", "j5_hi_j2_hi"];

/// While the arm still follows MuJoCo's (every joint within 1 mrad at the record before), each
/// joint MuJoCo holds past its range (past it at this record and the one before) is within
/// 0.5 mrad of MuJoCo's; a stop at the range would be off by the whole 1-9 mrad MuJoCo's joints
/// sink in. The record of the impact itself, where a joint arrives past its range at speed, is
/// printed, not asserted: there ours differs from MuJoCo by up to about 2 mrad on the fast
/// pushes (`fast_*`), an open gap of the limit model (see the limit sequences in docs/measurements.md).
#[test]
fn joints_held_past_their_limits_sink_in_as_far_as_in_mujoco() {
    let Some(dir) = limit_refs("joints_held_past_their_limits_sink_in_as_far_as_in_mujoco") else { return };
    let (mut held, mut worst) = (0usize, 0.0f64);
    let (mut impacts, mut worst_impact) = (0usize, 0.0f64);
    for path in xval::recordings_in(&dir).unwrap() {
        let rec = Recording::load(&path).unwrap();
        let mut sim = xval::start(&rec).unwrap();
        let panda: Panda = sim.model().robot.panda().cloned().unwrap();
        let ranges: Vec<[f64; 2]> = (0..7).map(|i| panda.arm().model().joint(i).range).collect();
        let mut following = true;
        let mut was_past = [false; 7];
        for record in &rec.steps[1..] {
            sim.step(&record.action().unwrap());
            let ours = panda.joints(sim.world()).q;
            let error = |i: usize| (ours[i] - record.joint_qpos[i]).abs();
            for (i, [lo, hi]) in ranges.iter().enumerate() {
                let past = (lo - record.joint_qpos[i]).max(record.joint_qpos[i] - hi);
                let impact = !was_past[i];
                was_past[i] = past > 2e-4;
                if following && past > 2e-4 && impact {
                    impacts += 1;
                    worst_impact = worst_impact.max(error(i));
                } else if following && past > 2e-4 {
                    held += 1;
                    worst = worst.max(error(i));
                    assert!(error(i) <= 5e-4, "{} record {}: joint {} {past:.2e} rad past its range in MuJoCo, ours off by {:.2e}", path.display(), record.t, i + 1, error(i));
                }
            }
            following = (0..7).all(|i| error(i) <= 1e-3);
        }
    }
    println!("{held} records of a joint held past its range while following MuJoCo; largest difference {worst:.2e} rad");
    println!("{impacts} impacts (a joint's first record past its range) while following MuJoCo; largest difference {worst_impact:.2e} rad");
    assert!(held > 0, "no record holds a joint past its range while following MuJoCo");
}
