//! LIBERO's 40 BDDL files parse, and each equals our built-in definition of that task.

use serde::Deserialize;
use vifo_scenes::bddl;

/// One entry of `libero/init_states_index.json`: an independent record of the task order.
#[derive(Deserialize)]
struct IndexEntry {
    suite: String,
    task_index: usize,
    task: String,
}

#[test]
fn bddl_files_equal_the_builtin_tasks() {
    let test = "bddl_files_equal_the_builtin_tasks";
    let (Some(index), Some(bddl_dir)) = (
        vifo_tests::shared("libero/init_states_index.json", test),
        vifo_tests::shared("libero/libero/libero/bddl_files", test),
    ) else {
        return;
    };
    let entries: Vec<IndexEntry> = serde_json::from_str(&std::fs::read_to_string(index).unwrap()).unwrap();
    assert_eq!(entries.len(), 40);
    for entry in &entries {
        let path = bddl_dir.join(&entry.suite).join(format!("{}.bddl", entry.task));
        let text = std::fs::read_to_string(&path).unwrap();
        let mut task = bddl::parse(&text, &path).unwrap_or_else(|e| panic!("{e}"));
        task.suite = Some(entry.suite.clone());
        task.index = Some(entry.task_index);
        let builtin = vifo_scenes::task(&entry.suite, entry.task_index)
            .unwrap_or_else(|| panic!("no built-in task {}[{}]", entry.suite, entry.task_index));
        assert_eq!(&task, builtin, "{}", path.display());
    }
    // And the built-in set has nothing the files lack.
    assert_eq!(vifo_scenes::all_tasks().count(), entries.len());
}

#[test]
fn every_suite_folder_holds_exactly_its_ten_tasks() {
    let test = "every_suite_folder_holds_exactly_its_ten_tasks";
    let Some(bddl_dir) = vifo_tests::shared("libero/libero/libero/bddl_files", test) else {
        return;
    };
    for suite in vifo_scenes::suites() {
        let mut on_disk: Vec<String> = std::fs::read_dir(bddl_dir.join(&suite.name))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "bddl"))
            .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
            .collect();
        on_disk.sort();
        let mut builtin: Vec<String> = suite.tasks.iter().map(|t| t.name.clone()).collect();
        builtin.sort();
        assert_eq!(on_disk, builtin, "{}", suite.name);
    }
}
