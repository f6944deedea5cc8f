//! The openpi websocket client against a scripted server written with openpi-client's own
//! msgpack code (`tests/python/scripted_policy_server.py`), and our image preparation against
//! openpi-client's `image_tools` (`tests/python/openpi_image.py`).
//!
//! Needs `python3` with `openpi-client` and `websockets` (`.ci/run` installs them); without
//! them every test prints why it skipped and passes.

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use rmpv::Value;
use vifo_cues::RgbImage;
use vifo_protocols::remote::{RemoteConfig, RemotePolicy, Reply, image::openpi_image, ndarray};
use vifo_protocols::{Observation, Policy, PolicyError};
use vifo_tests::python;
use vifo_tests::scripted_actions::SameAsServer;

fn python_dir() -> PathBuf {
    vifo_tests::workspace_root().join("tests").join("python")
}

/// A scripted server process, killed when dropped.
struct Server {
    child: Child,
    port: u16,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new("python3")
            .arg(python_dir().join("scripted_policy_server.py"))
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .spawn()
            .expect("start python3");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        let port = line.trim().strip_prefix("PORT ").and_then(|p| p.parse().ok()).unwrap_or_else(|| {
            let _ = child.kill();
            panic!("server did not report its port: {line:?}")
        });
        Server { child, port }
    }

    fn url(&self) -> String {
        format!("ws://127.0.0.1:{}", self.port)
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        self.kill();
    }
}

fn pattern(w: u32, h: u32, salt: u32) -> RgbImage {
    let data = (0..w * h)
        .flat_map(|i| {
            let (x, y) = (i % w, i / w);
            [(x * 3 + salt) as u8, (y * 5) as u8, ((x * y) >> 3) as u8 ^ salt as u8]
        })
        .collect();
    RgbImage::from_raw(w, h, data).unwrap()
}

fn observation(prompt: &str) -> Observation {
    Observation {
        agentview: pattern(256, 256, 0),
        wrist: pattern(256, 256, 77),
        eef_pos: [0.1, -0.2, 1.05],
        eef_quat_xyzw: [0.99, 0.05, -0.1, 0.02],
        gripper_qpos: [0.039, -0.039],
        joint_pos: [0.0; 7],
        instruction: prompt.to_string(),
        step: 0,
    }
}

fn config(server: &Server) -> RemoteConfig {
    RemoteConfig { request_timeout: Duration::from_secs(20), ..RemoteConfig::new(&server.url()) }
}

fn echo<'a>(reply: &'a Reply, key: &str) -> &'a Value {
    let (_, echo) = reply.extra.iter().find(|(k, _)| k == "echo").expect("echo");
    let Value::Map(m) = echo else { panic!("echo is not a map") };
    ndarray::get(m, key).unwrap_or_else(|| panic!("echo has no {key}"))
}

fn array(v: &Value) -> ndarray::NdArray {
    ndarray::decode(v).unwrap().expect("an array")
}

