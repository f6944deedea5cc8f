//! Turns parsed clauses into ordered steps: resolves "it"/"them"/"inside" against earlier
//! clauses and merges "pick up X" with a following "place it ...".

use super::clause::{Action, Clause, Entity, Np};
use super::relation::Relation;
use super::{ParseError, Step};

/// Entities mentioned so far, clause by clause.
struct History {
    clauses: Vec<Vec<Entity>>,
}

impl History {
    /// "it": the entity mentioned last in an earlier clause.
    fn last(&self) -> Option<&Entity> {
        self.clauses.iter().rev().find_map(|c| c.last())
    }

    /// "them": every entity of the previous clause.
    fn previous_clause(&self) -> Option<&[Entity]> {
        self.clauses.last().map(Vec::as_slice).filter(|c| !c.is_empty())
    }
}

fn unresolved(instruction: &str, clause: &Clause, what: &str) -> ParseError {
    ParseError {
        instruction: instruction.to_string(),
        position: clause.start,
        expected: format!("an earlier object for '{what}' to refer to"),
        found: "none".into(),
    }
}

fn resolve_one(instruction: &str, clause: &Clause, history: &History, np: &Np) -> Result<Vec<Entity>, ParseError> {
    match np {
        Np::Named(e) => Ok(vec![e.clone()]),
        Np::It => history.last().cloned().map(|e| vec![e]).ok_or_else(|| unresolved(instruction, clause, "it")),
        Np::Them => {
            history.previous_clause().map(<[Entity]>::to_vec).ok_or_else(|| unresolved(instruction, clause, "them"))
        }
    }
}

fn step(source: &Entity, relation: Relation, target: Option<&Entity>) -> Step {
    Step {
        source: source.name.clone(),
        source_qualifier: source.qualifier.clone(),
        relation,
        target: target.map(|t| match &t.qualifier {
            Some(q) => format!("{} {}", t.name, q),
            None => t.name.clone(),
        }),
        source_id: None,
        target_id: None,
    }
}

/// Resolves pronouns and builds the step list (never empty for a successful parse).
pub fn resolve(instruction: &str, clauses: Vec<Clause>) -> Result<Vec<Step>, ParseError> {
    let mut history = History { clauses: Vec::new() };
    let mut steps = Vec::new();
    // The object of a "pick up X" clause, waiting for a "place it ..." clause.
    let mut held: Option<Entity> = None;
    for clause in &clauses {
        let mut mentioned = Vec::new();
        match &clause.action {
            Action::Grasp(np) => {
                if let Some(previous) = held.take() {
                    steps.push(step(&previous, Relation::PickUp, None));
                }
                let mut objects = resolve_one(instruction, clause, &history, np)?;
                held = objects.pop();
                mentioned.extend(held.clone());
            }
            Action::Place { objects, relation, target } => {
                let mut sources = Vec::new();
                for np in objects {
                    sources.extend(resolve_one(instruction, clause, &history, np)?);
                }
                let target = match target {
                    Some(np) => resolve_one(instruction, clause, &history, np)?.pop(),
                    None => Some(history.last().cloned().ok_or_else(|| unresolved(instruction, clause, "inside"))?),
                };
                // "pick up X and place it ...": the held object is the source of this step.
                if let Some(previous) = held.take()
                    && !sources.contains(&previous)
                {
                    steps.push(step(&previous, Relation::PickUp, None));
                }
                for source in &sources {
                    // "pick up the bowl and put it in them": a thing is never its own target.
                    if target.as_ref().is_some_and(|t| t.name == source.name && t.qualifier == source.qualifier) {
                        return Err(ParseError {
                            instruction: instruction.to_string(),
                            position: clause.start,
                            expected: format!("a target other than the {} itself", source.name),
                            found: format!("the {} as its own target", source.name),
                        });
                    }
                    steps.push(step(source, *relation, target.as_ref()));
                }
                mentioned.extend(sources);
                mentioned.extend(target);
            }
            Action::State { relation, object } => {
                if let Some(previous) = held.take() {
                    steps.push(step(&previous, Relation::PickUp, None));
                }
                for entity in resolve_one(instruction, clause, &history, object)? {
                    steps.push(step(&entity, *relation, None));
                    mentioned.push(entity);
                }
            }
        }
        history.clauses.push(mentioned);
    }
    if let Some(previous) = held.take() {
        steps.push(step(&previous, Relation::PickUp, None));
    }
    Ok(steps)
}
