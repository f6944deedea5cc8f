//! The LIBERO-VIFO benchmark protocols.
//!
//! - [`spec`]: what one episode is (task, protocol, language condition, cue instance, seed) and
//!   what it produced — the records the runner writes and the reports read.
//! - [`policy`]: the observation a policy sees and the [`Policy`] trait every policy implements
//!   (built-in reference policies, remote VLA servers).
//! - `remote` (feature `net`, on by default): the openpi websocket client, a [`Policy`] served by a VLA server.
//! - `serving` (feature `net`): every VLA serving path (openpi, InternVLA, OpenVLA-OFT, Xiaomi, LeRobot) with
//!   one observation/action profile per model.
//! - [`report`]: the paper's Tables 1 and 2 (Markdown, CSV, JSON) and per-family bar charts.
//! - [`text_file`]: reading an input text file, refusing devices and naming bad bytes.
//! - [`runner`]: parallel, resumable, shardable runs writing one JSON line per episode.
//! - [`scene_cues`]: cue instances drawn on simulated scenes (anchors, ghosts, goal pictures).
//! - [`studies`]: the paper's extended studies (§4.2 cues as scene objects, ...) as episode
//!   selections and tables for the same runner and report.
//! - [`vqa`]: Part I-A questions, their export, answer extraction, scoring and answerers.

pub mod benchmark;
pub mod env;
pub mod policies;
pub mod policy;
#[cfg(feature = "net")]
pub mod remote;
pub mod report;
pub mod runner;
pub mod scene_cues;
#[cfg(feature = "net")]
pub mod serving;
pub mod spec;
pub mod studies;
pub mod text_file;
pub mod vqa;

pub use policy::{EpisodeState, Observation, Policy, PolicyError};
pub use spec::{CueForm, EpisodeRecord, EpisodeSpec, Outcome, Protocol, TaskRef};

/// The README's examples, compiled (and run where they need no server) as doctests so they
/// cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
