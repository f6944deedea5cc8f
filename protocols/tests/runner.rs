//! The runner: thread-count independence, resume after a stop (with a cut-off last line),
//! sharding, and error handling.

use std::path::{Path, PathBuf};

use vifo_cues::SetName;
use vifo_protocols::runner::{self, ErrorTally, RunError, RunOptions, Shard, final_records, read_records, seed_for};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec, Outcome, Protocol, RESULTS_VERSION, TaskRef};

fn specs(n: usize) -> Vec<EpisodeSpec> {
    (0..n)
        .map(|i| {
            let protocol = Protocol::ALL[i % 4];
            let task = TaskRef { suite: "libero_goal".into(), index: i % 10 };
            let instance = protocol.uses_cue().then(|| format!("{task}/F2/straight_arrow_red"));
            let mut spec = EpisodeSpec {
                task: task.clone(),
                protocol,
                instance,
                init: i / 4,
                episode: 0,
                instruction: String::new(),
                language_task: Some(task.clone()),
                cue_task: protocol.uses_cue().then_some(task),
                seed: 0,
                cue_form: Default::default(),
            };
            spec.seed = seed_for(&spec);
            spec
        })
        .collect()
}

/// A deterministic "episode": the outcome depends only on the spec.
fn episode(spec: &EpisodeSpec) -> EpisodeRecord {
    let steps = (spec.seed % 300) as usize;
    EpisodeRecord {
        version: RESULTS_VERSION,
        spec: spec.clone(),
        policy: "scripted".into(),
        outcome: Outcome::Completed {
            language_success: Some(spec.seed.is_multiple_of(3)),
            cue_success: spec.protocol.uses_cue().then_some(spec.seed.is_multiple_of(5)),
            steps,
        },
        wall_ms: 0.0,
        set: SetName::Paper,
        look: String::new(),
    }
}

/// A results file in a scratch folder that is removed when the returned guard drops.
fn temp() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("results.jsonl");
    (dir, path)
}

fn options(path: &Path, threads: usize) -> RunOptions {
    RunOptions { threads, quiet: true, policy: "scripted".into(), ..RunOptions::new(path) }
}

/// The file's records sorted by key, with the informational wall time removed.
fn sorted(path: &Path) -> Vec<String> {
    let mut lines: Vec<String> = read_records(path)
        .unwrap()
        .records
        .into_iter()
        .map(|r| serde_json::to_string(&EpisodeRecord { wall_ms: 0.0, ..r }).unwrap())
        .collect();
    lines.sort();
    lines
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let all = specs(40);
    let (_one_dir, one) = temp();
    let (_two_dir, two) = temp();
    let s1 = runner::run(&all, episode, &options(&one, 1)).unwrap();
    let s2 = runner::run(&all, episode, &options(&two, 2)).unwrap();
    assert_eq!((s1.ran, s2.ran, s1.errors), (40, 40, 0));
    assert_eq!(sorted(&one), sorted(&two));
    // Every line is a complete record and the runner filled in the wall time.
    let text = std::fs::read_to_string(&two).unwrap();
    assert_eq!(text.lines().count(), 40);
    assert!(text.ends_with('\n'));
}

