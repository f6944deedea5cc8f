//! Errors of cue construction and insertion.

use crate::image::ImageError;

/// Why a cue could not be inserted. Insertion never panics on bad input; it reports one of
/// these and leaves the frame untouched.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CueError {
    #[error("unknown cue variant {0:?} (see `vifo cues variants`)")]
    UnknownVariant(String),
    #[error("inconsistent cue spec: {0}")]
    BadSpec(String),
    #[error("bad cue parameter: {0}")]
    BadParam(String),
    #[error("cue {variant} needs {what}")]
    MissingInput { variant: String, what: String },
    #[error("frame: {0}")]
    Frame(#[from] ImageError),
    #[error("{what}: {source}")]
    Input { what: String, source: ImageError },
    #[error("cannot encode cue payload: {0}")]
    Encode(String),
}
