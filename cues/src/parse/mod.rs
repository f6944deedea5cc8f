//! Rule-based task parser: instruction (+ optional goal atoms) → ordered steps of
//! (source, relation, target).
//!
//! The paper's cue specification needs the manipulated object `e_src`, the target object or
//! region `e_tgt` and the relation `r_task`. LIBERO instructions come from a small grammar
//! ("pick up X and place it on Y", "put both X and Y in Z", "open X", "turn on X and put Y on
//! it", ...), so a hand-written clause parser covers all 130 LIBERO instructions without a
//! language model, gives the same answer every time and says exactly where it got stuck.
//!
//! Pipeline: `text` normalises and tokenises, `clause` splits the instruction into verb
//! clauses and parses each into an action, `steps` resolves pronouns and merges
//! "pick up X" + "place it ..." into one step, `ground` optionally links each step to the
//! goal atoms (`On akita_black_bowl_1 plate_1`) so callers know which simulator bodies to
//! anchor cues on.

mod clause;
mod ground;
mod relation;
mod steps;
mod text;

pub use ground::{GoalAtom, ground_to_names};
pub use relation::Relation;
pub use text::instruction_from_task_name;

use serde::{Deserialize, Serialize};

/// One thing the robot must achieve, in instruction order.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Step {
    /// The manipulated object (or, for state changes, the fixture acted on), as written in
    /// the instruction without its article: "black bowl", "middle drawer of the cabinet".
    pub source: String,
    /// A locating phrase that picks out which source is meant: "between the plate and the
    /// ramekin", "at the back", "on the left".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source_qualifier: Option<String>,
    pub relation: Relation,
    /// The target object or region ("plate", "top drawer of the cabinet", "front of the
    /// stove"); `None` for relations without one (open, close, turn on/off, pick up).
    #[serde(default)]
    pub target: Option<String>,
    /// Goal-atom argument naming the source body (only when goal atoms were given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source_id: Option<String>,
    /// Goal-atom argument naming the target body or region (only when goal atoms were given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_id: Option<String>,
}

/// The parse of one instruction. `source`, `target` and `relation` repeat the primary (first)
/// step so a consumer that only needs the main intent does not have to index `steps`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ParsedTask {
    /// The normalised instruction (lower case, single spaces).
    pub instruction: String,
    pub source: String,
    /// `null` in JSON when the relation has no target, so the key is always present.
    #[serde(default)]
    pub target: Option<String>,
    pub relation: Relation,
    pub steps: Vec<Step>,
}

impl ParsedTask {
    fn from_steps(instruction: String, steps: Vec<Step>) -> ParsedTask {
        let primary = &steps[0];
        ParsedTask {
            source: primary.source.clone(),
            target: primary.target.clone(),
            relation: primary.relation,
            instruction,
            steps,
        }
    }

    /// The first step, which the cue specification uses as (e_src, r_task, e_tgt).
    pub fn primary(&self) -> &Step {
        &self.steps[0]
    }

    /// True when some step moves its source object to a target (so an object trajectory,
    /// and hence a ghost cue, exists).
    pub fn moves_an_object(&self) -> bool {
        self.steps.iter().any(|s| s.relation.moves_source())
    }
}

/// Why an instruction could not be parsed. `position` is a character offset into the
/// normalised instruction (lower case, single spaces), which the message repeats.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("cannot parse instruction {instruction:?} at character {position}: expected {expected}, found {found}")]
pub struct ParseError {
    pub instruction: String,
    pub position: usize,
    pub expected: String,
    pub found: String,
}

/// Parses an instruction such as "put the black bowl in the bottom drawer of the cabinet and
/// close it" into ordered steps.
pub fn parse(instruction: &str) -> Result<ParsedTask, ParseError> {
    let normalised = text::normalise(instruction)?;
    let tokens = text::tokenise(&normalised);
    let clauses = clause::split_and_parse(&normalised, &tokens)?;
    let steps = steps::resolve(&normalised, clauses)?;
    Ok(ParsedTask::from_steps(normalised, steps))
}

/// Like [`parse`], then links each step to the goal atoms (`(On akita_black_bowl_1 plate_1)`)
/// by word overlap. A plural source ("both moka pots") that matches several atoms is split
/// into one step per atom. Atoms that match no step are ignored.
pub fn parse_with_goals(instruction: &str, goals: &[GoalAtom]) -> Result<ParsedTask, ParseError> {
    let parsed = parse(instruction)?;
    let steps = ground::ground(parsed.steps, goals);
    Ok(ParsedTask::from_steps(parsed.instruction, steps))
}

#[cfg(test)]
mod tests;
