//! The Panda replays LIBERO's MuJoCo recordings with the same motion (issue gates: end-effector
//! ≤ 5 mm max and ≤ 2 mm RMS, orientation ≤ 2°, fingers ≤ 2 mm).

use vifo::xval::{self, Recording};

#[test]
fn replays_match_mujoco_within_the_gates() {
    let Some(dir) = vifo_tests::shared("xval/libero_reference", "replays_match_mujoco_within_the_gates") else {
        return;
    };
    let mut reports = Vec::new();
    for path in xval::recordings_in(&dir).unwrap() {
        let rec = Recording::load(&path).unwrap();
        reports.push(xval::replay(&path.display().to_string(), &rec).unwrap());
    }
    assert_eq!(reports.len(), 4, "expected the four reference tasks");
    let s = xval::summarize(&reports).stats;
    println!("{s:?}");
    assert_eq!(s.records, 4 * 90);
    assert!(s.eef_pos_max_m <= 0.005, "eef max {} m", s.eef_pos_max_m);
    assert!(s.eef_pos_rms_m <= 0.002, "eef rms {} m", s.eef_pos_rms_m);
    assert!(s.eef_rot_max_deg <= 2.0, "rot max {}°", s.eef_rot_max_deg);
    assert!(s.finger_max_m <= 0.002, "finger max {} m", s.finger_max_m);
}

#[test]
fn malformed_recordings_are_refused_with_the_file_name() {
    let dir = std::env::temp_dir().join(format!("vifo-xval-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("broken_task0_init0.json");
    std::fs::write(&file, "{\"meta\": {\"suite\": \"x\"}, \"steps\": []}").unwrap();
    let err = Recording::load(&file).unwrap_err();
    assert!(format!("{err:#}").contains("broken_task0_init0.json"), "{err:#}");
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(xval::recordings_in(&dir).is_err());
}
