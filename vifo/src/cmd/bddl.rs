//! `vifo bddl FILE... [--json]`: parse LIBERO BDDL files and show the tasks they define.

use anyhow::bail;
use clap::Args as ClapArgs;
use serde::Serialize;
use std::path::PathBuf;
use vifo_scenes::Task;
use vifo_scenes::bddl::{self, BddlError};

#[derive(ClapArgs)]
pub struct Args {
    /// BDDL files to parse.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Print one JSON document {"tasks": [...], "errors": [...]} instead of text.
    #[arg(long)]
    json: bool,
}

/// Why one file could not be read as a task.
enum Failure {
    Unreadable { file: String, message: String },
    Malformed(BddlError),
}

/// A failure in the `--json` report; position fields only for malformed files.
#[derive(Serialize)]
struct FailureJson<'a> {
    file: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    line: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    column: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    expected: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    found: Option<&'a str>,
    message: String,
}

#[derive(Serialize)]
struct Report<'a> {
    tasks: Vec<&'a Task>,
    errors: Vec<FailureJson<'a>>,
}

impl Failure {
    fn to_json(&self) -> FailureJson<'_> {
        match self {
            Failure::Unreadable { file, message } => FailureJson {
                file,
                line: None,
                column: None,
                expected: None,
                found: None,
                message: message.clone(),
            },
            Failure::Malformed(err) => FailureJson {
                file: &err.file,
                line: Some(err.line),
                column: Some(err.column),
                expected: Some(&err.expected),
                found: Some(&err.found),
                message: err.to_string(),
            },
        }
    }

    fn message(&self) -> String {
        match self {
            Failure::Unreadable { file, message } => format!("{file}: {message}"),
            Failure::Malformed(err) => err.to_string(),
        }
    }
}

/// Parses every file, reports all of them, and fails if any did not parse.
pub fn run(args: Args) -> anyhow::Result<()> {
    let mut tasks = Vec::new();
    let mut failures = Vec::new();
    for path in &args.files {
        match vifo_protocols::text_file::read(path) {
            Err(err) => failures.push(Failure::Unreadable { file: path.display().to_string(), message: err.to_string() }),
            Ok(text) => match bddl::parse(&text, path) {
                Ok(task) => tasks.push((path, task)),
                Err(err) => failures.push(Failure::Malformed(err)),
            },
        }
    }
    if args.json {
        let report = Report {
            tasks: tasks.iter().map(|(_, task)| task).collect(),
            errors: failures.iter().map(Failure::to_json).collect(),
        };
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        for (path, task) in &tasks {
            print!("{}", describe(&path.display().to_string(), task));
        }
        for failure in &failures {
            eprintln!("{}", failure.message());
        }
    }
    if !failures.is_empty() {
        bail!("{} of {} files did not parse", failures.len(), args.files.len());
    }
    Ok(())
}

/// The readable text form of one task.
fn describe(file: &str, task: &Task) -> String {
    let mut out = format!("{file}\n");
    let mut line = |key: &str, value: &str| out.push_str(&format!("  {key:<16}{value}\n"));
    line("problem", task.problem.name());
    line("instruction", &task.instruction);
    line("language", &task.language);
    let entities = |list: &[vifo_scenes::task::Entity]| {
        list.iter().map(|e| format!("{} ({})", e.name, e.category)).collect::<Vec<_>>().join(", ")
    };
    line("fixtures", &entities(&task.fixtures));
    line("objects", &entities(&task.objects));
    line("obj_of_interest", &task.obj_of_interest.join(", "));
    out.push_str("  regions\n");
    for region in &task.regions {
        let mut text = format!("    {}", region.key);
        if region.ranges.is_empty() {
            text.push_str(&format!("  site of {}", region.target));
        }
        for [x0, y0, x1, y1] in &region.ranges {
            text.push_str(&format!("  x [{x0}, {x1}] y [{y0}, {y1}]"));
        }
        if let Some([a, b]) = region.yaw_rotation {
            text.push_str(&format!("  yaw [{a}, {b}]"));
        }
        if let Some([r, g, b, a]) = region.rgba {
            text.push_str(&format!("  rgba ({r} {g} {b} {a})"));
        }
        out.push_str(&text);
        out.push('\n');
    }
    for (title, atoms) in [("init", &task.init), ("goal", &task.goal)] {
        out.push_str(&format!("  {title}\n"));
        for atom in atoms {
            out.push_str(&format!("    {atom}\n"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn text_form_lists_every_part() {
        let text = "(define (problem LIBERO_Floor_Manipulation) (:language Lift it)
            (:regions (box_region (:target floor) (:ranges ((0 0.1 0.2 0.3))) (:yaw_rotation ((0 1)))))
            (:fixtures floor - floor) (:objects box_1 - box) (:obj_of_interest box_1)
            (:init (On box_1 floor_box_region)) (:goal (And (Up box_1))))";
        let task = bddl::parse(text, Path::new("lift_the_box.bddl")).unwrap();
        let shown = describe("lift_the_box.bddl", &task);
        for part in [
            "problem         LIBERO_Floor_Manipulation",
            "instruction     lift the box",
            "language        Lift it",
            "objects         box_1 (box)",
            "floor_box_region  x [0, 0.2] y [0.1, 0.3]  yaw [0, 1]",
            "(On box_1 floor_box_region)",
            "(Up box_1)",
        ] {
            assert!(shown.contains(part), "missing {part:?} in\n{shown}");
        }
    }

    #[test]
    fn reports_every_file_and_fails_if_any_did_not_parse() {
        let dir = std::env::temp_dir().join(format!("vifo-bddl-cmd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let good = dir.join("lift_the_box.bddl");
        std::fs::write(&good, "(define (problem LIBERO_Floor_Manipulation) (:fixtures floor - floor) (:objects box_1 - box) (:goal (Up box_1)))").unwrap();
        let bad = dir.join("broken.bddl");
        std::fs::write(&bad, "(define (problem LIBERO_Floor_Manipulation)").unwrap();
        let missing = dir.join("missing.bddl");
        let run_on = |files: Vec<PathBuf>, json: bool| run(Args { files, json });
        assert!(run_on(vec![good.clone()], false).is_ok());
        let err = run_on(vec![bad.clone(), good.clone(), missing.clone()], true).unwrap_err();
        assert_eq!(err.to_string(), "2 of 3 files did not parse");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
