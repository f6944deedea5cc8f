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
