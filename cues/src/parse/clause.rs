//! Splits an instruction into verb clauses and parses each clause into an [`Action`].
//!
//! A new clause starts at "and" followed by a verb ("... the bowl and close it"), so
//! "yellow and white mug", "between the plate and the ramekin" and "both X and Y" stay inside
//! their noun phrase.

use super::ParseError;
use super::relation::Relation;
use super::text::Token;

/// A noun phrase: a named entity or a pronoun to be resolved against earlier clauses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Np {
    Named(Entity),
    /// "it": the entity mentioned last in an earlier clause.
    It,
    /// "them": every entity of the previous clause.
    Them,
}

/// A named entity: its name as written (without article) and an optional locating phrase.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entity {
    pub name: String,
    pub qualifier: Option<String>,
}

/// What one clause asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Action {
    /// "pick up X": merged with a following "place it ..." into one step.
    Grasp(Np),
    /// "put X on Y", "put both X and Y in Z", "push X to Y", "put X inside" (target `None`:
    /// the entity mentioned last).
    Place { objects: Vec<Np>, relation: Relation, target: Option<Np> },
    /// "open X", "close X", "turn on X", "turn off X".
    State { relation: Relation, object: Np },
}

/// Words that start a clause.
const VERBS: &[&str] =
    &["put", "place", "pick", "lift", "open", "close", "turn", "switch", "push", "stack", "move", "set"];

/// Multi-word placement prepositions, longest first so "on top of" wins over "on".
const PLACEMENT_PREPOSITIONS: &[(&[&str], Relation)] = &[
    (&["to", "the", "left", "of"], Relation::LeftOf),
    (&["to", "the", "right", "of"], Relation::RightOf),
    (&["to", "the", "front", "of"], Relation::FrontOf),
    (&["to", "the", "back", "of"], Relation::Behind),
    (&["on", "the", "left", "of"], Relation::LeftOf),
    (&["on", "the", "right", "of"], Relation::RightOf),
    (&["in", "front", "of"], Relation::FrontOf),
    (&["on", "top", "of"], Relation::On),
    (&["next", "to"], Relation::NextTo),
    (&["onto"], Relation::On),
    (&["on"], Relation::On),
    (&["into"], Relation::In),
    (&["inside"], Relation::In),
    (&["in"], Relation::In),
    (&["under"], Relation::Under),
    (&["underneath"], Relation::Under),
    (&["below"], Relation::Under),
    (&["behind"], Relation::Behind),
    (&["beside"], Relation::NextTo),
];

/// Position phrases that belong to the preceding noun ("the butter at the back"), not to the
/// placement. They count only when the noun phrase ends right after them.
const POSITION_QUALIFIERS: &[&[&str]] = &[
    &["at", "the", "back"],
    &["at", "the", "front"],
    &["at", "the", "left"],
    &["at", "the", "right"],
    &["in", "the", "middle"],
    &["in", "the", "center"],
    &["on", "the", "left"],
    &["on", "the", "right"],
];

/// Words that begin a locating phrase inside a noun phrase ("black bowl next to the plate").
const LOCATING_WORDS: &[&str] =
    &["between", "next", "on", "in", "from", "at", "near", "beside", "behind", "under", "inside"];

const ARTICLES: &[&str] = &["the", "a", "an"];

/// A parsed clause and where it starts in the instruction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Clause {
    pub action: Action,
    pub start: usize,
}

