//! §4.4's PiPER study through environment, runner and the study's table: the rows of the
//! reference policies on the first three initial states of both conditions (cameras off).
//!
//! What a policy ignores cannot make it stack or move, so the zero patterns are asserted
//! outright; the experts' stacking is asserted on states `vifo expert --suite vifo_piper`
//! shows them solving.

use std::path::Path;

use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::policies::builtin;
use vifo_protocols::runner::{RunOptions, final_records, read_records};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec, Outcome};
use vifo_protocols::studies::{self, piper::{self, Row}};

const STATES: usize = 3;

fn run(policy: &str, specs: &[EpisodeSpec], path: &Path) -> Vec<EpisodeRecord> {
    let config = EnvConfig { size: 64, cameras: Vec::new(), ..EnvConfig::default() };
    let options = RunOptions { threads: 2, quiet: true, policy: policy.into(), ..RunOptions::new(path) };
    let make = || builtin(policy).ok_or_else(|| format!("no policy {policy}"));
    run_episodes(specs, make, config, &RolloutOptions::default(), &options).unwrap();
    final_records(read_records(path).unwrap().records).into_values().collect()
}

fn row(policy: &str, dir: &Path) -> Row {
    let specs = piper::episodes(STATES, 1).unwrap();
    let records = run(policy, &specs, &dir.join(format!("{policy}.jsonl")));
    assert!(records.iter().all(|r| matches!(r.outcome, Outcome::Completed { .. })), "{policy}: {records:?}");
    let rows = piper::table(&records);
    assert_eq!(rows.len(), 1);
    let row = rows.into_iter().next().unwrap();
    assert_eq!((row.authorized_n, row.conflict_n, row.errors), (STATES, STATES, 0), "{policy}");
    row
}

#[test]
fn reference_policies_give_their_expected_rows() {
    let dir = tempfile::tempdir().unwrap();
    let all = Some(100.0);
    let none = Some(0.0);
    // The cue follower stacks as the authorized note says, and under conflict obeys STOP.
    let cue = row("expert-cue", dir.path());
    assert_eq!((cue.authorized_success, cue.conflict_success, cue.conflict_stop), (all, none, all), "{cue:?}");
    // The language follower stacks when told to (conflict), so it breaks the STOP; "follow the
    // note" alone tells it nothing.
    let language = row("expert-language", dir.path());
    assert_eq!((language.authorized_success, language.conflict_success, language.conflict_stop), (none, all, none), "{language:?}");
    // The authorized expert follows the note only when language authorises it.
    let authorized = row("expert-authorized", dir.path());
    assert_eq!((authorized.authorized_success, authorized.conflict_success, authorized.conflict_stop), (all, all, none), "{authorized:?}");
    // Holding still never stacks, and always obeys STOP.
    let zero = row("zero", dir.path());
    assert_eq!((zero.authorized_success, zero.conflict_success, zero.conflict_stop), (none, none, all), "{zero:?}");
    // The report folder gets the study's table in three formats and its chart.
    let records: Vec<EpisodeRecord> = ["expert-cue", "expert-language", "expert-authorized", "zero"]
        .iter()
        .flat_map(|p| final_records(read_records(&dir.path().join(format!("{p}.jsonl"))).unwrap().records).into_values())
        .collect();
    let out = dir.path().join("report");
    let markdown = studies::write_reports(&records, &Default::default(), &out).unwrap();
    assert!(markdown.contains("PiPER cup stacking"), "{markdown}");
    for file in ["piper.md", "piper.csv", "piper.json", "chart_piper.png"] {
        assert!(std::fs::metadata(out.join(file)).is_ok_and(|m| m.len() > 0), "{file} not written");
    }
}

#[test]
fn a_bad_action_is_refused_in_the_piper_s_own_terms() {
    let mut env = vifo_protocols::env::Env::new(EnvConfig { size: 64, cameras: Vec::new(), ..EnvConfig::default() });
    env.reset(&piper::spec(vifo_protocols::Protocol::Authorized, 0, 0).unwrap()).unwrap();
    let err = env.step(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, -1.0]).err().unwrap();
    assert!(err.to_string().contains("value 2 (dq3) is NaN"), "{err}");
    assert!(env.step(&[0.0; 7]).is_ok(), "the refused action left the episode running");
}
