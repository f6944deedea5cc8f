//! Links parsed steps to goal atoms such as `(On akita_black_bowl_1 plate_1)`.
//!
//! Cue insertion needs simulator bodies to project, and the instruction only names them
//! loosely ("black bowl" for `akita_black_bowl_1`, "top drawer of the cabinet" for
//! `wooden_cabinet_1_top_region`). Each (step, atom) pair is scored by the words the step's
//! names share with the atom's arguments; pairs are taken best first, each step and atom at
//! most once, so "white mug" and "yellow and white mug" end up on the right mugs.

use serde::{Deserialize, Serialize};
use std::str::FromStr;

use super::Step;
use super::relation::Relation;

/// A goal predicate as LIBERO writes it: `On`, `In`, `Open`, `Close`, `Turnon`, `Turnoff`
/// with body or region names as arguments.
///
/// Read from JSON (a task description's `goals`) with the same checks as from text.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "RawGoalAtom")]
pub struct GoalAtom {
    pub predicate: String,
    pub args: Vec<String>,
}

/// A goal atom's JSON fields before [`check_arity`].
#[derive(Deserialize)]
struct RawGoalAtom {
    predicate: String,
    args: Vec<String>,
}

impl TryFrom<RawGoalAtom> for GoalAtom {
    type Error = String;

    fn try_from(raw: RawGoalAtom) -> Result<GoalAtom, String> {
        let shown = format!("({} {})", raw.predicate, raw.args.join(" "));
        if raw.predicate.contains(|c: char| c.is_whitespace() || c == '(' || c == ')')
            || raw.args.iter().any(|a| a.is_empty() || a.contains(|c: char| c.is_whitespace() || c == '(' || c == ')'))
        {
            return Err(format!("goal atom {shown:?}: a predicate and arguments are single names"));
        }
        check_arity(&shown, &raw.predicate, raw.args.len())?;
        Ok(GoalAtom { predicate: raw.predicate, args: raw.args })
    }
}

/// One of the predicates a goal can link to, with its number of arguments.
fn check_arity(shown: &str, predicate: &str, args: usize) -> Result<(), String> {
    let arity = match predicate.to_ascii_lowercase().as_str() {
        "on" | "in" => 2,
        "open" | "close" | "turnon" | "turnoff" => 1,
        _ => return Err(format!("goal atom {shown:?}: unknown predicate {predicate:?} (expected On, In, Open, Close, TurnOn or TurnOff)")),
    };
    if args != arity {
        return Err(format!("goal atom {shown:?}: {predicate} takes {arity} argument{}, found {args}", if arity == 1 { "" } else { "s" }));
    }
    Ok(())
}

impl GoalAtom {
    pub fn new(predicate: &str, args: &[&str]) -> GoalAtom {
        GoalAtom { predicate: predicate.to_string(), args: args.iter().map(|a| a.to_string()).collect() }
    }
}

/// Parses `(On akita_black_bowl_1 plate_1)` (parentheses optional, but balanced), with one of
/// the predicates a goal can link to and its number of arguments.
impl FromStr for GoalAtom {
    type Err = String;

    fn from_str(s: &str) -> Result<GoalAtom, String> {
        let trimmed = s.trim();
        let one_atom = || format!("goal atom {s:?}: expected one (Predicate arg ...) with nothing before or after it");
        let inner = match trimmed.strip_prefix('(') {
            Some(rest) => match rest.find(')') {
                None => return Err(format!("goal atom {s:?}: a '(' without its closing ')'")),
                Some(end) if end + 1 == rest.len() => &rest[..end],
                Some(_) => return Err(one_atom()),
            },
            None => trimmed,
        };
        if inner.contains(['(', ')']) {
            return Err(one_atom());
        }
        let mut words = inner.split_whitespace();
        let predicate =
            words.next().ok_or_else(|| format!("goal atom {s:?}: expected a predicate name, found nothing"))?;
        let args: Vec<String> = words.map(str::to_string).collect();
        check_arity(s, predicate, args.len())?;
        Ok(GoalAtom { predicate: predicate.to_string(), args })
    }
}

/// Which relations a goal predicate can stand for.
fn predicate_fits(predicate: &str, relation: Relation) -> bool {
    match predicate.to_ascii_lowercase().as_str() {
        "on" | "in" => relation.moves_source(),
        "open" => relation == Relation::Open,
        "close" => relation == Relation::Close,
        "turnon" => relation == Relation::TurnOn,
        "turnoff" => relation == Relation::TurnOff,
        _ => false,
    }
}

