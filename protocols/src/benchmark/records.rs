//! The records of this benchmark's results files, checked: a record whose spec is not the
//! one `vifo run` makes for its episode (an edited instance, seed or initial state), or whose
//! outcome cannot be, is refused with its file and line instead of counting in a table.

use std::path::Path;

use super::BenchmarkError;
use crate::runner::{Loaded, RunError, read_records};
use crate::spec::{EpisodeRecord, EpisodeSpec, Outcome};
use crate::studies::piper;

/// The spec `vifo run` makes for `spec`'s episode (task, protocol, instance, initial state,
/// repetition and cue form): the main benchmark's and the objects and safety studies' from the
/// instance library, the PiPER study's from its own conditions.
pub fn expected_spec(spec: &EpisodeSpec) -> Result<EpisodeSpec, BenchmarkError> {
    let made = if spec.task.suite == piper::SUITE {
        piper::spec(spec.protocol, spec.init, spec.episode)?
    } else {
        super::specs::spec(&spec.task, spec.protocol, spec.instance.as_deref(), spec.init, spec.episode)?
    };
    Ok(EpisodeSpec { cue_form: spec.cue_form, ..made })
}

/// Whether `record` is one a run of this benchmark writes: its spec is the one
/// [`expected_spec`] makes (an edited instance, seed, task or initial state would put the
/// episode in another family's column, or in none while it still counted), and it took no more steps
/// than the suite's budget.
pub fn check_record(record: &EpisodeRecord) -> Result<(), String> {
    let spec = &record.spec;
    check_spec(spec)?;
    if let Outcome::Completed { steps, .. } = record.outcome
        && steps > spec.step_budget()
    {
        return Err(format!("episode {} is not one this benchmark runs: {steps} steps, past the suite's budget of {}", spec.key(), spec.step_budget()));
    }
    Ok(())
}

/// Whether `spec` is the one [`expected_spec`] makes for its episode (what a driver that
/// runs specs it was given checks before running them).
pub fn check_spec(spec: &EpisodeSpec) -> Result<(), String> {
    let not_ours = |why: String| Err(format!("episode {} is not one this benchmark runs: {why}", spec.key()));
    let init_states = super::specs::INIT_STATES;
    if spec.init >= init_states {
        return not_ours(format!("initial state {} (the tasks have {init_states})", spec.init));
    }
    let expected = match expected_spec(spec) {
        Ok(expected) => expected,
        Err(e) => return not_ours(e.to_string()),
    };
    match differing_field(spec, &expected) {
        Some(field) => not_ours(format!("its {field} differs from the one vifo makes for it")),
        None => Ok(()),
    }
}

/// The first field in which `a` and `b` differ.
fn differing_field(a: &EpisodeSpec, b: &EpisodeSpec) -> Option<&'static str> {
    [
        ("instance", a.instance != b.instance),
        ("instruction", a.instruction != b.instruction),
        ("language task", a.language_task != b.language_task),
        ("cue task", a.cue_task != b.cue_task),
        ("seed", a.seed != b.seed),
        ("spec", a != b),
    ]
    .into_iter()
    .find_map(|(name, differs)| differs.then_some(name))
}

/// Reads a results file of this benchmark ([`read_records`]) and refuses it, naming the file
/// and line, where a record is not one it runs ([`check_record`]): what reports and resumed
/// runs read.
pub fn read_checked(path: &Path) -> Result<Loaded, RunError> {
    let loaded = read_records(path)?;
    for (record, &line) in loaded.records.iter().zip(&loaded.lines) {
        check_record(record).map_err(|message| RunError::BadLine { path: path.to_path_buf(), line, message })?;
    }
    Ok(loaded)
}

#[cfg(test)]
mod tests {
    use vifo_cues::SetName;

    use super::*;
    use crate::spec::{CueForm, Protocol, RESULTS_VERSION, TaskRef};

    fn record(spec: EpisodeSpec) -> EpisodeRecord {
        let outcome = Outcome::Completed {
            language_success: spec.language_task.as_ref().map(|_| true),
            cue_success: spec.cue_task.as_ref().map(|_| false),
            steps: 90,
        };
        EpisodeRecord { version: RESULTS_VERSION, spec, policy: "p".into(), outcome, wall_ms: 1.0, set: SetName::Paper, look: String::new() }
    }

    fn authorized() -> EpisodeSpec {
        let task = TaskRef { suite: "libero_goal".into(), index: 0 };
        super::super::specs::spec(&task, Protocol::Authorized, Some("libero_goal/0/F1/caption_bar"), 3, 0).unwrap()
    }

    #[test]
    fn the_records_a_run_writes_pass() {
        let specs = super::super::specs::specs(&super::super::specs::Selection::quick()).unwrap();
        let piper = crate::studies::piper::episodes(2, 1).unwrap();
        let object = EpisodeSpec { cue_form: CueForm::Object, ..authorized() };
        for spec in specs.into_iter().chain(piper).chain([object]) {
            check_record(&record(spec.clone())).unwrap_or_else(|e| panic!("{}: {e}", spec.key()));
        }
    }

    /// Each edit once counted in a table: in another family's column, in none while still
    /// counted among the episodes, or as a real episode of a task or state that does not exist.
    #[test]
    fn an_edited_record_is_refused_saying_what_is_wrong() {
        type Edit = fn(&mut EpisodeRecord);
        let edits: [(&str, Edit); 7] = [
            ("unknown cue instance 'x'", |r| r.spec.instance = Some("x".into())),
            ("its instance differs", |r| {
                r.spec.protocol = Protocol::Original;
                r.outcome = Outcome::Completed { language_success: Some(true), cue_success: None, steps: 5 };
            }),
            ("unknown task bogus/0", |r| r.spec.task.suite = "bogus".into()),
            ("instance libero_goal/0/F1/caption_bar belongs to task libero_goal/0, not to libero_goal/9", |r| r.spec.task.index = 9),
            ("initial state 1000000000000000000 (the tasks have 50)", |r| r.spec.init = 1_000_000_000_000_000_000),
            ("its seed differs", |r| r.spec.seed ^= 1),
            ("past the suite's budget of 300", |r| r.outcome = Outcome::Completed { language_success: None, cue_success: Some(true), steps: usize::MAX }),
        ];
        let good = record(authorized());
        check_record(&good).unwrap();
        for (says, edit) in edits {
            let mut r = good.clone();
            edit(&mut r);
            let e = check_record(&r).unwrap_err();
            assert!(e.contains("is not one this benchmark runs") && e.contains(says), "{says}: {e}");
        }
    }

    #[test]
    fn a_results_file_with_an_edited_record_is_refused_naming_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("results-p.jsonl");
        let good = record(authorized());
        let mut bad = good.clone();
        bad.spec.seed ^= 1;
        let lines: Vec<String> = [&good, &good, &bad].iter().map(|r| serde_json::to_string(r).unwrap()).collect();
        std::fs::write(&path, format!("{}\n\n{}\n{}\n", lines[0], lines[1], lines[2])).unwrap();
        let e = read_checked(&path).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}:4: episode libero_goal/0|authorized", path.display())) && e.contains("seed"), "{e}");
        std::fs::write(&path, format!("{}\n", lines[0])).unwrap();
        assert_eq!(read_checked(&path).unwrap().records, vec![good]);
    }
}
