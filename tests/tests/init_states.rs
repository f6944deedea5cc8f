//! LIBERO's 40 original `.pruned_init` files import in pure Rust, agree with their CSV copies to
//! the last bit, and fit the state layouts of the built-in tasks.

use serde::Deserialize;
use vifo_scenes::init_file::{self, StateLayout};

#[derive(Deserialize)]
struct IndexEntry {
    suite: String,
    task_index: usize,
    source: String,
    csv: String,
    rows: usize,
    cols: usize,
    nq: usize,
    nv: usize,
}

fn index(test: &str) -> Option<(std::path::PathBuf, Vec<IndexEntry>)> {
    let libero = vifo_tests::shared("libero", test)?;
    let text = std::fs::read_to_string(libero.join("init_states_index.json")).unwrap();
    Some((libero, serde_json::from_str(&text).unwrap()))
}

/// The CSV copy: a header naming every column, then one row per state (Python `repr` floats).
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_string).collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn pruned_init_files_match_their_csv_copies_and_the_task_layouts() {
    let Some((libero, entries)) = index("pruned_init_files_match_their_csv_copies_and_the_task_layouts") else {
        return;
    };
    assert_eq!(entries.len(), 40);
    for entry in &entries {
        let task = vifo_scenes::task(&entry.suite, entry.task_index).unwrap();
        let states = init_file::load(&libero.join(&entry.source)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((states.rows(), states.cols()), (entry.rows, entry.cols), "{}", entry.source);
        assert_eq!(states.rows(), 50);

        let (header, csv_rows) = read_csv(&libero.join(&entry.csv));
        assert_eq!(csv_rows.len(), states.rows(), "{}", entry.csv);
        for (ours, theirs) in states.iter().zip(&csv_rows) {
            let ours: Vec<u64> = ours.iter().map(|v| v.to_bits()).collect();
            let theirs: Vec<u64> = theirs.iter().map(|v| v.to_bits()).collect();
            assert_eq!(ours, theirs, "{}", entry.source);
        }

        let layout = StateLayout::for_task(task);
        assert_eq!((layout.row_len(), layout.nq(), layout.nv()), (entry.cols, entry.nq, entry.nv), "{}", task.label());
        assert_eq!(layout.column_names(), header, "{}", task.label());
        for row in states.iter() {
            let state = layout.decode(row).unwrap();
            assert_eq!(state.objects.len(), task.objects.len());
            assert_eq!(state.time, 0.0);
        }
    }
}

#[test]
fn a_state_from_another_task_is_refused() {
    let Some((libero, entries)) = index("a_state_from_another_task_is_refused") else {
        return;
    };
    let spatial = entries.iter().find(|e| e.suite == "libero_spatial").unwrap();
    let states = init_file::load(&libero.join(&spatial.source)).unwrap();
    let goal_task = vifo_scenes::task("libero_goal", 0).unwrap();
    let err = StateLayout::for_task(goal_task).decode(states.row(0).unwrap()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "state vector has 92 values, task open_the_middle_drawer_of_the_cabinet expects 79 = 1 + nq 41 + nv 37"
    );
}

#[test]
fn drawer_and_door_values_lie_in_libero_sampling_ranges() {
    let Some((libero, entries)) = index("drawer_and_door_values_lie_in_libero_sampling_ranges") else {
        return;
    };
    // libero_spatial task 4 starts with the top drawer open (U[-0.16, -0.14]); libero_10 task 9
    // with the microwave open (U[-2.094, -1.3]).
    for (suite, index, joint, lo, hi) in
        [("libero_spatial", 4, "top_level", -0.16, -0.14), ("libero_10", 9, "microjoint", -2.094, -1.3)]
    {
        let entry = entries.iter().find(|e| e.suite == suite && e.task_index == index).unwrap();
        let layout = StateLayout::for_task(vifo_scenes::task(suite, index).unwrap());
        for row in init_file::load(&libero.join(&entry.source)).unwrap().iter() {
            let state = layout.decode(row).unwrap();
            let value = state.joints.iter().find(|j| j.joint == joint).unwrap().qpos;
            assert!((lo..=hi).contains(&value), "{suite}[{index}] {joint} = {value}");
        }
    }
}
