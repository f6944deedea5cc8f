//! Every serving format of `vifo_protocols::serving` against its scripted test server
//! (`tests/python/format_servers.py`, which checks every request field against the format's
//! documented shape), plus the openpi format with the `pi05` profile against
//! `tests/python/scripted_policy_server.py`.
//!
//! For each format, one LIBERO episode over the wire must give the same actions (the same
//! final state, bit for bit) and the same result as the same scripted policy in-process; the
//! test prints one `GATE serving <format>` line each (`cargo test -p vifo-tests --test
//! serving_formats -- --nocapture`). Each malformed reply must be an episode error naming the
//! field, and the next episode must work again.
//!
//! Needs `python3` with openpi-client, websockets, json-numpy and grpcio (`.ci/run` installs
//! them); without them every test prints why it skipped and passes.

use std::time::Duration;

use vifo_cues::RgbImage;
use vifo_protocols::benchmark::specs::spec;
use vifo_protocols::env::rollout::{RolloutOptions, rollout};
use vifo_protocols::env::{Env, EnvConfig};
use vifo_protocols::serving::{Format, Profile, ServedPolicy, ServingConfig};
use vifo_protocols::spec::{Outcome, Protocol, TaskRef};
use vifo_protocols::{Observation, Policy, PolicyError};
use vifo_tests::python;
use vifo_tests::scripted_actions::SameAsServer;

/// The Python modules each format's test server needs.
fn modules(format: Format) -> &'static str {
    match format {
        Format::Openpi | Format::InternVla => "openpi_client, websockets",
        Format::OpenVlaOft => "json_numpy, numpy",
        Format::Xiaomi => "numpy, PIL",
        Format::LeRobot => "grpc, numpy",
    }
}

/// The scripted test server of a format.
struct Server(python::Server);

impl Server {
    /// The server for `format` (`chunk` actions per reply).
    fn for_format(format: Format, chunk: usize, extra: &[&str]) -> Server {
        let chunk = chunk.to_string();
        match format {
            Format::Openpi => Server(python::Server::start(&script("scripted_policy_server.py"), &["--chunk", &chunk])),
            other => {
                let mut args = vec![other.name(), "--chunk", &chunk, "--lifetime", "600"];
                args.extend(extra);
                Server(python::Server::start(&script("format_servers.py"), &args))
            }
        }
    }

    fn url(&self, format: Format) -> String {
        match format {
            Format::OpenVlaOft => format!("http://127.0.0.1:{}/act", self.0.port),
            other => format!("{}://127.0.0.1:{}", other.scheme(), self.0.port),
        }
    }

    /// What the server printed on stderr (its failed checks).
    fn log(&self) -> String {
        self.0.log()
    }
}

fn script(name: &str) -> std::path::PathBuf {
    vifo_tests::workspace_root().join("tests").join("python").join(name)
}

/// A case: the format, the model profile, the chunk the server answers.
struct Case {
    format: Format,
    profile: &'static str,
    chunk: usize,
    /// The server sees a float32 state.
    state32: bool,
    /// The server answers float32 actions.
    action32: bool,
    /// The gripper value of request n, in LIBERO's convention, after the client's conversion.
    gripper: fn(usize) -> f64,
    /// URL query (LeRobot's policy setup).
    query: &'static str,
}

fn open_close(n: usize) -> f64 {
    if n.is_multiple_of(2) { -1.0 } else { 1.0 }
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            format: Format::Openpi,
            profile: "pi05",
            chunk: 10,
            state32: false,
            action32: false,
            gripper: |n| n as f64,
            query: "",
        },
        Case {
            format: Format::InternVla,
            profile: "internvla",
            chunk: 8,
            state32: true,
            action32: true,
            gripper: open_close,
            query: "",
        },
        Case {
            format: Format::OpenVlaOft,
            profile: "openvla-oft",
            chunk: 8,
            state32: false,
            action32: false,
            gripper: open_close,
            query: "",
        },
        Case {
            format: Format::Xiaomi,
            profile: "xiaomi",
            chunk: 10,
            state32: false,
            action32: true,
            gripper: open_close,
            query: "",
        },
        Case {
            format: Format::LeRobot,
            profile: "molmoact2",
            chunk: 10,
            state32: true,
            action32: true,
            gripper: open_close,
            query: "?policy_type=molmoact2&pretrained=allenai/MolmoAct2-LIBERO&device=cpu&kw.norm_tag=libero&kw.inference_action_mode=continuous",
        },
    ]
}

fn connect(case: &Case, server: &Server) -> Result<ServedPolicy, PolicyError> {
    let url = format!("{}{}", server.url(case.format), case.query);
    let mut config = ServingConfig::new(&url, Some(case.format), Profile::named(case.profile))?;
    config.request_timeout = Duration::from_secs(20);
    ServedPolicy::connect(&config)
}