#[test]
fn requests_arrive_as_openpi_sends_them() {
    if !python::ready("requests_arrive_as_openpi_sends_them", "openpi_client, websockets") {
        return;
    }
    for dtype in ["f4", "f8"] {
        let server = Server::start(&["--dtype", dtype, "--metadata", r#"{"reset_pose": [0, -1.5]}"#]);
        let mut policy = RemotePolicy::with_config(config(&server)).unwrap();
        let Value::Map(meta) = policy.metadata() else { panic!("metadata is not a map") };
        assert!(ndarray::get(meta, "reset_pose").is_some());

        let obs = observation("put the bowl on the plate");
        let reply = policy.infer(&obs).unwrap();
        let image = array(echo(&reply, "image"));
        assert_eq!((image.dtype.as_str(), image.shape.as_slice()), ("|u1", &[224, 224, 3][..]));
        assert_eq!(image.data, openpi_image(&obs.agentview, 224).data);
        assert_eq!(array(echo(&reply, "wrist_image")).data, openpi_image(&obs.wrist, 224).data);
        let state = array(echo(&reply, "state"));
        assert_eq!((state.dtype.as_str(), state.shape.as_slice()), ("<f8", &[8][..]));
        assert_eq!(state.to_f64().unwrap(), obs.state8());
        assert_eq!(echo(&reply, "prompt").as_str(), Some("put the bowl on the plate"));

        // actions[i, j] = state[j] + 0.01 i, in the server's dtype.
        assert_eq!(reply.actions.len(), 10);
        let s = obs.state8();
        let tol = if dtype == "f4" { 1e-6 } else { 0.0 };
        for (i, row) in reply.actions.iter().enumerate() {
            for j in 0..6 {
                assert!((row[j] - (s[j] + 0.01 * i as f64)).abs() <= tol, "{dtype} [{i},{j}]");
            }
        }
    }
}

#[test]
fn chunks_are_replanned_every_few_steps() {
    if !python::ready("chunks_are_replanned_every_few_steps", "openpi_client, websockets") {
        return;
    }
    let server = Server::start(&["--chunk", "10"]);
    let mut policy = RemotePolicy::with_config(config(&server)).unwrap();
    policy.reset().unwrap();
    let obs = observation("pick up the ketchup");
    let actions: Vec<[f64; 7]> = (0..23).map(|_| policy.act(&obs).unwrap()).collect();
    assert_eq!(policy.requests(), 5);
    // Step k uses row k % 5 of the chunk from request k / 5 (column 6 counts requests).
    for (k, a) in actions.iter().enumerate() {
        assert_eq!(a[6], (k / 5) as f64, "step {k}");
        assert!((a[0] - (obs.state8()[0] + 0.01 * (k % 5) as f64)).abs() < 1e-12, "step {k}");
    }
    // A new episode drops what is left of the queue.
    policy.reset().unwrap();
    assert_eq!(policy.act(&obs).unwrap()[6], 5.0);

    let mut wide = RemotePolicy::with_config(RemoteConfig { replan_steps: 3, ..config(&server) }).unwrap();
    for _ in 0..10 {
        wide.act(&obs).unwrap();
    }
    assert_eq!(wide.requests(), 4);

    let short = Server::start(&["--chunk", "4"]);
    let mut policy = RemotePolicy::with_config(config(&short)).unwrap();
    match policy.act(&obs) {
        Err(PolicyError::Malformed(m)) => assert!(m.contains("fewer than replan_steps"), "{m}"),
        other => panic!("expected Malformed, got {other:?}"),
    }
}

#[test]
fn a_killed_server_is_a_connection_error() {
    if !python::ready("a_killed_server_is_a_connection_error", "openpi_client, websockets") {
        return;
    }
    let mut server = Server::start(&[]);
    let mut policy = RemotePolicy::with_config(config(&server)).unwrap();
    policy.reset().unwrap();
    let obs = observation("open the drawer");
    for _ in 0..7 {
        policy.act(&obs).unwrap();
    }
    server.kill();
    // Three queued actions remain; the next request finds the server gone.
    for _ in 0..3 {
        policy.act(&obs).unwrap();
    }
    match policy.act(&obs) {
        Err(PolicyError::Connection(m)) => println!("mid-episode: {m}"),
        other => panic!("expected Connection, got {other:?}"),
    }
    // The next episode tries to reconnect and says why it cannot.
    match policy.reset() {
        Err(PolicyError::Connection(m)) => assert!(m.contains("cannot connect"), "{m}"),
        other => panic!("expected Connection, got {other:?}"),
    }
}

#[test]
fn misbehaving_servers_give_clear_errors_and_the_next_episode_recovers() {
    if !python::ready("misbehaving_servers_give_clear_errors_and_the_next_episode_recovers", "openpi_client, websockets") {
        return;
    }
    let server = Server::start(&[]);
    let mut policy =
        RemotePolicy::with_config(RemoteConfig { request_timeout: Duration::from_secs(2), ..config(&server) }).unwrap();
    let cases = [
        ("malformed:missing_actions", "no `actions`"),
        ("malformed:wrong_shape", "shape [10, 8]"),
        ("malformed:nan", "`actions`[2, 3] is NaN"),
        ("malformed:short_data", "needs 560 bytes of data, got 552"),
        ("malformed:not_msgpack", "msgpack"),
    ];
    for (prompt, expected) in cases {
        policy.reset().unwrap();
        match policy.act(&observation(prompt)) {
            Err(PolicyError::Malformed(m)) => assert!(m.contains(expected), "{prompt}: {m}"),
            other => panic!("{prompt}: expected Malformed, got {other:?}"),
        }
    }
    policy.reset().unwrap();
    match policy.act(&observation("malformed:text_error")) {
        Err(PolicyError::Other(m)) => assert!(m.contains("scripted failure"), "{m}"),
        other => panic!("expected the server's error text, got {other:?}"),
    }
    policy.reset().unwrap();
    match policy.act(&observation("slow:5")) {
        Err(PolicyError::Timeout(t)) => assert_eq!(t, 2.0),
        other => panic!("expected Timeout, got {other:?}"),
    }
    policy.reset().unwrap();
    assert!(policy.act(&observation("fine")).is_ok());

    // The server closes an idle connection between episodes: the client reconnects once.
    policy.reset().unwrap();
    policy.act(&observation("close_after_reply")).unwrap();
    std::thread::sleep(Duration::from_millis(200));
    policy.reset().unwrap();
    assert!(policy.act(&observation("fine")).is_ok());
}

#[test]
fn images_match_openpi_image_tools() {
    if !python::ready("images_match_openpi_image_tools", "openpi_client, websockets") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("vifo-openpi-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (w, h, size) in [(256, 256, 224), (128, 128, 224), (320, 240, 224), (200, 300, 224), (97, 61, 50)] {
        let img = pattern(w, h, w ^ h);
        let (input, output) = (dir.join("in.rgb"), dir.join("out.rgb"));
        std::fs::write(&input, &img.data).unwrap();
        let status = Command::new("python3")
            .arg(python_dir().join("openpi_image.py"))
            .args([w.to_string(), h.to_string(), size.to_string()])
            .args([&input, &output])
            .status()
            .unwrap();
        assert!(status.success());
        let expected = std::fs::read(&output).unwrap();
        let ours = openpi_image(&img, size).data;
        let differing = ours.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!((ours.len(), differing), (expected.len(), 0), "{w}x{h} -> {size}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_remote_episode_scores_as_the_same_actions_in_process() {
    use vifo_protocols::benchmark::specs::spec;
    use vifo_protocols::env::rollout::{RolloutOptions, rollout};
    use vifo_protocols::env::{Env, EnvConfig};
    use vifo_protocols::spec::{Outcome, Protocol, TaskRef};

    if !python::ready("a_remote_episode_scores_as_the_same_actions_in_process", "openpi_client, websockets") {
        return;
    }
    let server = Server::start(&["--chunk", "10"]);
    let task = TaskRef { suite: "libero_spatial".into(), index: 0 };
    let episode = spec(&task, Protocol::Original, None, 0, 0).unwrap();
    let mut env = Env::new(EnvConfig { size: 64, ..EnvConfig::default() });
    let options = RolloutOptions::default();
    let mut remote = RemotePolicy::with_config(config(&server)).unwrap();
    let over_the_wire = rollout(&mut env, &mut remote, &episode, &options);
    let end_remote = env.observation().clone();
    let mut local = SameAsServer::openpi(5);
    let in_process = rollout(&mut env, &mut local, &episode, &options);
    assert!(matches!(over_the_wire.outcome, Outcome::Completed { steps: 220, .. }), "{:?}", over_the_wire.outcome);
    assert_eq!(over_the_wire.outcome, in_process.outcome);
    // Both end in the same state bit for bit, so every action was the same.
    assert_eq!(end_remote.step, 220);
    assert_eq!(end_remote, *env.observation());
}