#[test]
fn a_stopped_run_resumes_to_the_same_result() {
    let all = specs(30);
    let (_reference_dir, reference) = temp();
    runner::run(&all, episode, &options(&reference, 2)).unwrap();

    // First attempt: stops after 12 episodes, two of them errors, while writing a 13th line.
    let (_path_dir, path) = temp();
    let flaky = |spec: &EpisodeSpec| {
        if spec.init == 1 {
            EpisodeRecord { outcome: Outcome::Error { message: "server dropped".into() }, ..episode(spec) }
        } else {
            episode(spec)
        }
    };
    let first = runner::run(&all[..12], flaky, &options(&path, 2)).unwrap();
    assert_eq!(first.errors, 4);
    let mut cut = serde_json::to_string(&episode(&all[20])).unwrap();
    cut.truncate(cut.len() / 2);
    std::fs::OpenOptions::new().append(true).open(&path).unwrap().write_all(cut.as_bytes()).unwrap();
    let loaded = read_records(&path).unwrap();
    assert_eq!((loaded.records.len(), loaded.truncated_tail), (12, cut.len()));

    // Without resume the file is protected.
    assert!(matches!(runner::run(&all, episode, &options(&path, 2)), Err(RunError::Exists(_))));

    let second = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 2) }).unwrap();
    assert_eq!((second.already_done, second.ran, second.truncated_tail), (8, 22, cut.len()));
    // The errors stay in the file as history, the completed retries win.
    let loaded = read_records(&path).unwrap();
    assert_eq!((loaded.records.len(), loaded.truncated_tail), (34, 0));
    let settled: Vec<String> = final_records(loaded.records)
        .into_values()
        .map(|r| serde_json::to_string(&EpisodeRecord { wall_ms: 0.0, ..r }).unwrap())
        .collect();
    assert_eq!(settled, sorted(&reference));

    // Nothing left to do.
    let third = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) }).unwrap();
    assert_eq!((third.already_done, third.ran), (30, 0));
}

use std::io::Write;

/// A last record that lost only its newline (an editor's save) is a record, kept on resume,
/// and the next record starts on a line of its own.
#[test]
fn a_last_record_without_its_newline_is_kept() {
    let all = specs(6);
    let (_dir, path) = temp();
    runner::run(&all[..3], episode, &options(&path, 1)).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.trim_end()).unwrap();
    let loaded = read_records(&path).unwrap();
    assert_eq!((loaded.records.len(), loaded.truncated_tail), (3, 0));

    let resumed = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) }).unwrap();
    assert_eq!((resumed.already_done, resumed.ran, resumed.truncated_tail), (3, 3, 0));
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!((text.lines().count(), read_records(&path).unwrap().records.len()), (6, 6));
    assert!(text.ends_with('\n'));
}