fn run_gate(case: &Case) {
    let server = Server::for_format(case.format, case.chunk, &[]);
    let task = TaskRef { suite: "libero_spatial".into(), index: 0 };
    let episode = spec(&task, Protocol::Original, None, 0, 0).unwrap();
    let mut env = Env::new(EnvConfig { size: 256, ..EnvConfig::default() });
    let options = RolloutOptions::default();
    let mut remote =
        connect(case, &server).unwrap_or_else(|e| panic!("{}: {e}; server: {}", case.format, server.log()));
    let over_the_wire = rollout(&mut env, &mut remote, &episode, &options);
    let end_remote = env.observation().clone();
    let profile = Profile::named(case.profile).unwrap();
    let replan = profile.used(case.chunk);
    let mut local = SameAsServer::new(replan, case.state32, case.action32, case.gripper);
    let in_process = rollout(&mut env, &mut local, &episode, &options);
    let same_state = end_remote == *env.observation();
    println!(
        "GATE serving {} (profile {}): over the wire {:?} with {} requests; in-process {:?}; same outcome: {}; \
         final state bit-identical: {}",
        case.format,
        case.profile,
        over_the_wire.outcome,
        remote.requests(),
        in_process.outcome,
        over_the_wire.outcome == in_process.outcome,
        same_state
    );
    assert!(
        matches!(over_the_wire.outcome, Outcome::Completed { steps: 220, .. }),
        "{}: {:?}; server: {}",
        case.format,
        over_the_wire.outcome,
        server.log()
    );
    assert_eq!(over_the_wire.outcome, in_process.outcome, "{}", case.format);
    assert!(same_state, "{}: the episodes ended in different states", case.format);
    assert_eq!(remote.requests(), 220usize.div_ceil(replan), "{}", case.format);
    assert!(!server.log().contains("CHECK FAILED"), "{}: {}", case.format, server.log());
}

fn gate(format: Format) {
    let test = format!("gate_{}", format.name());
    let case = cases().into_iter().find(|c| c.format == format).unwrap();
    if python::ready(&test, modules(format)) {
        run_gate(&case);
    }
}

#[test]
fn gate_openpi() {
    gate(Format::Openpi);
}

#[test]
fn gate_internvla() {
    gate(Format::InternVla);
}

#[test]
fn gate_openvla_oft() {
    gate(Format::OpenVlaOft);
}

#[test]
fn gate_xiaomi() {
    gate(Format::Xiaomi);
}

#[test]
fn gate_lerobot() {
    gate(Format::LeRobot);
}

