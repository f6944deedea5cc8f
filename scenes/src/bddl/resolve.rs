//! Turns the raw parts into a [`Task`], checking names, predicates and arities.

use super::BddlError;
use super::grammar::{RawAtom, RawEntity, RawProblem, Word};
use super::lexer::Pos;
use crate::task::{Arity, Atom, Entity, Predicate, ProblemClass, Region, Task, instruction_from_file_name};

pub fn resolve(raw: RawProblem<'_>, name: &str, file: &str) -> Result<Task, BddlError> {
    let fail = |pos: Pos, expected: &str, found: String| BddlError {
        file: file.to_string(),
        line: pos.line,
        column: pos.column,
        expected: expected.to_string(),
        found,
    };

    let problem = ProblemClass::from_name(raw.problem.text).ok_or_else(|| {
        let known: Vec<&str> = ProblemClass::ALL.iter().map(|c| c.name()).collect();
        fail(
            raw.problem.pos,
            &format!("a LIBERO problem class ({})", known.join(", ")),
            format!("'{}'", raw.problem.text),
        )
    })?;

    // Names are unique across fixtures and objects: atoms refer to both the same way.
    let mut declared: Vec<(String, Pos)> = Vec::new();
    let mut entities = |raw: &[RawEntity<'_>]| -> Result<Vec<Entity>, BddlError> {
        raw.iter()
            .map(|e| {
                let name = e.name.ident();
                if let Some((_, first)) = declared.iter().find(|(n, _)| *n == name) {
                    let expected = format!("a name not declared before ('{name}' is declared at line {})", first.line);
                    return Err(fail(e.name.pos, &expected, format!("'{}' again", e.name.text)));
                }
                declared.push((name.clone(), e.name.pos));
                Ok(Entity { name, category: e.category.ident() })
            })
            .collect()
    };
    let fixtures = entities(&raw.fixtures)?;
    let objects = entities(&raw.objects)?;

    let mut regions: Vec<Region> = Vec::new();
    let mut region_lines: Vec<usize> = Vec::new();
    for r in &raw.regions {
        let target = r.target.ident();
        // LIBERO only makes sites for regions whose target exists; the others (libero_goal's
        // `bowl_drainer_1` regions) are silently ignored.
        if !fixtures.iter().chain(&objects).any(|e| e.name == target) {
            continue;
        }
        let region_name = r.name.ident();
        let key = format!("{target}_{region_name}");
        if let Some(i) = regions.iter().position(|existing| existing.key == key) {
            let expected = format!("a region key not defined before ('{key}' is defined at line {})", region_lines[i]);
            return Err(fail(r.name.pos, &expected, format!("'{}' for target '{}' again", r.name.text, r.target.text)));
        }
        region_lines.push(r.name.pos.line);
        regions.push(Region {
            key,
            name: region_name,
            target,
            ranges: r.ranges.clone(),
            yaw_rotation: r.yaw_rotation,
            rgba: r.rgba,
        });
    }

    let mut task = Task {
        suite: None,
        index: None,
        name: name.to_string(),
        instruction: instruction_from_file_name(name),
        language: raw.language,
        problem,
        fixtures,
        objects,
        regions,
        obj_of_interest: Vec::new(),
        init: Vec::new(),
        goal: Vec::new(),
    };

    let known = |task: &Task, word: &Word<'_>| task.resolve(&word.ident()).is_some();
    for word in &raw.obj_of_interest {
        if !known(&task, word) {
            return Err(fail(
                word.pos,
                "an object, fixture or region key in (:obj_of_interest",
                format!("'{}'", word.text),
            ));
        }
    }
    task.obj_of_interest = raw.obj_of_interest.iter().map(Word::ident).collect();

    let atom = |task: &Task, raw: &RawAtom<'_>| -> Result<Atom, BddlError> {
        let predicate = Predicate::from_name(raw.predicate.text).ok_or_else(|| {
            fail(
                raw.predicate.pos,
                &format!("a predicate LIBERO knows ({})", Predicate::known_names()),
                format!("'{}' in {}", raw.predicate.text, raw.text()),
            )
        })?;
        if let Arity::Exactly(n) = predicate.arity()
            && raw.args.len() != n
        {
            let plural = if n == 1 { "" } else { "s" };
            return Err(fail(
                raw.open,
                &format!("{n} argument{plural} for {predicate}"),
                format!("{} in {}", raw.args.len(), raw.text()),
            ));
        }
        for (i, arg) in raw.args.iter().enumerate() {
            if !known(task, arg) {
                return Err(fail(
                    arg.pos,
                    &format!("an object, fixture or region key as argument {} of {}", i + 1, raw.text()),
                    format!("'{}'", arg.text),
                ));
            }
        }
        Ok(Atom { predicate, args: raw.args.iter().map(Word::ident).collect() })
    };
    task.init = raw.init.iter().map(|a| atom(&task, a)).collect::<Result<_, _>>()?;
    task.goal = raw.goal.iter().map(|a| atom(&task, a)).collect::<Result<_, _>>()?;
    Ok(task)
}
