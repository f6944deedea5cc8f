//! §4.3's safety-critical scenes through environment, runner and the study's report: the rows
//! of the reference policies on the quick sample (two scenes, a text and a geometric cue), and
//! the same records with 1 or 2 threads.
//!
//! What a policy ignores cannot make it succeed, so the zero patterns are asserted outright.
//! The "high" ones are asserted as equal to the same expert doing the same task told by
//! language from the same initial state (the same plan from the same state is the same
//! trajectory), and non-zero, since `vifo expert --suite vifo_safety` shows it solving them.

use std::path::Path;

use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::policies::builtin;
use vifo_protocols::runner::{RunOptions, final_records, read_records};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec, Protocol};
use vifo_protocols::studies::safety::{self, SafetyRow};
use vifo_protocols::studies::{Study, StudyOptions};

fn sample() -> Vec<EpisodeSpec> {
    Study::Safety.episodes(&StudyOptions { set: vifo_cues::SetName::Paper, episodes: 1, quick: true }).unwrap()
}

fn run(policy: &str, specs: &[EpisodeSpec], path: &Path, threads: usize) -> Vec<EpisodeRecord> {
    let config = EnvConfig { size: 64, cameras: Vec::new(), ..EnvConfig::default() };
    let options = RunOptions { threads, quiet: true, policy: policy.into(), ..RunOptions::new(path) };
    let make = || builtin(policy).ok_or_else(|| format!("no policy {policy}"));
    run_episodes(specs, make, config, &RolloutOptions::default(), &options).unwrap();
    final_records(read_records(path).unwrap().records).into_values().collect()
}

/// The all-scenes, both-families row of one policy.
fn overall(records: &[EpisodeRecord]) -> SafetyRow {
    safety::build(records).rows.into_iter().find(|r| r.scene.is_none() && r.family.is_none()).unwrap()
}

fn rate(a: &vifo_protocols::vqa::Accuracy) -> (usize, usize) {
    (a.correct, a.total)
}

#[test]
fn reference_policies_give_their_expected_rows() {
    let specs = sample();
    assert_eq!(specs.iter().filter(|s| s.protocol == Protocol::Conflict).count(), 2);
    let dir = tempfile::tempdir().unwrap();
    let mut rows = std::collections::BTreeMap::new();
    for policy in ["expert-cue", "expert-language", "expert-authorized"] {
        let records = run(policy, &specs, &dir.path().join(format!("{policy}.jsonl")), 2);
        assert!(records.iter().all(|r| matches!(r.outcome, vifo_protocols::Outcome::Completed { .. })), "{policy}: {records:?}");
        rows.insert(policy, overall(&records));
    }
    let (cue, language, authorized) = (&rows["expert-cue"], &rows["expert-language"], &rows["expert-authorized"]);
    // Told by language, the expert does both tasks of both scenes.
    assert_eq!(rate(&language.safe_told), (2, 2));
    assert_eq!(rate(&language.hazard_told), (2, 2));
    // The cue follower carries out the hazardous task in both conditions and never the safe one.
    assert_eq!(rate(&cue.authorized_hazard), rate(&language.hazard_told));
    assert_eq!(rate(&cue.conflict_hazard), rate(&language.hazard_told));
    assert_eq!((cue.conflict_safe.correct, cue.safe_told.correct, cue.hazard_told.correct), (0, 0, 0));
    // The language follower never does what only the cue shows.
    assert_eq!((language.authorized_hazard.correct, language.conflict_hazard.correct), (0, 0));
    assert_eq!(rate(&language.conflict_safe), rate(&language.safe_told));
    // The authorized expert follows the authorized cue, and the language under conflict: its
    // hazard metric there is 0.
    assert_eq!(rate(&authorized.authorized_hazard), rate(&language.hazard_told));
    assert_eq!(rate(&authorized.conflict_hazard), (0, 2));
    assert_eq!(rate(&authorized.conflict_safe), rate(&language.safe_told));
    // Per scene and family rows exist and add up to the overall one.
    let report = safety::build(&run("expert-cue", &specs, &dir.path().join("again.jsonl"), 1));
    let per_scene: usize = report.rows.iter().filter(|r| r.scene.is_some() && r.family.is_none()).map(|r| r.episodes).sum();
    assert_eq!(per_scene, specs.len());
    assert!(report.markdown().contains("| expert-cue | F1 |") && report.csv().lines().count() > 3);
}

#[test]
fn one_or_two_threads_give_the_same_records() {
    let specs = sample();
    let dir = tempfile::tempdir().unwrap();
    let strip = |mut rs: Vec<EpisodeRecord>| {
        rs.iter_mut().for_each(|r| r.wall_ms = 0.0);
        rs
    };
    let one = strip(run("expert-authorized", &specs, &dir.path().join("one.jsonl"), 1));
    let two = strip(run("expert-authorized", &specs, &dir.path().join("two.jsonl"), 2));
    assert_eq!(one.len(), specs.len());
    assert_eq!(one, two);
}
