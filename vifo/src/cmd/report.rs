//! `vifo report RESULTS.jsonl... [--vqa POLICY=scores.json]... --out DIR`: the paper's Tables 1
//! and 2 (Markdown printed; Markdown, CSV, JSON and bar charts written to DIR).

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;
use vifo_protocols::report;
use vifo_protocols::studies::{Study, safety};
use vifo_protocols::runner::read_records;
use vifo_protocols::vqa::VqaScores;

#[derive(ClapArgs)]
pub struct Args {
    /// Results files written by the runner (any number of policies).
    results: Vec<PathBuf>,
    /// VQA scores of a policy, from `vifo vqa score --out`: POLICY=FILE; repeatable.
    #[arg(long = "vqa")]
    vqa: Vec<String>,
    /// Folder for table1/table2 .md/.csv/.json and chart_*.png.
    #[arg(long, default_value = "report")]
    out: PathBuf,
    /// Put episodes drawn with different looks (built-in, LIBERO's assets) in one table.
    #[arg(long)]
    mix_looks: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut records = Vec::new();
    for path in &args.results {
        anyhow::ensure!(path.is_file(), "{}: no such results file", path.display());
        let loaded = read_records(path)?;
        if loaded.truncated_tail > 0 {
            eprintln!("note: {}: ignored a cut-off last line", path.display());
        }
        records.extend(loaded.records);
    }
    let mut vqa = BTreeMap::new();
    for item in &args.vqa {
        let (policy, file) = item.split_once('=').context("--vqa expects POLICY=FILE")?;
        let text = std::fs::read_to_string(file).with_context(|| format!("reading {file}"))?;
        let scores: VqaScores = serde_json::from_str(&text)
            .with_context(|| format!("{file}: expected VQA scores from `vifo vqa score --out`"))?;
        vqa.insert(policy.to_string(), scores);
    }
    anyhow::ensure!(!records.is_empty() || !vqa.is_empty(), "nothing to report: give results files or --vqa scores");
    let looks = report::looks(&records);
    let listed = looks.iter().map(|(l, n)| format!("{l} ({n} episodes)")).collect::<Vec<_>>().join(", ");
    anyhow::ensure!(
        looks.len() <= 1 || args.mix_looks,
        "the results mix looks: {listed}; their numbers are not comparable (report them separately, or pass --mix-looks)"
    );
    if !looks.is_empty() {
        eprintln!("look: {listed}");
    }
    // Study episodes (their own suites) get their own tables, not the main ones.
    let (study, main): (Vec<_>, Vec<_>) = records.into_iter().partition(|r| Study::of(&r.spec).is_some());
    if !main.is_empty() || !vqa.is_empty() {
        let report = report::build(&main, &vqa);
        let markdown = report.write(&args.out).with_context(|| format!("writing {}", args.out.display()))?;
        print!("{markdown}");
    }
    if !study.is_empty() {
        let markdown = safety::build(&study).write(&args.out).with_context(|| format!("writing {}", args.out.display()))?;
        print!("\n{markdown}");
    }
    println!("\nwritten to {}", args.out.display());
    Ok(())
}
