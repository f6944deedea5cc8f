//! Cues on simulated scenes: the bridge from a running episode to the cue library.
//!
//! `vifo-cues` draws a cue given pixel anchors, ghost layers and pictures; this module gets
//! those from the simulator (paper appendix B):
//!
//! - [`EpisodeCue::prepare`] once per episode (after reset): finds the cue's source and target
//!   in the scene ([`anchors`]), and for ghosts and goal pictures runs the scripted expert on a
//!   fork of the episode ([`demo`]).
//! - [`EpisodeCue::apply`] per camera frame: scene-anchored cues are projected from the current
//!   state through the frame's camera ([`CameraProjector`]), ghosts are rendered from that
//!   camera (`ghost`), fixed-region cues keep their place.
//! - [`tasks`]: the instance set of the 40 built-in tasks and lookup by instance id.
//! - [`gallery`]: contact sheets of every variant on real scene frames.

pub mod anchors;
pub mod demo;
mod episode;
mod error;
pub mod gallery;
mod ghost;
mod projector;
pub mod start;
pub mod tasks;

pub use anchors::{CuePoints, ScenePoint};
pub use demo::DemoOutcome;
pub use episode::{CueFacing, DEFAULT_GHOSTS, EpisodeCue};
pub use error::SceneCueError;
pub use projector::CameraProjector;
pub use tasks::{builtin_instances, builtin_set, describe, instance, study_instances, task_of, unknown_instance_hint};
