//! `vifo cues`: the task parser, the variant catalogue, the instance set and a quick renderer.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::{Args as ClapArgs, Subcommand};
use serde::Serialize;
use vifo_render::imageio::save_png;
use vifo_cues::composition;
use vifo_cues::instances::{InstanceSet, TaskDescription, paper};
use vifo_cues::parse::{GoalAtom, instruction_from_task_name, parse, parse_with_goals};
use vifo_cues::{Anchor, Anchors, CueSpec, Family, FrameInputs, Inserter, RgbImage, SetName, VARIANTS, variants};
use vifo_protocols::report;
use vifo_protocols::scene_cues::{builtin_set, gallery};

#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Parse an instruction (or a LIBERO task name) into steps of source, relation, target.
    Parse {
        /// The instruction ("put the bowl on the plate") or a task name with underscores.
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
        /// Print JSON (per variant: name, family, description, what it needs, form and marks).
        #[arg(long)]
        json: bool,
    },
    /// Build the instance set from a JSON list of task descriptions
    /// ({"suite", "index", "instruction", "goals": [{"predicate", "args"}], "objects", "fixtures"}).
    Instances {
        /// The JSON file of task descriptions.
        tasks: PathBuf,
        /// Print the whole set as JSON instead of the per-family summary.
        #[arg(long)]
        json: bool,
    },
    /// An instance set of the 40 built-in tasks: counts per family and per task, the variants;
    /// with --ids, the instance ids that `vifo render --cue`, `vifo web episode --cue` and
    /// Python's `cue=` take (`vifo run --instance` selects among a study's own instances).
    List {
        /// paper (the paper's 1,347 instances) or full (every instance the library makes).
        #[arg(long, default_value = "paper", value_parser = super::parse_set)]
        set: SetName,
        /// Print JSON (keys set, total, per_family, tasks_per_family, per_task, variants; with
        /// --ids a list of ids).
        #[arg(long)]
        json: bool,
        /// Print the instance ids, one per line, instead of the counts.
        #[arg(long)]
        ids: bool,
        /// With --ids: only this task's instances (<suite>/<index>, e.g. libero_goal/3); repeatable.
        #[arg(long, requires = "ids")]
        task: Vec<String>,
        /// With --ids: only this family's instances (F1..F8); repeatable.
        #[arg(long, requires = "ids", value_parser = super::parse_family)]
        family: Vec<Family>,
    },
    /// Composition statistics of an instance set beside the paper's (appendix A): family shares
    /// and what the instances encode; draws both panels of the paper's figure as a PNG.
    Stats {
        /// paper (the paper's 1,347 instances) or full (every instance the library makes).
        #[arg(long, default_value = "paper", value_parser = super::parse_set)]
        set: SetName,
        /// The figure's file.
        #[arg(short = 'o', long, visible_alias = "output", default_value = "cue-statistics.png", value_parser = super::png_file)]
        out: PathBuf,
    },
    /// One contact-sheet PNG per family: every variant drawn on a real scene frame.
    Gallery {
        /// Folder for the sheets (`F1.png` ... `F8.png`).
        #[arg(short = 'o', long = "out", visible_alias = "output", value_name = "DIR")]
        output: PathBuf,
        /// Task shown (<suite>/<index>); variants it cannot carry use another task.
        #[arg(long, default_value = gallery::SHOWCASE)]
        task: String,
        /// Only this family (F1..F8).
        #[arg(long, value_parser = super::parse_family)]
        family: Option<Family>,
        /// Index of the shipped initial state.
        #[arg(long, default_value_t = 0)]
        init: usize,
        /// Tile width and height in pixels.
        #[arg(long, default_value_t = 256, value_parser = super::image_side)]
        size: u32,
    },
    /// Draw one cue over a plain grey frame and write it as a binary PPM image.
    Render {
        /// Variant name (`vifo cues variants` lists them).
        variant: String,
        /// The instruction the cue encodes.
        instruction: String,
        /// The PPM image to write (a name ending in .ppm).
        #[arg(short = 'o', long, visible_alias = "output", default_value = "cue.ppm", value_parser = super::ppm_file)]
        out: PathBuf,
        /// Frame width and height in pixels.
        #[arg(long, default_value_t = 256, value_parser = super::image_side)]
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
        Command::List { set, json, ids: true, task, family } => ids_cmd(set, &task, &family, json),
        Command::List { set, json, .. } => list_cmd(set, json),
        Command::Stats { set, out } => stats_cmd(set, &out),
        Command::Gallery { output, task, family, init, size } => gallery_cmd(&output, &task, family, init, size),
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
    for g in &goals {
        if !parsed.steps.iter().any(|s| s.source_id.as_ref() == g.args.first()) {
            eprintln!("note: goal ({} {}) links to no step of the instruction", g.predicate, g.args.join(" "));
        }
    }
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

fn instances_cmd(path: &Path, json: bool) -> anyhow::Result<()> {
    let text = vifo_protocols::text_file::read(path).with_context(|| format!("reading {}", path.display()))?;
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

/// Counts of the built-in instance set, as `vifo cues list --json` prints them.
#[derive(Serialize)]
struct Listing {
    set: SetName,
    total: usize,
    per_family: BTreeMap<Family, usize>,
    tasks_per_family: BTreeMap<Family, usize>,
    /// Tasks in suite order.
    per_task: Vec<TaskCount>,
    variants: Vec<VariantCount>,
}

#[derive(Serialize)]
struct TaskCount {
    task: String,
    total: usize,
    per_family: BTreeMap<Family, usize>,
}

#[derive(Serialize)]
struct VariantCount {
    name: &'static str,
    family: Family,
    description: &'static str,
    instances: usize,
}

fn listing(name: SetName) -> anyhow::Result<Listing> {
    let set = builtin_set(name)?;
    let composition = set.composition();
    let mut per_task: Vec<TaskCount> = Vec::new();
    for spec in &set.instances {
        if per_task.last().is_none_or(|t| t.task != spec.task) {
            per_task.push(TaskCount { task: spec.task.clone(), total: 0, per_family: BTreeMap::new() });
        }
        if let Some(t) = per_task.last_mut() {
            t.total += 1;
            *t.per_family.entry(spec.family).or_default() += 1;
        }
    }
    Ok(Listing {
        set: name,
        total: set.instances.len(),
        per_family: composition.iter().map(|(f, c)| (*f, c.instances)).collect(),
        tasks_per_family: composition.iter().map(|(f, c)| (*f, c.tasks)).collect(),
        per_task,
        variants: VARIANTS
            .iter()
            .filter(|v| name == SetName::Full || set.instances.iter().any(|s| s.variant == v.name))
            .map(|v| VariantCount {
                name: v.name,
                family: v.family,
                description: v.description,
                instances: set.instances.iter().filter(|s| s.variant == v.name).count(),
            })
            .collect(),
    })
}

fn list_cmd(set: SetName, json: bool) -> anyhow::Result<()> {
    let l = listing(set)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&l)?);
        return Ok(());
    }
    println!("{set} set: {} instances over {} tasks, {} VQA questions (paper: 1,347, 5,388)\n", l.total, l.per_task.len(), 4 * l.total);
    println!("family                        variants  instances  share  tasks");
    for family in Family::ALL {
        let n = l.per_family[&family];
        let variants = l.variants.iter().filter(|v| v.family == family).count();
        let share = 100.0 * n as f64 / l.total.max(1) as f64;
        println!("{family} {:<26} {variants:>8} {n:>10} {share:>5.1} % {:>6}", family.name(), l.tasks_per_family[&family]);
    }
    println!("\ntask                 {} total", Family::ALL.map(|f| format!("{:>4}", f.to_string())).join(""));
    for t in &l.per_task {
        let cells = Family::ALL.map(|f| format!("{:>4}", t.per_family.get(&f).copied().unwrap_or(0))).join("");
        println!("{:<20} {cells} {:>5}", t.task, t.total);
    }
    println!("\nvariants ({}):", l.variants.len());
    for v in &l.variants {
        println!("{} {:<26} {:>4}  {}", v.family, v.name, v.instances, v.description);
    }
    let smallest = Family::ALL.iter().map(|f| l.variants.iter().filter(|v| v.family == *f).count()).min().unwrap_or(0);
    let full = Family::ALL.iter().filter(|f| **f != Family::F3 && l.tasks_per_family[f] == 40).count();
    println!(
        "\ngates: {} variants (paper 33), smallest family {smallest} (>= 2), total {} (paper 1,347), {full} of 7 non-ghost families on 40 tasks, ghosts on {} (>= 38)",
        l.variants.len(),
        l.total,
        l.tasks_per_family[&Family::F3]
    );
    Ok(())
}

