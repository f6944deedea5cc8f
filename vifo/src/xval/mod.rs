//! Cross-validation against the original MuJoCo LIBERO: replay recorded actions from recorded
//! initial states and measure how far our motion is from the reference; compare our camera
//! images and pixel projections with MuJoCo's.

pub mod images;
pub mod projection;
mod reference;
mod replay;

pub use reference::{REFERENCE_PHASES, Record, Recording, recordings_in};
pub use replay::{ErrorStats, ObjectError, PhaseReport, Summary, TaskReport, replay, start, summarize};
