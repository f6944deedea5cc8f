//! `vifo report RESULTS.jsonl... [--vqa POLICY=scores.json]... --out DIR`: the paper's Tables 1
//! and 2 (Markdown printed; Markdown, CSV, JSON and bar charts written to DIR).

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::Context;
use clap::Args as ClapArgs;
use vifo_protocols::report;
use vifo_protocols::benchmark::records::read_checked;
use vifo_protocols::studies;
use vifo_protocols::vqa::VqaScores;
use vifo_cues::SetName;
use vifo_protocols::spec::{EpisodeRecord, Outcome, RESULTS_VERSION};
use vifo_protocols::CueForm;

#[derive(ClapArgs)]
pub struct Args {
    /// Results files written by the runner (any number of policies), or a run's output folder
    /// (its `results-*.jsonl`).
    results: Vec<PathBuf>,
    /// VQA scores of a policy, from `vifo vqa score --out`: POLICY=FILE; repeatable.
    #[arg(long = "vqa")]
    vqa: Vec<String>,
    /// VQA scores of a policy on the cue-object export (`vifo vqa export --form object`), for
    /// the objects study's table (§4.2): POLICY=FILE; repeatable.
    #[arg(long = "vqa-object")]
    vqa_object: Vec<String>,
    /// Folder for table1/table2 .md/.csv/.json and chart_*.png.
    #[arg(short = 'o', long, visible_alias = "output", default_value = "report")]
    out: PathBuf,
    /// Put episodes and VQA scores drawn with different looks (built-in, LIBERO's assets) in one
    /// table.
    #[arg(long)]
    mix_looks: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let mut records = Vec::new();
    // Per episode (policy, set, key), the files holding a completed record of it.
    let mut seen_in: BTreeMap<(String, SetName, String), Vec<PathBuf>> = BTreeMap::new();
    let files = results_files(&args.results)?;
    for path in &files {
        anyhow::ensure!(path.exists(), "{}: no such results file", path.display());
        let loaded = read_checked(path)?;
        if loaded.truncated_tail > 0 {
            eprintln!("note: {}: ignored a cut-off last line", path.display());
        }
        // Another version's fields may mean something else: its rows would be wrong, not missing.
        if let Some(r) = loaded.records.iter().find(|r| r.version != RESULTS_VERSION) {
            anyhow::bail!(
                "{}: holds records of results version {}; this vifo reads version {RESULTS_VERSION}",
                path.display(),
                r.version
            );
        }
        for r in loaded.records.iter().filter(|r| matches!(r.outcome, Outcome::Completed { .. })) {
            seen_in.entry((r.policy.clone(), r.set, r.spec.key())).or_default().push(path.clone());
        }
        records.extend(loaded.records);
    }
    note_repeats(&seen_in);
    let vqa = read_scores(&args.vqa, "--vqa", CueForm::Overlay)?;
    let vqa_object = read_scores(&args.vqa_object, "--vqa-object", CueForm::Object)?;
    check_sets(&records, vqa.iter().chain(&vqa_object))?;
    note_unmatched_scores(&records, vqa.keys().chain(vqa_object.keys()));
    let mut by_form: studies::objects::FormVqa = BTreeMap::new();
    for (forms, form) in [(&vqa, CueForm::Overlay), (&vqa_object, CueForm::Object)] {
        by_form.extend(forms.iter().map(|(p, s)| ((p.clone(), form), s.clone())));
    }
    anyhow::ensure!(!records.is_empty() || !vqa.is_empty() || !vqa_object.is_empty(), "nothing to report: {}", match files.len() {
        0 => "give results files, --vqa or --vqa-object scores".to_string(),
        1 => format!("{} holds no episode records", files[0].display()),
        _ => format!("{} hold no episode records", files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")),
    });
    let scores = vqa.iter().chain(&vqa_object).map(|(policy, s)| (policy.as_str(), s));
    let looks = report::looks_with_vqa(&records, scores);
    let listed = report::check_looks(&looks, args.mix_looks, "--mix-looks").map_err(anyhow::Error::msg)?;
    if !looks.is_empty() {
        eprintln!("look: {listed}");
    }
    let report = report::build(&studies::main_records(&records), &vqa);
    let mut markdown = report.write(&args.out).with_context(|| format!("writing {}", args.out.display()))?;
    markdown += &studies::write_reports(&records, &by_form, &args.out).with_context(|| format!("writing {}", args.out.display()))?;
    print!("{markdown}");
    println!("\nwritten to {} ({})", args.out.display(), report::MORE_FILES);
    Ok(())
}

/// The files named, with each folder replaced by the `results-*.jsonl` that `vifo run` wrote
/// there, in name order.
fn results_files(given: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for path in given {
        if !path.is_dir() {
            files.push(path.clone());
            continue;
        }
        let entries = std::fs::read_dir(path).with_context(|| format!("reading {}", path.display()))?;
        let mut found: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.file_name().and_then(|n| n.to_str()).is_some_and(vifo_protocols::runner::results::is_file_name))
            .collect();
        anyhow::ensure!(!found.is_empty(), "{}: a folder without results-*.jsonl files (vifo run --out writes them)", path.display());
        found.sort();
        files.extend(found);
    }
    Ok(once_each(files))
}