/// The policy setup names the wrist camera as MolmoAct2's LIBERO evaluation does, or as the URL
/// asks, and carries the `kw.` keys as `policy_kwargs` (MolmoAct2's `norm_tag`, ...).
#[test]
fn lerobot_setup_names_the_wrist_camera_and_passes_policy_kwargs() {
    if !python::ready("lerobot_setup_names_the_wrist_camera_and_passes_policy_kwargs", modules(Format::LeRobot)) {
        return;
    }
    let case = cases().into_iter().find(|c| c.format == Format::LeRobot).unwrap();
    for (query, says) in [
        (case.query, r#"SETUP wrist=wrist_image policy_kwargs={"inference_action_mode": "continuous", "norm_tag": "libero"}"#),
        ("?policy_type=pi0&pretrained=lerobot/pi0_libero&wrist=image2", "SETUP wrist=image2 policy_kwargs={}"),
    ] {
        let server = Server::for_format(Format::LeRobot, case.chunk, &[]);
        let mut policy = connect(&Case { query, ..case }, &server).unwrap();
        policy.reset().unwrap();
        policy.act(&observation("pick up the bowl")).unwrap_or_else(|e| panic!("{query}: {e}; {}", server.log()));
        let log = server.0.log_once(|log| log.contains(says));
        assert!(log.contains(says) && !log.contains("CHECK FAILED"), "{query}: {log}");
    }
}

fn pattern(salt: u32) -> RgbImage {
    let data = (0..256 * 256)
        .flat_map(|i: u32| {
            let (x, y) = (i % 256, i / 256);
            [(x * 3 + salt) as u8, (y * 5) as u8, ((x * y) >> 3) as u8 ^ salt as u8]
        })
        .collect();
    RgbImage::from_raw(256, 256, data).unwrap()
}

fn observation(instruction: &str) -> Observation {
    Observation {
        agentview: pattern(0),
        wrist: pattern(77),
        eef_pos: [0.1, -0.2, 1.05],
        eef_quat_xyzw: [0.99, 0.05, -0.1, 0.02],
        gripper_qpos: [0.039, -0.039],
        joint_pos: [0.0; 7],
        instruction: instruction.to_string(),
        step: 0,
    }
}

/// Each malformed reply is an error naming what is wrong; the next episode works.
fn malformed(format: Format, kinds: &[(&str, &str)]) {
    let test = format!("malformed_{}", format.name());
    if !python::ready(&test, modules(format)) {
        return;
    }
    let case = cases().into_iter().find(|c| c.format == format).unwrap();
    let server = Server::for_format(format, case.chunk, &[]);
    let mut policy = connect(&case, &server).unwrap();
    for (kind, expected) in kinds {
        policy.reset().unwrap_or_else(|e| panic!("{format} reset after {kind}: {e}"));
        match policy.act(&observation(&format!("malformed:{kind}"))) {
            Err(e) => {
                let m = e.to_string();
                println!("{format} malformed:{kind} -> {m}");
                assert!(m.contains(expected), "{format} {kind}: {m:?} lacks {expected:?}");
            }
            Ok(a) => panic!("{format} {kind}: expected an error, got {a:?}"),
        }
    }
    policy.reset().unwrap();
    policy
        .act(&observation("pick up the bowl"))
        .unwrap_or_else(|e| panic!("{format} after errors: {e}; {}", server.log()));
    assert!(!server.log().contains("CHECK FAILED"), "{format}: {}", server.log());
}

#[test]
fn malformed_internvla() {
    malformed(
        Format::InternVla,
        &[
            ("missing_actions", "no `data.actions`"),
            ("wrong_shape", "`data.actions` has shape [8, 7], expected (B, T, D)"),
            ("wrong_dtype", "`data.actions`: dtype \"<i8\""),
            ("error_status", "`ok` = false, `status` = \"error\"): scripted failure"),
            ("missing_ok", "no `ok`"),
            ("nan", "`data.actions`[0, 1, 2] is NaN"),
            ("not_msgpack", "reply is not a msgpack document: it starts with byte 0xc1"),
        ],
    );
}

#[test]
fn malformed_openvla_oft() {
    malformed(
        Format::OpenVlaOft,
        &[
            ("error", "answered \"error\""),
            ("wrong_shape", "`actions` has 8 rows of 6"),
            ("wrong_dtype", "`actions[0]` has dtype \"<i8\""),
            ("missing_field", "`actions[0]` is an object without `__numpy__`"),
            ("http_500", "HTTP status 500"),
            ("not_json", "not JSON"),
            ("oversize", "the reply is larger than 64 MiB"),
        ],
    );
}

#[test]
fn malformed_xiaomi() {
    malformed(
        Format::Xiaomi,
        &[
            ("wrong_shape", "reply `action` has shape [10, 9], expected (1, T, D)"),
            ("wrong_dtype", "torch.LongStorage is not a float tensor"),
            ("not_tensor", "a dict, expected a torch tensor"),
            ("short_data", "reply is not a pickle"),
            ("close", "waiting for the reply"),
        ],
    );
}

#[test]
fn malformed_lerobot() {
    malformed(
        Format::LeRobot,
        &[
            ("wrong_shape", "`actions[0].action` has shape [5]"),
            ("wrong_dtype", "torch.LongStorage is not a float tensor"),
            ("missing_action", "`actions[0]` has no `action`"),
            ("error_status", "scripted failure"),
            ("empty_reply", "the server answered no actions for observation #"),
        ],
    );
}

/// gRPC reconnects by itself to a restarted LeRobot server, which then has no policy loaded:
/// every later episode failed as "empty actions". After a failed request the next episode sets
/// the policy up again.
#[test]
fn lerobot_sets_its_policy_up_again_after_a_failed_request() {
    if !python::ready("lerobot_sets_its_policy_up_again_after_a_failed_request", modules(Format::LeRobot)) {
        return;
    }
    let case = cases().into_iter().find(|c| c.format == Format::LeRobot).unwrap();
    let server = Server::for_format(Format::LeRobot, case.chunk, &[]);
    let mut policy = connect(&case, &server).unwrap();
    let setups = |n: usize| server.0.log_once(|log| log.matches("SETUP ").count() >= n).matches("SETUP ").count();
    policy.reset().unwrap();
    policy.act(&observation("pick up the bowl")).unwrap();
    policy.reset().unwrap();
    assert_eq!(setups(1), 1, "a good episode needs no new set-up: {}", server.log());
    assert!(policy.act(&observation("malformed:error_status")).is_err());
    policy.reset().unwrap();
    assert_eq!(setups(2), 2, "{}", server.log());
    policy.act(&observation("pick up the bowl")).unwrap();
}

#[test]
fn internvla_metadata_is_checked() {
    if !python::ready("internvla_metadata_is_checked", modules(Format::InternVla)) {
        return;
    }
    let case = cases().into_iter().find(|c| c.format == Format::InternVla).unwrap();
    let server = Server::for_format(Format::InternVla, 8, &["--bad-metadata"]);
    match connect(&case, &server) {
        Err(PolicyError::Malformed(m)) => {
            assert!(m.contains("`protocol_version` is \"2.0\""), "{m}")
        }
        Err(other) => panic!("expected Malformed, got {other}"),
        Ok(_) => panic!("expected the metadata to be refused"),
    }
}
