//! Robot arms for LIBERO-VIFO.
//!
//! - [`model`]: immutable arm descriptions (kinematic tree, inertials, joint parameters, shapes).
//! - [`dynamics`]: our own forward kinematics, Jacobians, mass matrix and bias forces
//!   (fixed-size maths, identical bits natively and in wasm).
//! - [`panda`]: the Panda + PandaGripper (+ RethinkMount) exactly as LIBERO uses them, its links
//!   colliding as hulls fitted to robosuite's collision meshes (`panda_hulls`).
//! - [`soft`], [`limits`], [`soft_contact`]: MuJoCo's soft constraints, its joint limits, and its
//!   soft contacts of the arm with itself and the scene's fixed bodies.

// The model files write angles and quaternions in rounded digits (0.707107, 1.5708, 3.14); the
// arms keep those digits, not the exact constants, to match the originals.
#![allow(clippy::approx_constant)]

pub mod action;
pub mod arm;
pub mod contact;
pub mod convert;
pub mod dynamics;
pub mod fluid;
pub mod gripper;
pub mod joint;
pub mod limits;
pub mod model;
pub mod osc;
pub mod panda;
mod panda_hulls;
pub mod piper;
pub mod soft_contact;
pub mod soft;
pub mod spatial;

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