/// `files` without a file met again (by its canonical path, so a folder and a file in it, or
/// two spellings of one file, count its episodes once); says which were dropped.
fn once_each(files: Vec<PathBuf>) -> Vec<PathBuf> {
    let mut seen = std::collections::BTreeSet::new();
    let mut kept = Vec::new();
    for path in files {
        if seen.insert(std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone())) {
            kept.push(path);
        } else {
            eprintln!("note: {} was given more than once; its episodes are counted once", path.display());
        }
    }
    kept
}

/// Scores under a name no episode has get a row of their own (a VLM evaluated on VQA only);
/// said aloud, since a served policy's episodes are named by its address (`openpi@ws://…`).
fn note_unmatched_scores<'a>(records: &[EpisodeRecord], names: impl Iterator<Item = &'a String>) {
    let policies: std::collections::BTreeSet<&str> = records.iter().map(|r| r.policy.as_str()).collect();
    if policies.is_empty() {
        return;
    }
    let unmatched: std::collections::BTreeSet<&String> = names.filter(|n| !policies.contains(n.as_str())).collect();
    let listed = policies.into_iter().collect::<Vec<_>>().join(", ");
    for name in unmatched {
        eprintln!("note: VQA scores of {name}: no episodes of that name (the results hold {listed}), so they get a row of their own");
    }
}

/// Says when files overlap (a copied file, overlapping shards): of an episode completed in
/// several files, the one given last counts, so the order of the arguments would change the
/// tables without a word.
fn note_repeats(seen_in: &BTreeMap<(String, SetName, String), Vec<PathBuf>>) {
    let repeated: Vec<_> = seen_in.iter().filter(|(_, files)| files.len() > 1).collect();
    if let Some(((policy, _, key), files)) = repeated.first() {
        let mut names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
        names.dedup();
        eprintln!(
            "note: completed episodes recorded more than once: {} (the first: {policy} {key}, {} times in {}); each counts once, \
             as recorded last (in the file given last)",
            repeated.len(),
            files.len(),
            names.join(" and ")
        );
    }
}

/// `POLICY=FILE` items of VQA scores (`vifo vqa score --out`) of the `form` export: scores
/// of the other form's export are refused (they record it since `form.txt`).
fn read_scores(items: &[String], option: &str, form: CueForm) -> anyhow::Result<BTreeMap<String, VqaScores>> {
    let mut out = BTreeMap::new();
    for item in items {
        let (policy, file) = item.split_once('=').with_context(|| format!("{option} expects POLICY=FILE"))?;
        let text = std::fs::read_to_string(file).with_context(|| format!("reading {file}"))?;
        let scores: VqaScores = serde_json::from_str(&text)
            .with_context(|| format!("{file}: expected VQA scores from `vifo vqa score --out`"))?;
        scores.check().map_err(|e| anyhow::anyhow!("{file}: not scores `vifo vqa score` writes: {e}"))?;
        if let Some(theirs) = scores.form.filter(|&f| f != form) {
            anyhow::bail!("{file}: scores of the {} export (vqa export --form {}); {option} takes the {} export's", theirs.name(), theirs.name(), form.name());
        }
        anyhow::ensure!(!policy.is_empty(), "{option} {item}: name the policy before `=`");
        anyhow::ensure!(out.insert(policy.to_string(), scores).is_none(), "{option}: {policy} is given scores twice; give one file per policy");
    }
    Ok(out)
}

