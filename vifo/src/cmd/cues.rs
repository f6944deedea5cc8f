//! `vifo cues`: the task parser, the variant catalogue, the instance set and a quick renderer.

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::{Args as ClapArgs, Subcommand};
use vifo_cues::instances::{InstanceSet, TaskDescription};
use vifo_cues::parse::{GoalAtom, instruction_from_task_name, parse, parse_with_goals};
use vifo_cues::{Anchor, Anchors, CueSpec, FrameInputs, Inserter, RgbImage, VARIANTS, variants};

#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse an instruction (or a LIBERO task name) into steps of source, relation, target.
    Parse {
        instruction: String,
        /// A goal atom such as "(On akita_black_bowl_1 plate_1)" to link steps to bodies; repeatable.
        #[arg(long = "goal")]
        goals: Vec<String>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// List the cue variants.
    Variants {
        #[arg(long)]
        json: bool,
    },
    /// Build the instance set from a JSON list of task descriptions
    /// ({"suite", "index", "instruction", "goals": [{"predicate", "args"}], "objects", "fixtures"}).
    Instances {
        tasks: PathBuf,
        /// Print the whole set as JSON instead of the per-family summary.
        #[arg(long)]
        json: bool,
    },
    /// Draw one cue over a plain grey frame and write it as a binary PPM image.
    Render {
        variant: String,
        instruction: String,
        #[arg(long, default_value = "cue.ppm")]
        out: PathBuf,
        #[arg(long, default_value_t = 256)]
        size: u32,
        /// Source anchor "u,v[,radius]" in pixels.
        #[arg(long, default_value = "70,160,16")]
        source: String,
        /// Target anchor "u,v[,radius]" in pixels.
        #[arg(long, default_value = "185,110,22")]
        target: String,
    },
}

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        Command::Parse { instruction, goals, json } => parse_cmd(&instruction, &goals, json),
        Command::Variants { json } => {
            if json {
                println!("{}", serde_json::to_string_pretty(VARIANTS)?);
            } else {
                for v in VARIANTS {
                    println!("{} {:<26} {}", v.family, v.name, v.description);
                }
            }
            Ok(())
        }
        Command::Instances { tasks, json } => instances_cmd(&tasks, json),
        Command::Render { variant, instruction, out, size, source, target } => {
            render_cmd(&variant, &instruction, &out, size, &source, &target)
        }
    }
}

fn parse_cmd(instruction: &str, goals: &[String], json: bool) -> anyhow::Result<()> {
    let instruction = instruction_from_task_name(instruction);
    let goals: Vec<GoalAtom> =
        goals.iter().map(|g| g.parse().map_err(anyhow::Error::msg)).collect::<anyhow::Result<_>>()?;
    let parsed = if goals.is_empty() { parse(&instruction)? } else { parse_with_goals(&instruction, &goals)? };
    if json {
        println!("{}", serde_json::to_string_pretty(&parsed)?);
        return Ok(());
    }
    for (i, s) in parsed.steps.iter().enumerate() {
        let qualifier = s.source_qualifier.as_deref().map(|q| format!(" ({q})")).unwrap_or_default();
        let target = s.target.as_deref().map(|t| format!(" -> {t}")).unwrap_or_default();
        let ids = match (&s.source_id, &s.target_id) {
            (Some(a), Some(b)) => format!("   [{a} -> {b}]"),
            (Some(a), None) => format!("   [{a}]"),
            _ => String::new(),
        };
        println!("{}. {}: {}{qualifier}{target}{ids}", i + 1, s.relation, s.source);
    }
    Ok(())
}

fn instances_cmd(path: &PathBuf, json: bool) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let tasks: Vec<TaskDescription> = serde_json::from_str(&text)
        .with_context(|| format!("{}: expected a JSON list of task descriptions", path.display()))?;
    let set = InstanceSet::build(&tasks)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&set)?);
        return Ok(());
    }
    println!("{} instances over {} tasks", set.instances.len(), tasks.len());
    for (family, c) in set.composition() {
        println!("{family} {:<24} {:>5} {:>5.1} %  {:>3} tasks", family.name(), c.instances, c.share * 100.0, c.tasks);
    }
    Ok(())
}

fn anchor(text: &str) -> anyhow::Result<Anchor> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>().with_context(|| format!("anchor {text:?}: expected numbers u,v[,radius]")))
        .collect::<anyhow::Result<_>>()?;
    match parts.as_slice() {
        [u, v] => Ok(Anchor::at(*u, *v)),
        [u, v, r] => Ok(Anchor::at(*u, *v).with_radius(*r)),
        _ => bail!("anchor {text:?}: expected u,v or u,v,radius"),
    }
}

fn render_cmd(
    variant: &str,
    instruction: &str,
    out: &PathBuf,
    size: u32,
    source: &str,
    target: &str,
) -> anyhow::Result<()> {
    let v = variants::find(variant)
        .with_context(|| format!("unknown variant {variant:?}; `vifo cues variants` lists them"))?;
    let parsed = parse(&instruction_from_task_name(instruction))?;
    let step = vifo_cues::instances::step_for(&parsed, v.needs).unwrap_or(0);
    let spec = CueSpec::new("cli/0", &parsed, step, v)?;
    let mut frame = RgbImage::filled(size, size, [128, 128, 128])?;
    let k = size as f64 / 256.0;
    let scaled = |a: Anchor| Anchor { u: a.u * k, v: a.v * k, radius: a.radius.map(|r| r * k), ..a };
    let inputs =
        FrameInputs::anchored(Anchors { source: Some(scaled(anchor(source)?)), target: Some(scaled(anchor(target)?)) });
    let report = Inserter::new().insert(&mut frame, &spec, &inputs)?;
    let mut ppm = format!("P6\n{} {}\n255\n", frame.width, frame.height).into_bytes();
    ppm.extend_from_slice(&frame.data);
    std::fs::write(out, ppm).with_context(|| format!("writing {}", out.display()))?;
    println!("{} -> {} ({})", spec.id(), out.display(), serde_json::to_string(&report)?);
    Ok(())
}
