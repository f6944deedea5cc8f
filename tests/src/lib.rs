//! Helpers for the end-to-end tests in `tests/tests/`.
//!
//! Tests that need LIBERO's reference data read it from `../shared` next to the workspace root.
//! A fresh clone has no such folder; such tests then print why they skipped and pass.
//!
//! [`fault_server`] is a misbehaving openpi server and [`fault_trials`] the runs against it
//! that the fault test and `examples/policy_faults.rs` share.

pub mod fault_server;
pub mod fault_trials;

use std::path::PathBuf;

/// The workspace root (the folder holding the top-level `Cargo.toml`).
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `<workspace>/../shared/<relative>` if it exists; otherwise prints a skip notice naming the
/// test and the missing path, and returns `None`.
pub fn shared(relative: &str, test: &str) -> Option<PathBuf> {
    let path = workspace_root().join("..").join("shared").join(relative);
    if path.exists() {
        Some(path)
    } else {
        println!(
            "SKIPPED {test}: reference data {} not found (it lives outside the repository; \
             CI provides it)",
            path.display()
        );
        None
    }
}