/// Splits the token stream at "and <verb>" and parses every clause.
pub fn split_and_parse(instruction: &str, tokens: &[Token<'_>]) -> Result<Vec<Clause>, ParseError> {
    let mut clauses = Vec::new();
    let mut begin = 0;
    for i in 0..=tokens.len() {
        let boundary =
            i == tokens.len() || (tokens[i].word == "and" && tokens.get(i + 1).is_none_or(|t| VERBS.contains(&t.word)));
        if boundary {
            clauses.push(parse_clause(instruction, &tokens[begin..i])?);
            begin = i + 1;
        }
    }
    Ok(clauses)
}

fn error(instruction: &str, position: usize, expected: &str, found: &str) -> ParseError {
    ParseError {
        instruction: instruction.to_string(),
        position,
        expected: expected.to_string(),
        found: found.to_string(),
    }
}

fn found_at(tokens: &[Token<'_>], i: usize) -> String {
    tokens.get(i).map_or_else(|| "the end of the clause".to_string(), |t| format!("'{}'", t.word))
}

fn position_at(instruction: &str, tokens: &[Token<'_>], i: usize) -> usize {
    tokens.get(i).map_or(instruction.len(), |t| t.start)
}

fn parse_clause(instruction: &str, tokens: &[Token<'_>]) -> Result<Clause, ParseError> {
    let Some(first) = tokens.first() else {
        return Err(error(instruction, instruction.len(), "a verb after 'and'", "the end of the instruction"));
    };
    let start = first.start;
    let action = match first.word {
        "pick" | "lift" => {
            let skip = if first.word == "pick" { expect_word(instruction, tokens, 1, "up")? } else { 1 };
            Action::Grasp(noun_phrase(instruction, tokens, skip, tokens.len())?)
        }
        "open" => {
            Action::State { relation: Relation::Open, object: noun_phrase(instruction, tokens, 1, tokens.len())? }
        }
        "close" => {
            Action::State { relation: Relation::Close, object: noun_phrase(instruction, tokens, 1, tokens.len())? }
        }
        "turn" | "switch" => parse_turn(instruction, tokens)?,
        "push" => parse_place(instruction, tokens, Some(Relation::PushTo))?,
        "put" | "place" | "stack" | "move" | "set" => parse_place(instruction, tokens, None)?,
        other => {
            return Err(error(
                instruction,
                start,
                "a verb (put, place, pick up, stack, push, open, close, turn on, turn off)",
                &format!("'{other}'"),
            ));
        }
    };
    Ok(Clause { action, start })
}

/// Checks that `tokens[at]` is `word` and returns the index after it.
fn expect_word(instruction: &str, tokens: &[Token<'_>], at: usize, word: &str) -> Result<usize, ParseError> {
    if tokens.get(at).is_some_and(|t| t.word == word) {
        Ok(at + 1)
    } else {
        Err(error(instruction, position_at(instruction, tokens, at), &format!("'{word}'"), &found_at(tokens, at)))
    }
}

/// "turn on X", "turn off X", "turn X on", "switch off X".
fn parse_turn(instruction: &str, tokens: &[Token<'_>]) -> Result<Action, ParseError> {
    let relation_of = |w: &str| match w {
        "on" => Some(Relation::TurnOn),
        "off" => Some(Relation::TurnOff),
        _ => None,
    };
    if let Some(relation) = tokens.get(1).and_then(|t| relation_of(t.word)) {
        return Ok(Action::State { relation, object: noun_phrase(instruction, tokens, 2, tokens.len())? });
    }
    match tokens.last().and_then(|t| relation_of(t.word)) {
        Some(relation) if tokens.len() > 2 => {
            Ok(Action::State { relation, object: noun_phrase(instruction, tokens, 1, tokens.len() - 1)? })
        }
        _ => Err(error(
            instruction,
            position_at(instruction, tokens, 1),
            "'on' or 'off' after 'turn'",
            &found_at(tokens, 1),
        )),
    }
}

/// Does `phrase` occur at `tokens[at..]`?
fn matches_at(tokens: &[Token<'_>], at: usize, phrase: &[&str]) -> bool {
    tokens.len() >= at + phrase.len() && phrase.iter().zip(&tokens[at..]).all(|(p, t)| *p == t.word)
}

fn placement_preposition_at(tokens: &[Token<'_>], at: usize) -> Option<(usize, Relation)> {
    PLACEMENT_PREPOSITIONS
        .iter()
        .find(|(phrase, _)| matches_at(tokens, at, phrase))
        .map(|(phrase, r)| (phrase.len(), *r))
}

/// Length of a position qualifier at `at` that ends its noun phrase (followed by the end, by
/// a placement preposition or by "and").
fn position_qualifier_at(tokens: &[Token<'_>], at: usize) -> Option<usize> {
    POSITION_QUALIFIERS.iter().find_map(|phrase| {
        if !matches_at(tokens, at, phrase) {
            return None;
        }
        let end = at + phrase.len();
        let ends_phrase =
            end == tokens.len() || tokens[end].word == "and" || placement_preposition_at(tokens, end).is_some();
        ends_phrase.then_some(phrase.len())
    })
}

/// "put [both] X [and Y] PREP Z"; `forced` is the relation implied by the verb ("push").
fn parse_place(instruction: &str, tokens: &[Token<'_>], forced: Option<Relation>) -> Result<Action, ParseError> {
    let verb = tokens[0].word;
    let mut begin = 1;
    let both = tokens.get(1).is_some_and(|t| t.word == "both");
    if both {
        begin = 2;
    }
    // Find the preposition that separates the objects from the target.
    let mut at = begin + 1;
    let split = loop {
        if at >= tokens.len() {
            break None;
        }
        if let Some(len) = position_qualifier_at(tokens, at) {
            at += len;
            continue;
        }
        if forced == Some(Relation::PushTo) && tokens[at].word == "to" {
            break Some((at, 1, Relation::PushTo));
        }
        if let Some((len, relation)) = placement_preposition_at(tokens, at) {
            break Some((at, len, forced.unwrap_or(relation)));
        }
        at += 1;
    };
    let Some((prep_at, prep_len, relation)) = split else {
        let expected = if forced == Some(Relation::PushTo) {
            "'to <target>' after the pushed object".to_string()
        } else {
            format!("a placement preposition (on, in, under, to the left of, ...) after '{verb} <object>'")
        };
        return Err(error(instruction, instruction.len(), &expected, "the end of the clause"));
    };
    if prep_at <= begin {
        return Err(error(
            instruction,
            position_at(instruction, tokens, begin),
            &format!("an object after '{verb}'"),
            &found_at(tokens, begin),
        ));
    }
    let objects = if both {
        split_conjunction(instruction, tokens, begin, prep_at)?
    } else {
        vec![noun_phrase(instruction, tokens, begin, prep_at)?]
    };
    let target_begin = prep_at + prep_len;
    // "... on the plate and the mug on the plate": a second placement without its verb would
    // otherwise be read as part of the target's name.
    if let Some(at) = (target_begin..tokens.len()).find(|&i| {
        tokens[i].word == "and"
            && tokens.get(i + 1).is_some_and(|t| ARTICLES.contains(&t.word))
            && (i + 2..tokens.len()).any(|j| placement_preposition_at(tokens, j).is_some())
    }) {
        return Err(error(
            instruction,
            position_at(instruction, tokens, at + 1),
            &format!("a verb after 'and' to start the next step ('and {verb} the ...')"),
            &found_at(tokens, at + 1),
        ));
    }
    let target = if target_begin == tokens.len() && relation == Relation::In {
        None // "put the bowl inside": into the entity mentioned last
    } else {
        Some(noun_phrase(instruction, tokens, target_begin, tokens.len())?)
    };
    Ok(Action::Place { objects, relation, target })
}

/// "the alphabet soup and the tomato sauce" → two noun phrases. Splits at "and" followed by
/// an article, else at the last "and" ("both moka pots" has none and stays one phrase).
fn split_conjunction(instruction: &str, tokens: &[Token<'_>], begin: usize, end: usize) -> Result<Vec<Np>, ParseError> {
    let ands: Vec<usize> = (begin..end).filter(|&i| tokens[i].word == "and").collect();
    let at = ands
        .iter()
        .copied()
        .find(|&i| tokens.get(i + 1).is_some_and(|t| ARTICLES.contains(&t.word)))
        .or_else(|| ands.last().copied());
    match at {
        Some(at) => {
            // "both" names two things: a third "and <article>" after the split is one too many.
            if let Some(extra) = (at + 1..end).find(|&i| tokens[i].word == "and" && tokens.get(i + 1).is_some_and(|t| ARTICLES.contains(&t.word))) {
                return Err(error(instruction, position_at(instruction, tokens, extra), "two objects after 'both'", "a third"));
            }
            Ok(vec![noun_phrase(instruction, tokens, begin, at)?, noun_phrase(instruction, tokens, at + 1, end)?])
        }
        None => Ok(vec![noun_phrase(instruction, tokens, begin, end)?]),
    }
}

/// Parses `tokens[begin..end]` as a noun phrase: article, name, optional locating phrase.
fn noun_phrase(instruction: &str, tokens: &[Token<'_>], begin: usize, end: usize) -> Result<Np, ParseError> {
    let mut begin = begin;
    while begin < end && ARTICLES.contains(&tokens[begin].word) {
        begin += 1;
    }
    if begin >= end {
        return Err(error(
            instruction,
            position_at(instruction, tokens, begin),
            "an object name",
            &found_at(tokens, begin.min(end)),
        ));
    }
    let words: Vec<&str> = tokens[begin..end].iter().map(|t| t.word).collect();
    match words.as_slice() {
        ["it"] => return Ok(Np::It),
        ["them"] => return Ok(Np::Them),
        _ => {}
    }
    let cut = (1..words.len())
        .find(|&i| LOCATING_WORDS.contains(&words[i]) && !(words[i] == "next" && words.get(i + 1) != Some(&"to")));
    let (name, qualifier) = match cut {
        Some(i) => (words[..i].join(" "), Some(words[i..].join(" "))),
        None => (words.join(" "), None),
    };
    Ok(Np::Named(Entity { name, qualifier }))
}
