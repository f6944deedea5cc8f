//! Helpers for the end-to-end tests in `tests/tests/`.
//!
//! Tests that need LIBERO's reference data read it from `../shared` next to the workspace root.
//! A fresh clone has no such folder; such tests then say why they skipped ([`skip_notice`]) and
//! pass.
//!
//! [`fault_server`] is a misbehaving openpi server and [`fault_trials`] the runs against it
//! that the fault test and `examples/policy_faults.rs` share. [`scripted_actions`] is what the
//! scripted policy servers answer, computed in-process.

pub mod fault_server;
pub mod fault_trials;
pub mod scripted_actions;

use std::fmt::Display;
use std::io::Write;
use std::path::PathBuf;

/// Says that `test` skipped and why, where a plain `cargo test` shows it: straight to stderr,
/// which the test harness does not capture (it captures `print!` and `eprint!` only), so a run
/// on a fresh clone lists what it could not check. One write, so lines of parallel tests do not
/// interleave.
pub fn skip_notice(test: &str, why: impl Display) {
    let _ = std::io::stderr().write_all(format!("SKIPPED {test}: {why}\n").as_bytes());
}

/// The workspace root (the folder holding the top-level `Cargo.toml`).
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `<workspace>/../shared/<relative>` if it exists; otherwise gives a skip notice naming the
/// test and the missing path, and returns `None`.
pub fn shared(relative: &str, test: &str) -> Option<PathBuf> {
    let path = workspace_root().join("..").join("shared").join(relative);
    if path.exists() {
        Some(path)
    } else {
        skip_notice(
            test,
            format_args!("reference data {} not found (it lives outside the repository; CI provides it)", path.display()),
        );
        None
    }
}

/// A set of MuJoCo recordings kept outside the repository (they are made with the original
/// stack, not shipped): `$<env>` if set, else `~/.cache/libero-vifo/<name>`, when it holds
/// `*_init0.json` recordings; otherwise gives a skip notice naming the test, the folder and
/// `how` to record it, and returns `None`.
pub fn recorded(env: &str, name: &str, how: &str, test: &str) -> Option<PathBuf> {
    let dir = std::env::var_os(env)
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache/libero-vifo").join(name)));
    let has_recordings = |d: &PathBuf| {
        std::fs::read_dir(d).is_ok_and(|entries| {
            entries.filter_map(Result::ok).any(|e| e.file_name().to_string_lossy().ends_with("_init0.json"))
        })
    };
    match dir {
        Some(d) if has_recordings(&d) => Some(d),
        d => {
            let dir = d.map_or_else(|| format!("$HOME/.cache/libero-vifo/{name}"), |d| d.display().to_string());
            skip_notice(test, format_args!("no recordings at {dir} (record them with `{how}`, or set {env})"));
            None
        }
    }
}

pub mod python {
    //! Python helper processes for the policy client tests: an import check that gives a skip
    //! notice, and a server process that reports its port and is killed when dropped.

    use std::io::{BufRead, BufReader, Read};
    use std::path::Path;
    use std::process::{Child, Command, Stdio};
    use std::sync::{Arc, Mutex};
    use std::time::Duration;

    /// True when python3 can import `modules` (comma-separated); otherwise gives a skip notice.
    pub fn ready(test: &str, modules: &str) -> bool {
        let ok = Command::new("python3")
            .args(["-c", &format!("import {modules}")])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            super::skip_notice(
                test,
                format_args!(
                    "python3 cannot import {modules} (.ci/run installs the test requirements: openpi-client, \
                     websockets, json-numpy, grpcio)"
                ),
            );
        }
        ok
    }

    /// A Python server started as `python3 SCRIPT ARGS... --port 0`, which prints `PORT <n>`
    /// once listening. Its stderr is collected for failure messages.
    pub struct Server {
        child: Child,
        pub port: u16,
        stderr: Arc<Mutex<String>>,
    }

    impl Server {
        pub fn start(script: &Path, args: &[&str]) -> Server {
            let mut child = Command::new("python3")
                .arg(script)
                .args(args)
                .args(["--port", "0"])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("start python3");
            let stderr = Arc::new(Mutex::new(String::new()));
            let mut pipe = child.stderr.take().expect("piped stderr");
            let sink = stderr.clone();
            std::thread::spawn(move || {
                let mut buf = [0u8; 4096];
                while let Ok(n) = pipe.read(&mut buf) {
                    if n == 0 {
                        break;
                    }
                    sink.lock().unwrap().push_str(&String::from_utf8_lossy(&buf[..n]));
                }
            });
            let mut line = String::new();
            BufReader::new(child.stdout.take().expect("piped stdout")).read_line(&mut line).unwrap();
            let Some(port) = line.trim().strip_prefix("PORT ").and_then(|p| p.parse().ok()) else {
                let _ = child.kill();
                std::thread::sleep(Duration::from_millis(200));
                panic!("{} did not report its port: {line:?}; stderr: {}", script.display(), stderr.lock().unwrap());
            };
            Server { child, port, stderr }
        }

        /// What the server printed on stderr so far.
        pub fn log(&self) -> String {
            self.stderr.lock().unwrap().clone()
        }

        /// [`Server::log`] once `holds` says it has what is awaited, or as it is after 10 s: the
        /// pipe is read on a thread of its own, so a line the server printed before it answered
        /// may still be on its way when the answer has arrived.
        pub fn log_once(&self, holds: impl Fn(&str) -> bool) -> String {
            let deadline = std::time::Instant::now() + Duration::from_secs(10);
            loop {
                let log = self.log();
                if holds(&log) || std::time::Instant::now() > deadline {
                    return log;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }

    impl Drop for Server {
        fn drop(&mut self) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
