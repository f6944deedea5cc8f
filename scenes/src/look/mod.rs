//! LIBERO's own look: its meshes and textures, found on this machine and loaded at run time.
//!
//! - [`discover`]: where the asset folders are (`--assets`, `VIFO_LIBERO_ASSETS`, Python
//!   packages; robosuite for the robot).
//! - [`AssetTree`]: one upstream file found by path, or by blob hash under another name.
//! - [`Look`]: every catalog category's and Panda body's visual parts loaded once (meshes and
//!   textures shared by `Arc`; categories side by side on up to four threads, the same look
//!   whatever the count), with a report per category and body and a content hash; those whose
//!   files are missing or broken keep the built-in procedural look.
//! - The disk cache (`cache.rs`): what loading made of each file, kept by content for the next
//!   process, which then loads in under a second instead of about ten.
//!
//! The visual facts (which mesh and material each part has, at which pose and scale) are written
//! in `facts.rs`, generated from LIBERO's XMLs by `scenes/tools/gen_look_facts.py`.

mod cache;
mod discover;
mod facts;
mod parallel;
mod parts;
mod store;
mod tree;

pub use cache::{CACHE_VAR, CacheReport};
pub use discover::{BadFlag, ENV_VAR, Origin, PythonFound, Root, Roots, Sources, ask_interpreter, discover, discover_from, discover_with};
pub use store::{BUILT_IN, CategoryReport, FileReport, LoadedPart, Lods, Look, MirrorFace, PartKind, Status, lod_step};
pub use tree::{AssetTree, FoundBy, KNOWN_BLOBS, Located, blob_sha1};

/// The robot parts body of robosuite's pedestal, drawn on the base of a mounted Panda.
pub const MOUNT: &str = "mount";

/// The arm whose meshes the look's robot parts are (robosuite's Panda).
const ARM: &str = "panda";

#[cfg(test)]
mod tests;
