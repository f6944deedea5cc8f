//! The work behind the `vifo` subcommands, as a library so tests can drive it directly.

pub mod bench;
pub mod expert;
pub mod look;
pub mod render;
pub mod start;
pub mod xval;
