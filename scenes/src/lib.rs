//! LIBERO-VIFO scenes: task definitions, BDDL import, scene classes and initial states.
//!
//! - [`task`](mod@task): the [`Task`] data model and the 40 built-in tasks of the four VLA suites.
//! - [`bddl`]: reads LIBERO's BDDL files into a [`Task`].
//! - [`scene_class`]: per problem class, the arena facts (table, robot base, camera, lights).
//! - [`init_file`]: reads LIBERO's `.pruned_init` files and names the parts of a state row.
//! - [`init_states`]: our own 50 initial states per task (LIBERO's placement rules, settled in
//!   our physics), shipped in `init_states/<suite>.json`.
//! - [`catalog`]: every object and fixture category the 40 tasks use (collision, mass, sites,
//!   procedural looks).
//! - [`look`]: LIBERO's own meshes and textures, found and loaded at run time when installed.
//! - [`cue_object`]: cues made physical (paper §4.2): text cards, signs and code tags as
//!   rigid bodies in the scene.
//! - [`sim`]: tasks running in the physics world ([`vifo_physics`], [`vifo_robots`]); [`view`]:
//!   rendering them with LIBERO's cameras ([`vifo_render`]).
//!
//! The task data and its parsing need none of those; the simulated scene and its view are
//! built on them. Nothing here knows of cues' drawings or protocols.

pub mod bddl;
pub mod catalog;
pub mod cue_object;
pub mod init_file;
pub mod init_states;
pub mod look;
pub mod scene_class;
pub mod sim;
pub mod task;
pub mod view;

pub use task::{PIPER_SUITE, SAFETY_SUITE, Suite, Task, all_tasks, study_suites, suite, suite_names, suites, task};

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
