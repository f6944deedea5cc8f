//! Visual cue library of LIBERO-VIFO.
pub mod parse;