#[test]
fn shards_partition_the_specs() {
    let all = specs(60);
    let mut seen = Vec::new();
    for i in 0..3 {
        let (_path_dir, path) = temp();
        let shard: Shard = format!("{i}/3").parse().unwrap();
        let s = runner::run(&all, episode, &RunOptions { shard: Some(shard), ..options(&path, 2) }).unwrap();
        assert!(s.ran > 5, "shard {i} got only {} of 60", s.ran);
        seen.extend(read_records(&path).unwrap().records.into_iter().map(|r| r.spec.key()));
    }
    seen.sort();
    let mut keys: Vec<String> = all.iter().map(|s| s.key()).collect();
    keys.sort();
    assert_eq!(seen, keys);
    for bad in ["3/3", "1", "a/2", "0/0", "-1/2"] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

#[test]
fn panics_and_foreign_records_become_errors() {
    let all = specs(8);
    let (_path_dir, path) = temp();
    let s = runner::run(
        &all,
        |spec: &EpisodeSpec| match spec.init {
            0 => panic!("simulated crash"),
            1 => episode(&all[7]),
            _ => episode(spec),
        },
        &options(&path, 2),
    )
    .unwrap();
    // Specs 0-3 panic; 4-6 return spec 7's record (7 itself is right).
    assert_eq!((s.ran, s.errors), (8, 7));
    let records = read_records(&path).unwrap().records;
    let messages: Vec<String> = records
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Error { message } => Some(message.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(messages.iter().filter(|m| m.contains("simulated crash")).count(), 4);
    assert_eq!(messages.iter().filter(|m| m.contains("instead")).count(), 3);
    assert!(records.iter().all(|r| r.policy == "scripted"));
    // Nothing of those was drawn: they go with any look (an empty look, the built-in one,
    // made a report of a run drawn with LIBERO's refuse it as mixed).
    let errors = records.iter().filter(|r| matches!(r.outcome, Outcome::Error { .. }));
    assert!(errors.clone().count() == 7 && errors.into_iter().all(|r| r.look == vifo_protocols::report::NO_IMAGES));
    // The summary gathers the distinct messages, most frequent first.
    let instead = format!("episode function returned a record for {} instead", all[7].key());
    // Each names its first episode in key order, whatever the threads' order.
    let first = |init: usize| all.iter().filter(|s| s.init == init && s.key() != all[7].key()).map(|s| s.key()).min().unwrap();
    let tally = |count, message: &str, first| ErrorTally { count, message: message.to_string(), first };
    assert_eq!(
        s.error_messages,
        vec![tally(4, "episode panicked: simulated crash", first(0)), tally(3, &instead, first(1))]
    );
}

#[test]
fn a_corrupt_middle_line_is_reported_with_its_position() {
    let (_path_dir, path) = temp();
    runner::run(&specs(3), episode, &options(&path, 1)).unwrap();
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.insert_str(text.find('\n').unwrap() + 1, "{\"spec\": 3}\n");
    std::fs::write(&path, text).unwrap();
    let err = read_records(&path).unwrap_err().to_string();
    assert!(err.contains("results.jsonl:2:") && err.contains("episode record"), "{err}");
}

#[test]
fn an_unwritable_output_is_a_clear_error_before_any_episode_runs() {
    let (dir, _) = temp();
    // A plain file where the output folder should be: no user (not even root) can write there.
    let blocker = dir.path().join("not-a-folder");
    std::fs::write(&blocker, "x").unwrap();
    let path = blocker.join("results.jsonl");
    let ran = std::sync::atomic::AtomicUsize::new(0);
    let counting = |spec: &EpisodeSpec| {
        ran.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        episode(spec)
    };
    match runner::run(&specs(4), counting, &options(&path, 1)) {
        Err(e @ RunError::Io { .. }) => {
            assert_eq!(e.to_string(), format!("{}: a file, where the output needs a folder", blocker.display()))
        }
        other => panic!("expected an I/O error naming the folder, got {other:?}"),
    }
    assert_eq!(ran.into_inner(), 0);
    // The same for a folder under the file, and a folder that can be made is made.
    let deeper = runner::create_folder(&blocker.join("a/b")).unwrap_err().to_string();
    assert_eq!(deeper, format!("{}: a file, where the output needs a folder", blocker.display()));
    let fresh = dir.path().join("a/b");
    runner::create_folder(&fresh).unwrap();
    assert!(fresh.is_dir());
    // Reports and charts name the file too (they said "File exists"), and a device as well.
    let report = runner::create_dir(&blocker).unwrap_err().to_string();
    assert_eq!(report, format!("{} is a file, where the output needs a folder", blocker.display()));
    let device = runner::create_dir(Path::new("/dev/null/report")).unwrap_err().to_string();
    assert!(device.starts_with("/dev/null is a file"), "{device}");
    // A device is no results file (and would be read forever).
    assert!(matches!(read_records(Path::new("/dev/zero")), Err(RunError::Io { .. })));
}

/// The lock file beside a results file.
fn lock_file(path: &Path) -> PathBuf {
    path.with_extension("jsonl.lock")
}

#[test]
fn a_second_run_on_the_same_file_is_refused_while_the_first_holds_the_lock() {
    let all = specs(6);
    let (_dir, path) = temp();
    let held = runner::RunLock::take(&path).unwrap();
    assert!(lock_file(&path).is_file());
    let err = runner::run(&all, episode, &options(&path, 1)).unwrap_err();
    assert!(matches!(err, RunError::Locked { .. }), "{err:?}");
    assert!(err.to_string().contains("another run is writing"), "{err}");
    assert!(!path.exists() || read_records(&path).unwrap().records.is_empty());
    // The refused run leaves the holder's lock file alone.
    assert!(lock_file(&path).is_file());
    drop(held);
    assert!(!lock_file(&path).exists());
    // The next run proceeds, and leaves no lock file beside its results; nor does one that
    // stops with an error after taking the lock.
    assert_eq!(runner::run(&all, episode, &options(&path, 1)).unwrap().ran, 6);
    assert!(!lock_file(&path).exists());
    let err = runner::run(&all, episode, &options(&path, 1)).unwrap_err();
    assert!(matches!(err, RunError::Exists(_)), "{err:?}");
    assert!(!lock_file(&path).exists());
}

/// A killed run leaves its (empty) lock file, but the operating system has dropped its lock:
/// the next run takes the file over and removes it at its end.
#[test]
fn a_lock_file_left_by_a_killed_run_is_taken_over() {
    let (_dir, path) = temp();
    std::fs::write(lock_file(&path), "").unwrap();
    assert_eq!(runner::run(&specs(6), episode, &options(&path, 1)).unwrap().ran, 6);
    assert!(!lock_file(&path).exists());
}

/// Runs taking and dropping the lock on one file side by side: removing the file at the end
/// of a run must never let two hold it at once (one that locked a file just removed retries).
#[test]
fn the_lock_excludes_runs_that_start_as_another_ends() {
    use std::sync::atomic::{AtomicUsize, Ordering};

    let (_dir, path) = temp();
    let (holders, taken) = (AtomicUsize::new(0), AtomicUsize::new(0));
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| {
                for _ in 0..5000 {
                    match runner::RunLock::take(&path) {
                        Ok(lock) => {
                            assert_eq!(holders.fetch_add(1, Ordering::SeqCst), 0, "two runs hold the lock");
                            std::thread::yield_now();
                            holders.fetch_sub(1, Ordering::SeqCst);
                            taken.fetch_add(1, Ordering::Relaxed);
                            drop(lock);
                        }
                        Err(RunError::Locked { .. }) => std::thread::yield_now(),
                        Err(e) => panic!("{e}"),
                    }
                }
            });
        }
    });
    assert!(taken.into_inner() > 0);
    assert!(!lock_file(&path).exists());
}

