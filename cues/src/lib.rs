//! Visual cue library of LIBERO-VIFO: eight cue families, the robot signage system, the
//! rule-based task parser, cue specifications, the three insertion modes and the
//! task-conditioned instance set.
//!
//! The crate needs nothing of the simulator: a caller passes an RGB frame, a [`CueSpec`] and
//! [`FrameInputs`] (projected anchors, and rendered layers or pictures where a family needs
//! them) to an [`Inserter`]. See the README for the family catalogue and the rules.

pub mod anchors;
pub mod composition;
pub mod draw;
pub mod error;
pub mod families;
pub mod glyphs;
pub mod hash;
pub mod image;
pub mod insert;
pub mod instances;
pub mod parse;
pub mod picture;
pub mod signage;
pub mod spec;
pub mod variants;

pub use anchors::{Anchor, Anchors, PinholeCamera, Projector, WorldAnchor};
pub use error::CueError;
pub use image::{RgbImage, RgbaImage};
pub use insert::{AnchorUse, FrameInputs, InsertReport, Inserter};
pub use instances::{InstanceSet, SetName, TaskDescription};
pub use picture::{OBJECT_FAMILIES, object_picture};
pub use parse::{ParseError, ParsedTask, Relation, Step, parse, parse_with_goals};
pub use spec::{CueParams, CueSpec, Family, InsertMode, NormBox};
pub use variants::{Needs, VARIANTS, Variant};

/// The README's examples, compiled and run as doctests so they cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