/// Extra words for instruction names that LIBERO's body names spell differently.
const ALIASES: &[(&str, &str)] = &[("white mug", "porcelain"), ("frying pan", "frypan"), ("pan", "frypan")];

fn singular(word: &str) -> &str {
    if word.len() > 3 && word.ends_with('s') && !word.ends_with("ss") { &word[..word.len() - 1] } else { word }
}

fn name_words(name: &str) -> Vec<String> {
    let mut words: Vec<String> = name
        .split(' ')
        .filter(|w| !matches!(*w, "the" | "of" | "a" | "an" | "and"))
        .map(|w| singular(w).to_string())
        .collect();
    words.extend(ALIASES.iter().filter(|(phrase, _)| *phrase == name).map(|(_, extra)| extra.to_string()));
    words
}

fn id_words(id: &str) -> Vec<&str> {
    id.split('_').filter(|w| !w.chars().all(|c| c.is_ascii_digit())).map(singular).collect()
}

fn overlap(name: &str, id: &str) -> usize {
    let ids = id_words(id);
    name_words(name).iter().filter(|w| ids.contains(&w.as_str())).count()
}

/// How well `atom` describes `step`; `None` when it cannot.
fn score(step: &Step, atom: &GoalAtom) -> Option<usize> {
    if !predicate_fits(&atom.predicate, step.relation) {
        return None;
    }
    let source = overlap(&step.source, atom.args.first()?);
    if source == 0 {
        return None;
    }
    match (&step.target, atom.args.get(1)) {
        (Some(target), Some(id)) => {
            let t = overlap(target, id);
            (t > 0).then_some(source + t)
        }
        _ => Some(source),
    }
}

fn is_plural(name: &str) -> bool {
    name.rsplit(' ').next().is_some_and(|w| singular(w) != w)
}

/// Fills `source_id`/`target_id` from the best-matching atoms and splits plural steps.
pub fn ground(steps: Vec<Step>, goals: &[GoalAtom]) -> Vec<Step> {
    let mut pairs: Vec<(usize, usize, usize)> = Vec::new();
    for (s, step) in steps.iter().enumerate() {
        for (a, atom) in goals.iter().enumerate() {
            if let Some(points) = score(step, atom) {
                pairs.push((points, s, a));
            }
        }
    }
    // Best score first; ties in instruction order, then goal order.
    pairs.sort_by(|x, y| y.0.cmp(&x.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut atom_used = vec![false; goals.len()];
    let mut matched: Vec<Vec<usize>> = vec![Vec::new(); steps.len()];
    for &(_, s, a) in &pairs {
        let plural_extra = is_plural(&steps[s].source) && !matched[s].is_empty();
        if !atom_used[a] && (matched[s].is_empty() || plural_extra) {
            atom_used[a] = true;
            matched[s].push(a);
        }
    }
    let mut out = Vec::with_capacity(steps.len());
    for (step, atoms) in steps.into_iter().zip(matched) {
        if atoms.is_empty() {
            out.push(step);
            continue;
        }
        let mut atoms = atoms;
        atoms.sort_unstable();
        for a in atoms {
            let mut grounded = step.clone();
            grounded.source_id = goals[a].args.first().cloned();
            grounded.target_id = goals[a].args.get(1).cloned().filter(|_| step.target.is_some());
            out.push(grounded);
        }
    }
    out
}

/// Without goal atoms: links each step's source and target to the scene name (object or
/// fixture, e.g. `akita_black_bowl_1`) sharing the most words with it; ties go to the name
/// listed first. Names sharing no word leave the id empty.
pub fn ground_to_names(steps: &mut [Step], names: &[&str]) {
    let best = |phrase: &str| -> Option<String> {
        let mut best: Option<(usize, &str)> = None;
        for n in names {
            let score = overlap(phrase, n);
            if score > 0 && best.is_none_or(|(b, _)| score > b) {
                best = Some((score, n));
            }
        }
        best.map(|(_, n)| n.to_string())
    };
    for step in steps {
        step.source_id = best(&step.source);
        step.target_id = step.target.as_deref().and_then(best);
    }
}