#[test]
fn results_of_another_version_are_refused_and_kept() {
    let all = specs(6);
    let (_dir, path) = temp();
    runner::run(&all[..3], episode, &options(&path, 1)).unwrap();
    // The same records as an older benchmark (before records carried a version) wrote them.
    let old: String = std::fs::read_to_string(&path).unwrap().replace("\"version\":1,", "");
    assert!(!old.contains("version"));
    std::fs::write(&path, &old).unwrap();
    assert!(read_records(&path).unwrap().records.iter().all(|r| r.version == 0));
    let err = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) }).unwrap_err();
    assert!(matches!(err, RunError::OtherVersion { found: 0, expected: 1, .. }), "{err:?}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), old);
}

/// `/dev/full` fails every write as a full disk does.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_stops_the_writer_without_a_partial_line() {
    let mut writer = runner::ResultsWriter::append(Path::new("/dev/full"), 0).unwrap();
    let record = episode(&specs(1)[0]);
    let first = writer.write(&record).unwrap_err().to_string();
    assert!(first.contains("/dev/full") && first.to_lowercase().contains("no space"), "{first}");
    let second = writer.write(&record).unwrap_err().to_string();
    assert!(second.contains("an earlier write failed"), "{second}");
}

/// A file of one policy renamed to another's is not resumed under the other's name: its
/// completed episodes would be skipped as done and reported as the first policy's.
#[test]
fn a_file_of_another_policy_is_not_resumed() {
    let all = specs(8);
    let (_dir, path) = temp();
    runner::run(&all[..4], episode, &options(&path, 1)).unwrap();
    let before = std::fs::read(&path).unwrap();
    let other = runner::run(&all, episode, &RunOptions { resume: true, policy: "zero".into(), ..options(&path, 1) });
    match other {
        Err(RunError::OtherPolicy { found, wanted, .. }) => assert_eq!((found.as_str(), wanted.as_str()), ("scripted", "zero")),
        other => panic!("expected OtherPolicy, got {other:?}"),
    }
    assert_eq!(std::fs::read(&path).unwrap(), before, "the refused run wrote nothing");
    // Its own name resumes it; so does a driver that gives no name (it checks nothing).
    let summary = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) }).unwrap();
    assert_eq!((summary.already_done, summary.ran), (4, 4));
    runner::run(&all, episode, &RunOptions { resume: true, policy: String::new(), ..options(&path, 1) }).unwrap();
}

