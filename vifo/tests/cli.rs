//! The `vifo` program as a shell runs it.

use std::process::{Command, Stdio};

/// `vifo cues list --ids | head` is ordinary use: when the reader closes the pipe, `vifo` ends
/// quietly with the status a closed pipe gives C tools, not with a panic on standard error.
#[test]
fn a_closed_output_pipe_ends_vifo_quietly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["cues", "list", "--ids", "--set", "full"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start vifo");
    // Closed before vifo has built its instance set, so its first line meets a closed pipe.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait for vifo");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(vifo::CLOSED_OUTPUT_STATUS), "stderr: {stderr}");
    assert!(stderr.is_empty(), "vifo printed on a closed pipe: {stderr}");
}
