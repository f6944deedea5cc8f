//! Subcommands of `vifo`, one module each.

pub mod xval;
pub mod bddl;
pub mod bench;
pub mod cues;
pub mod expert;
pub mod render;