#[test]
fn records_carry_the_set_and_a_file_of_another_set_is_not_resumed() {
    let all = specs(8);
    let (_dir, path) = temp();
    runner::run(&all[..4], episode, &RunOptions { set: SetName::Full, ..options(&path, 1) }).unwrap();
    assert!(read_records(&path).unwrap().records.iter().all(|r| r.set == SetName::Full));
    let other = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) });
    assert!(matches!(other, Err(RunError::OtherSet { found: SetName::Full, wanted: SetName::Paper, .. })));
    // A line written before sets existed reads as the full set.
    let mut line = serde_json::to_value(episode(&all[0])).unwrap();
    line.as_object_mut().unwrap().remove("set");
    let old: EpisodeRecord = serde_json::from_value(line).unwrap();
    assert_eq!(old.set, SetName::Full);
}

#[test]
fn built_in_look_records_have_no_look_field_asset_looks_round_trip() {
    let spec = specs(1).remove(0);
    let plain = episode(&spec);
    let line = serde_json::to_string(&plain).unwrap();
    assert!(!line.contains("\"look\""), "{line}");
    assert_eq!(serde_json::from_str::<EpisodeRecord>(&line).unwrap(), plain);
    let looked = EpisodeRecord { look: "libero-assets:0123456789abcdef".into(), ..plain };
    let line = serde_json::to_string(&looked).unwrap();
    assert!(line.contains("\"look\":\"libero-assets:0123456789abcdef\""), "{line}");
    assert_eq!(serde_json::from_str::<EpisodeRecord>(&line).unwrap(), looked);
}

#[test]
fn the_suites_with_the_longest_step_budget_run_first_in_list_order() {
    // libero_10 (520 steps) and libero_spatial (220) alternate in the list.
    let all: Vec<EpisodeSpec> = specs(12)
        .into_iter()
        .enumerate()
        .map(|(i, mut s)| {
            s.task.suite = if i % 2 == 0 { "libero_spatial" } else { "libero_10" }.into();
            s.seed = seed_for(&s);
            s
        })
        .collect();
    let started = std::sync::Mutex::new(Vec::new());
    let (_dir, path) = temp();
    runner::run(
        &all,
        |spec| {
            started.lock().unwrap().push(spec.key());
            episode(spec)
        },
        &options(&path, 1),
    )
    .unwrap();
    let long_first: Vec<String> = all.iter().filter(|s| s.task.suite == "libero_10").chain(all.iter().filter(|s| s.task.suite == "libero_spatial")).map(|s| s.key()).collect();
    assert_eq!(started.into_inner().unwrap(), long_first);
}

/// `stop` set by a driver (a Ctrl-C that Python saw) ends the run after the episodes running:
/// the rest are neither run nor written, and a resumed run does them.
#[test]
fn a_stop_takes_no_more_episodes_and_a_resume_does_the_rest() {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};

    let all = specs(20);
    let (_dir, path) = temp();
    let stop = Arc::new(AtomicBool::new(false));
    let stopping = |spec: &EpisodeSpec| {
        stop.store(true, Ordering::Relaxed);
        episode(spec)
    };
    let first = runner::run(&all, stopping, &RunOptions { stop: Some(stop.clone()), ..options(&path, 1) }).unwrap();
    assert_eq!(first.ran, 1);
    assert_eq!(read_records(&path).unwrap().records.len(), 1);
    assert!(!lock_file(&path).exists());
    let rest = runner::run(&all, episode, &RunOptions { resume: true, ..options(&path, 1) }).unwrap();
    assert_eq!((rest.ran, rest.already_done), (19, 1));
}

#[test]
fn results_file_names_keep_only_safe_ascii_and_are_recognized() {
    use vifo_protocols::runner::results::{file_name, is_file_name};
    assert_eq!(file_name("ws://h:8000"), "results-ws___h_8000.jsonl");
    assert_eq!(file_name("pi05 goal/1"), "results-pi05_goal_1.jsonl");
    // Non-ASCII letters too: Python's `str.isalnum` would have kept them.
    assert_eq!(file_name("modèle-v1.2"), "results-mod_le-v1.2.jsonl");
    assert!(is_file_name(&file_name("zero")));
    assert!(!is_file_name("results-zero.jsonl.lock") && !is_file_name("predictions-zero.jsonl"));
}
