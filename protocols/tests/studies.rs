//! The objects study (§4.2) end to end: the same records on 1 and 2 threads, and the reference
//! policies' patterns on cue objects.

use std::path::Path;

use vifo_cues::SetName;
use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::policies::builtin;
use vifo_protocols::runner::{RunOptions, final_records, read_records};
use vifo_protocols::spec::{CueForm, EpisodeRecord, EpisodeSpec, Outcome, Protocol};
use vifo_protocols::studies::{Study, StudyOptions};
use vifo_scenes::view::CameraName;

fn run(policy: &str, specs: &[EpisodeSpec], path: &Path, threads: usize, render: bool) -> Vec<EpisodeRecord> {
    let cameras = if render { CameraName::ALL.to_vec() } else { Vec::new() };
    let config = EnvConfig { size: 64, cameras, ..EnvConfig::default() };
    let options = RunOptions { threads, quiet: true, policy: policy.into(), ..RunOptions::new(path) };
    let make = || builtin(policy).ok_or_else(|| format!("no policy {policy}"));
    // Drawn at every step, as for a policy that looks at every observation.
    let rollout = RolloutOptions { draw_every_step: render, ..RolloutOptions::default() };
    run_episodes(specs, make, config, &rollout, &options).unwrap();
    final_records(read_records(path).unwrap().records).into_values().collect()
}

/// Records without their wall time, as JSON lines.
fn comparable(records: &[EpisodeRecord]) -> Vec<String> {
    records.iter().map(|r| serde_json::to_string(&EpisodeRecord { wall_ms: 0.0, ..r.clone() }).unwrap()).collect()
}

fn quick_objects() -> Vec<EpisodeSpec> {
    let options = StudyOptions { set: SetName::Paper, episodes: 1, quick: true };
    Study::Objects.episodes(&options).unwrap().into_iter().filter(|s| s.cue_form == CueForm::Object).collect()
}

#[test]
fn the_objects_study_gives_the_same_records_on_one_and_two_threads() {
    let specs = quick_objects();
    assert_eq!(specs.len(), 6);
    let dir = tempfile::tempdir().unwrap();
    // The random policy moves the arm through the scene (and into the cue object), with both
    // cameras rendering the object.
    let one = run("random", &specs, &dir.path().join("one.jsonl"), 1, true);
    let two = run("random", &specs, &dir.path().join("two.jsonl"), 2, true);
    assert_eq!(one.len(), 6);
    assert!(one.iter().all(|r| matches!(r.outcome, Outcome::Completed { .. })), "{:?}", one.iter().map(|r| &r.outcome).collect::<Vec<_>>());
    assert_eq!(comparable(&one), comparable(&two));
}

#[test]
fn the_reference_policies_keep_their_patterns_with_cue_objects() {
    let dir = tempfile::tempdir().unwrap();
    for spec in quick_objects().into_iter().filter(|s| s.protocol == Protocol::NoLanguage) {
        let overlay = EpisodeSpec { cue_form: CueForm::Overlay, ..spec.clone() };
        let path = |name: &str| dir.path().join(format!("{name}-{}.jsonl", spec.seed));
        let success = |records: &[EpisodeRecord]| match records[0].outcome {
            Outcome::Completed { cue_success, .. } => cue_success,
            Outcome::Error { ref message } => panic!("{}: {message}", records[0].spec.key()),
        };
        // Without language the language-following expert has nothing to do: UVI 0 in both forms.
        let language = run("expert-language", std::slice::from_ref(&spec), &path("language"), 1, false);
        assert_eq!(success(&language), Some(false), "{}", spec.key());
        // The cue-following expert reads the cue task from the state; where it solves the task
        // with the overlay it must solve it with the object standing in the scene too.
        let with_overlay = run("expert-cue", std::slice::from_ref(&overlay), &path("overlay"), 1, false);
        if success(&with_overlay) == Some(true) {
            let with_object = run("expert-cue", std::slice::from_ref(&spec), &path("object"), 1, false);
            assert_eq!(success(&with_object), Some(true), "{}", spec.key());
        } else {
            println!("SKIPPED {}: the expert does not solve the overlay episode", spec.key());
        }
    }
}