/// A policy's VQA scores must come from the instance set of its episodes, when both say which.
fn check_sets<'a>(records: &[EpisodeRecord], scores: impl Iterator<Item = (&'a String, &'a VqaScores)>) -> anyhow::Result<()> {
    for (policy, s) in scores {
        let Some(set) = s.set else { continue };
        let sets: std::collections::BTreeSet<SetName> = records.iter().filter(|r| &r.policy == policy).map(|r| r.set).collect();
        anyhow::ensure!(
            sets.is_empty() || sets.contains(&set),
            "{policy}: VQA scores of the {set} set, episodes of the {} set; score the export of the episodes' set (vqa export --set)",
            sets.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_stands_for_its_results_files_in_name_order() {
        let dir = std::env::temp_dir().join(format!("vifo-report-folder-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for name in ["results-zero.jsonl", "results-expert-cue.jsonl", "results-zero.jsonl.lock", "notes.jsonl"] {
            std::fs::write(dir.join(name), "").unwrap();
        }
        let other = PathBuf::from("elsewhere.jsonl");
        let files = results_files(&[dir.clone(), other.clone()]).unwrap();
        assert_eq!(files, vec![dir.join("results-expert-cue.jsonl"), dir.join("results-zero.jsonl"), other.clone()]);
        // A file met again, through its folder or another spelling, is read once.
        let again = dir.join(".").join("results-zero.jsonl");
        let files = results_files(&[dir.join("results-zero.jsonl"), dir.clone(), again]).unwrap();
        assert_eq!(files, vec![dir.join("results-zero.jsonl"), dir.join("results-expert-cue.jsonl")]);
        let empty = dir.join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        let err = results_files(&[empty]).unwrap_err().to_string();
        assert!(err.contains("without results-*.jsonl"), "{err}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Scores of the other form's export, or of another instance set than the policy's
    /// episodes, are refused by name; scores that do not say (written before) are taken.
    #[test]
    fn vqa_scores_must_match_the_form_and_set_they_are_reported_with() {
        let dir = std::env::temp_dir().join(format!("vifo-report-scores-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = |name: &str, scores: &VqaScores| {
            let path = dir.join(name);
            std::fs::write(&path, serde_json::to_string(scores).unwrap()).unwrap();
            format!("p={}", path.display())
        };
        let object = file("object.json", &VqaScores { form: Some(CueForm::Object), set: Some(SetName::Full), ..VqaScores::default() });
        let unsaid = file("old.json", &VqaScores::default());
        let err = read_scores(std::slice::from_ref(&object), "--vqa", CueForm::Overlay).unwrap_err().to_string();
        assert!(err.contains("scores of the object export") && err.contains("--vqa takes the overlay export's"), "{err}");
        let scores = read_scores(&[object], "--vqa-object", CueForm::Object).unwrap();
        assert!(read_scores(&[unsaid], "--vqa", CueForm::Overlay).is_ok());

        let task = vifo_protocols::spec::TaskRef { suite: "libero_goal".into(), index: 0 };
        let spec = vifo_protocols::benchmark::specs::spec(&task, vifo_protocols::Protocol::Original, None, 0, 0).unwrap();
        let outcome = vifo_protocols::spec::Outcome::Completed { language_success: Some(true), cue_success: None, steps: 1 };
        let mut record = EpisodeRecord { version: 1, spec, policy: "p".into(), outcome, wall_ms: 1.0, set: SetName::Paper, look: String::new() };
        let err = check_sets(std::slice::from_ref(&record), scores.iter()).unwrap_err().to_string();
        assert!(err.contains("p: VQA scores of the full set, episodes of the paper set"), "{err}");
        record.set = SetName::Full;
        check_sets(&[record], scores.iter()).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
    }
}
