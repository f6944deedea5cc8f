//! A misbehaving policy server (`vifo_tests::fault_server`): each fault ends the episode it
//! hits as an error naming the fault, the run goes on, the resumed run retries the episode,
//! and nothing written before is lost. (`examples/policy_faults.rs` repeats this 10 times per
//! fault and prints the counts.) Two client defects this found are fixed: a malformed reply
//! kept the connection (so a confused server kept serving the next episode), and metadata that
//! was not one msgpack map (`0xc1` decodes as nil) passed the handshake.

use vifo_tests::fault_server::Fault;
use vifo_tests::fault_trials::{Counts, run_faults};

#[test]
fn every_fault_is_an_error_naming_it_and_the_run_recovers() {
    let dir = tempfile::tempdir().unwrap();
    let c = run_faults(&Fault::ALL, 1, dir.path()).unwrap();
    let n = Fault::ALL.len();
    let expected = Counts { episodes: n + 1, fired: n, errors_named: n, ..Counts::default() };
    assert_eq!(c, expected);
}

/// A client that is done ends its connection with a websocket close, so the server sees a
/// normal close and not a dropped stream (servers other than openpi's log a traceback for each
/// dropped one); so does one that gives up a connection after a malformed reply.
#[test]
fn a_client_done_with_its_connection_closes_the_websocket() {
    use std::time::{Duration, Instant};
    use vifo_cues::RgbImage;
    use vifo_protocols::Policy;
    use vifo_protocols::policy::Observation;
    use vifo_protocols::remote::{RemoteConfig, RemotePolicy};
    use vifo_tests::fault_server::{CLIENT_TIMEOUT, FaultServer};

    let server = FaultServer::start(vec![Fault::Garbage], 1).unwrap();
    let mut config = RemoteConfig::new(&server.url());
    config.request_timeout = CLIENT_TIMEOUT;
    config.image_size = 32;
    let mut policy = RemotePolicy::with_config(config).unwrap();
    let obs = Observation {
        agentview: RgbImage::new(32, 32).unwrap(),
        wrist: RgbImage::new(32, 32).unwrap(),
        eef_pos: [0.0; 3],
        eef_quat_xyzw: [0.0, 0.0, 0.0, 1.0],
        gripper_qpos: [0.0; 2],
        joint_pos: [0.0; 7],
        instruction: "pick up the bowl".into(),
        step: 0,
    };
    let closed_within = |n: usize| {
        let deadline = Instant::now() + Duration::from_secs(5);
        while server.closed() < n && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(5));
        }
        server.closed()
    };
    // The first request gets garbage: the client gives that connection up.
    assert!(policy.act(&obs).is_err());
    assert_eq!(closed_within(1), 1, "the connection given up after garbage was not closed");
    // The next episode connects afresh, is served, and the client is dropped.
    policy.reset().unwrap();
    policy.act(&obs).unwrap();
    assert_eq!(server.served(), 1);
    drop(policy);
    assert_eq!(closed_within(2), 2, "the dropped client's connection was not closed");
}