/// `vifo cues list --ids`: the ids of a set's instances, of the given tasks and families (all
/// where none is given), in suite, task and catalogue order.
fn ids_cmd(name: SetName, tasks: &[String], families: &[Family], json: bool) -> anyhow::Result<()> {
    let set = builtin_set(name)?;
    for task in tasks {
        anyhow::ensure!(
            set.instances.iter().any(|s| &s.task == task),
            "no built-in task {task:?} (expected <suite>/<index>: suites {}, indices 0-9)",
            vifo_scenes::suite_names().join(", ")
        );
    }
    let ids: Vec<String> = set
        .instances
        .iter()
        .filter(|s| tasks.is_empty() || tasks.contains(&s.task))
        .filter(|s| families.is_empty() || families.contains(&s.family))
        .map(|s| s.id())
        .collect();
    if json {
        println!("{}", serde_json::to_string_pretty(&ids)?);
    } else {
        for id in &ids {
            println!("{id}");
        }
    }
    Ok(())
}

fn stats_cmd(name: SetName, out: &Path) -> anyhow::Result<()> {
    let set = builtin_set(name)?;
    let families = set.composition();
    let coverage = composition::coverage(&set.instances);
    let variants: BTreeSet<&str> = set.instances.iter().map(|s| s.variant.as_str()).collect();
    println!(
        "{name} set: {} instances, {} variants, {} VQA questions (paper: {}, {}, {})\n",
        set.instances.len(),
        variants.len(),
        4 * set.instances.len(),
        paper::INSTANCES,
        paper::VARIANTS,
        paper::QUESTIONS
    );
    let stated: BTreeMap<Family, f64> = paper::STATED_SHARES.into_iter().collect();
    println!("(a) family                     instances  share  tasks   paper  diff");
    for (family, c) in &families {
        let (theirs, diff) = match stated.get(family) {
            Some(p) => (format!("{:>5.1} %", p * 100.0), format!("{:+5.2}", (c.share - p) * 100.0)),
            None => ("    –  ".to_string(), String::new()),
        };
        println!("{family} {:<24} {:>9} {:>5.1} % {:>5}  {theirs} {diff}", family.name(), c.instances, c.share * 100.0, c.tasks);
    }
    println!("\n(b) component                     instances  share   paper  diff");
    for (component, c) in &coverage {
        println!(
            "{:<32} {:>9} {:>5.1} % {:>5.1} % {:+5.1}",
            component.label(),
            c.instances,
            c.percent,
            c.paper_percent,
            c.percent - c.paper_percent
        );
    }
    let png = report::composition_chart::composition_figure(name, &families, &coverage).map_err(anyhow::Error::msg)?;
    std::fs::write(out, png).with_context(|| format!("writing {}", out.display()))?;
    println!("\nfigure -> {}", out.display());
    Ok(())
}

fn gallery_cmd(dir: &Path, task: &str, family: Option<Family>, init: usize, size: u32) -> anyhow::Result<()> {
    let families: Vec<Family> = family.map_or(Family::ALL.to_vec(), |f| vec![f]);
    vifo::render::parse_task(task)?;
    vifo_protocols::runner::create_folder(dir)?;
    for family in families {
        let sheet = gallery::sheet(family, task, size, init)?;
        let path = dir.join(format!("{family}.png"));
        save_png(&sheet.image, &path)?;
        println!("{} ({} variants) -> {}", family, sheet.instances.len(), path.display());
        for id in &sheet.failed_demos {
            println!("  {id}: the expert's demonstration failed; the ghost/pictures show where it stopped");
        }
    }
    Ok(())
}

fn anchor(text: &str) -> anyhow::Result<Anchor> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>().with_context(|| format!("anchor {text:?}: expected numbers u,v[,radius]")))
        .collect::<anyhow::Result<_>>()?;
    if let Some(bad) = parts.iter().find(|x| !x.is_finite()) {
        bail!("anchor {text:?}: {bad} is not a finite number");
    }
    match parts.as_slice() {
        [_, _, r] if *r <= 0.0 => bail!("anchor {text:?}: the radius must be positive"),
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
