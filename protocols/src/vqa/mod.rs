//! Part I-A: image-based visual cue understanding as multiple-choice questions.
//!
//! - [`generate`](mod@generate): four questions per cue instance (detection, semantic, grounding,
//!   decision), family-specific wording (`wording`), distractors from the scene's objects
//!   and fixtures, the answer letter balanced over A–D.
//! - [`files`]: `questions.jsonl` + PNG images for a VLM, and prediction files back.
//! - [`extract`]: VLMEvalKit's answer extraction (letter, then option text; refusals are Z).
//! - [`score`](mod@score): accuracy per stage, per family, and full-chain accuracy (FCA).
//! - [`answerers`]: the oracle and the text-only (blind) baselines.
//! - `client` (feature `net`): an OpenAI-compatible chat client (vLLM, SGLang) answering the questions.

pub mod answerers;
#[cfg(feature = "net")]
pub mod client;
pub mod extract;
pub mod files;
pub mod generate;
pub mod score;
mod wording;

use serde::{Deserialize, Serialize};
use thiserror::Error;
use vifo_cues::Family;

pub use generate::{Scene, SceneEntity, generate};
pub use score::{Accuracy, VqaScores, mean_rate, score};

/// The four question stages of Part I-A, in the paper's order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Is there a cue, and of which kind?
    Detection,
    /// What does it convey?
    Semantic,
    /// Which object in the scene does it refer to?
    Grounding,
    /// What should the robot do?
    Decision,
}

impl Stage {
    pub const ALL: [Stage; 4] = [Stage::Detection, Stage::Semantic, Stage::Grounding, Stage::Decision];

    pub fn name(self) -> &'static str {
        match self {
            Stage::Detection => "detection",
            Stage::Semantic => "semantic",
            Stage::Grounding => "grounding",
            Stage::Decision => "decision",
        }
    }

    /// Column header of Table 1.
    pub fn short(self) -> &'static str {
        match self {
            Stage::Detection => "Det",
            Stage::Semantic => "Sem",
            Stage::Grounding => "Gnd",
            Stage::Decision => "Dec",
        }
    }
}

/// The option letters.
pub const LETTERS: [char; 4] = ['A', 'B', 'C', 'D'];

/// One multiple-choice question (one line of `questions.jsonl`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Question {
    /// `<instance id>/<stage>`.
    pub id: String,
    pub instance_id: String,
    pub family: Family,
    pub stage: Stage,
    /// Image path relative to the export folder.
    pub image: String,
    pub question: String,
    /// Exactly four options, A to D.
    pub options: Vec<String>,
    /// The correct letter.
    pub answer: String,
}

/// A model's raw answer to one question (one line of a predictions file).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    pub id: String,
    pub prediction: String,
}

/// Why questions could not be made, written, read or answered.
#[derive(Debug, Error)]
pub enum VqaError {
    #[error("instance {instance}: no scene given for task {task}")]
    MissingScene { instance: String, task: String },
    #[error("instance {0}: {1}")]
    BadInstance(String, String),
    #[error("instance {0} appears twice")]
    DuplicateInstance(String),
    #[error("{path}: {source}")]
    Io { path: std::path::PathBuf, source: std::io::Error },
    #[error("{0}: no such file (`vifo vqa export --out DIR` writes the questions)")]
    NoQuestions(std::path::PathBuf),
    #[error("{0} holds no questions")]
    EmptyQuestions(std::path::PathBuf),
    #[error("{path}:{line}: {message}")]
    BadLine { path: std::path::PathBuf, line: usize, message: String },
    #[error("image for {instance}: {message}")]
    Image { instance: String, message: String },
    #[error("{0}")]
    Client(String),
}

impl VqaError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> VqaError {
        VqaError::Io { path: path.to_path_buf(), source }
    }
}
