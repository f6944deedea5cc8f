//! Subcommands of `vifo`, one module each.

pub mod cues;
