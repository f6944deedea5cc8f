//! Physics core of LIBERO-VIFO.
//!
//! A [`World`] wraps a rapier3d world (f64, `enhanced-determinism`) stepped at LIBERO's rate.
//! Its whole mutable state can be captured as a [`Snapshot`] and restored bit for bit, which is
//! what resets and "simulated futures" (ghost trajectories) are built on. Like MuJoCo's split of
//! `mjModel` and `mjData`, the immutable parts (collision shapes) are shared by reference between
//! a world and its snapshots, so a snapshot costs a copy of the small per-body state only.
//! Each step skips the contact rows that cannot act within it ([`inert`]).
//!
//! This crate knows nothing of robots, tasks, cameras or cues.

mod fingerprint;
pub mod inert;
mod params;
mod world;

pub use fingerprint::Fingerprint;
pub use params::SimParams;
pub use world::{Snapshot, TOUCH_DISTANCE, World};

/// The rapier3d build this workspace uses (`rapier3d-f64` with `enhanced-determinism`).
pub use rapier3d as rapier;

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
