//! The adapters in `serving/` (InstructVLA, Action-Sketcher behind openpi's protocol) with
//! their stand-in models: LIBERO episodes through `vifo_protocols::serving` with the models'
//! profiles end exactly as the stand-in's fixed actions, converted as the models' scripts
//! convert them, run in-process; each episode resets the adapter's session once; a request
//! that does not have the documented shape is an error naming the field.
//!
//! Needs `python3` with openpi-client and websockets; without them the tests print why they
//! skipped and pass.

use std::time::Duration;

use vifo_protocols::benchmark::specs::spec;
use vifo_protocols::env::rollout::{RolloutOptions, rollout};
use vifo_protocols::env::{Env, EnvConfig};
use vifo_protocols::serving::{Profile, ServedPolicy, ServingConfig};
use vifo_protocols::spec::{Outcome, Protocol, TaskRef};
use vifo_protocols::{Observation, Policy, PolicyError};
use vifo_tests::python;

/// Replays a fixed list of actions, cyclically.
struct Cycle(Vec<[f64; 7]>, usize);

impl Policy for Cycle {
    fn name(&self) -> String {
        "in-process".into()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.1 = 0;
        Ok(())
    }

    fn act(&mut self, _obs: &Observation) -> Result<[f64; 7], PolicyError> {
        self.1 += 1;
        Ok(self.0[(self.1 - 1) % self.0.len()])
    }
}

/// Two episodes through the adapter, one in-process; returns the adapter's stderr.
fn episodes(script: &str, profile: &str, size: u32, expected: Vec<[f64; 7]>) {
    let test = format!("episodes_{profile}");
    if !python::ready(&test, "openpi_client, websockets") {
        return;
    }
    let path = vifo_tests::workspace_root().join("serving").join(script);
    let server = python::Server::start(&path, &["--stand-in", "--host", "127.0.0.1"]);
    let url = format!("ws://127.0.0.1:{}", server.port);
    let mut config = ServingConfig::new(&url, None, Profile::named(profile)).unwrap();
    config.request_timeout = Duration::from_secs(20);
    let mut remote = ServedPolicy::connect(&config).unwrap();

    let task = TaskRef { suite: "libero_spatial".into(), index: 0 };
    let episode = spec(&task, Protocol::Original, None, 0, 0).unwrap();
    let mut env = Env::new(EnvConfig { size, ..EnvConfig::default() });
    let options = RolloutOptions::default();
    let first = rollout(&mut env, &mut remote, &episode, &options);
    let end_remote = env.observation().clone();
    let second = rollout(&mut env, &mut remote, &episode, &options);
    let local = rollout(&mut env, &mut Cycle(expected, 0), &episode, &options);
    println!("{profile}: adapter {:?} ({} requests); in-process {:?}", first.outcome, remote.requests(), local.outcome);
    assert!(matches!(first.outcome, Outcome::Completed { steps: 220, .. }), "{:?}; {}", first.outcome, server.log());
    assert_eq!(first.outcome, local.outcome);
    assert_eq!(second.outcome, local.outcome);
    assert_eq!(end_remote, *env.observation(), "the episodes ended in different states");
    let log = server.log();
    let resets: Vec<&str> = log.lines().filter_map(|l| l.strip_prefix("RESET ")).collect();
    assert_eq!(resets, [episode.instruction.as_str(); 2], "one session reset per episode");
}

#[test]
fn instructvla_adapter_episodes() {
    // The stand-in answers [0.002, -0.001, 0.003, 0, 0, 0.01, 1.0] every step; 1.0 is "open"
    // in InstructVLA's RLDS convention, -1 in LIBERO's.
    episodes("instructvla_server.py", "instructvla", 256, vec![[0.002, -0.001, 0.003, 0.0, 0.0, 0.01, -1.0]]);
}

#[test]
fn action_sketcher_adapter_episodes() {
    // The stand-in answers a 4-row chunk, executed whole before the next request.
    let chunk = (0..4).map(|i| [0.001 * (i + 1) as f64, 0.0, -0.002, 0.0, 0.0, 0.0, -1.0]).collect();
    episodes("action_sketcher_server.py", "action-sketcher", 224, chunk);
}

#[test]
fn adapters_check_requests() {
    if !python::ready("adapters_check_requests", "openpi_client, websockets") {
        return;
    }
    // InstructVLA's adapter with Action-Sketcher's 224² frames: the stand-in names the field.
    let path = vifo_tests::workspace_root().join("serving").join("instructvla_server.py");
    let server = python::Server::start(&path, &["--stand-in", "--host", "127.0.0.1"]);
    let url = format!("ws://127.0.0.1:{}", server.port);
    let config = ServingConfig::new(&url, None, Profile::named("action-sketcher")).unwrap();
    let mut policy = ServedPolicy::connect(&config).unwrap();
    policy.reset().unwrap();
    let frame = vifo_cues::RgbImage::filled(224, 224, [10, 20, 30]).unwrap();
    let obs = Observation {
        agentview: frame.clone(),
        wrist: frame,
        eef_pos: [0.0, 0.0, 1.0],
        eef_quat_xyzw: [1.0, 0.0, 0.0, 0.0],
        gripper_qpos: [0.04, -0.04],
        joint_pos: [0.0; 7],
        instruction: "open the drawer".into(),
        step: 0,
    };
    match policy.act(&obs) {
        Err(PolicyError::Other(m)) => assert!(m.contains("observation/image is (224, 224, 3)"), "{m}"),
        other => panic!("expected the adapter's error, got {other:?}"),
    }
}
