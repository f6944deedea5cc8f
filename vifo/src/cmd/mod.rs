//! Subcommands of `vifo`, one module each.

pub mod assets;
pub mod xval;
pub mod report;
pub mod vqa;
pub mod bddl;
pub mod bench;
pub mod cues;
pub mod expert;
pub mod render;
pub mod run;
pub mod init_states;
pub mod web;

/// A count that must be 1 or more (`--episodes`, `--steps`, ...): 0 would run nothing and
/// report it as a result.
pub fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("expected 1 or more: 0 would run nothing".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}
