//! The paper's extended studies (§4.2–§4.4) as selections of episodes for the benchmark's own
//! runner, results files and report: `vifo run --study objects|safety|piper`, `--study all` for
//! every one. Each study module gives its episodes and its tables, laid out as the paper lays
//! that study out.
//!
//! - [`objects`]: §4.2, F1/F6/F8 cues as scene objects against their overlays (LIBERO's tasks).
//! - [`safety`]: §4.3, the six safety-critical scenes (their own suite, `vifo_safety`).
//! - [`piper`]: §4.4, the PiPER cup-stacking setting (its own suite, `vifo_piper`).

pub mod objects;
pub mod piper;
pub mod safety;

use std::path::Path;

use vifo_cues::SetName;

use crate::benchmark::BenchmarkError;
use crate::spec::{EpisodeRecord, EpisodeSpec};

/// One extended study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Study {
    /// §4.2: text cards, signs and code tags as scene objects, against their overlays.
    Objects,
    /// §4.3: safe vs hazardous tasks under authorized cue following and language–cue conflict.
    Safety,
    /// §4.4: the PiPER stacks cups, or stops, as a paper note on the table says.
    Piper,
}

impl Study {
    pub const ALL: [Study; 3] = [Study::Objects, Study::Safety, Study::Piper];

    pub fn name(self) -> &'static str {
        match self {
            Study::Objects => "objects",
            Study::Safety => "safety",
            Study::Piper => "piper",
        }
    }

    /// The studies a list of names asks for (`all` is every study), in [`Study::ALL`] order.
    pub fn parse_list(names: &[String]) -> Result<Vec<Study>, String> {
        let mut out = Vec::new();
        for name in names {
            let found: Vec<Study> = if name == "all" {
                Study::ALL.to_vec()
            } else {
                let s = Study::ALL.into_iter().find(|s| s.name() == name).ok_or_else(|| {
                    let known: Vec<&str> = Study::ALL.iter().map(|s| s.name()).collect();
                    format!("unknown study {name:?}: expected {} or all", known.join(", "))
                })?;
                vec![s]
            };
            out.extend(found);
        }
        out.sort();
        out.dedup();
        Ok(out)
    }

    /// The study's episodes.
    pub fn episodes(self, options: &StudyOptions) -> Result<Vec<EpisodeSpec>, BenchmarkError> {
        match self {
            Study::Objects => objects::episodes(options),
            Study::Safety => safety::episodes(options),
            // Every initial state of both conditions (the quick sample: the first), each
            // repeated `episodes` times.
            Study::Piper => piper::episodes(if options.quick { 1 } else { piper::STATES }, options.episodes),
        }
    }
}

/// What part of a study to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyOptions {
    /// The instance set cue instances come from.
    pub set: SetName,
    /// Episodes per instance (or scene), form and protocol; episode `e` starts from initial
    /// state `e mod 50`.
    pub episodes: usize,
    /// The quick default's small sample (a few instances) instead of the whole study.
    pub quick: bool,
}

/// How a suite's episodes show their cue: the one per-suite notion the environment and the
/// instance sets go by, so neither asks which study a suite belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SuiteCue {
    /// A cue instance of the library, drawn over the frames or standing in the scene as a cue
    /// object (§4.2): LIBERO's suites and the safety scenes (§4.3).
    Library,
    /// A note lying in the scene whose text the condition chooses, scored by the suite's own
    /// judges (the PiPER study, §4.4): no library instance, nothing drawn over the frames.
    SceneNote,
}

impl SuiteCue {
    pub fn of(suite: &str) -> SuiteCue {
        if suite == piper::SUITE { SuiteCue::SceneNote } else { SuiteCue::Library }
    }
}

/// Whether an episode runs in a study's own suite (not one of LIBERO's): such episodes are
/// reported in that study's tables only, never in the main benchmark's.
pub fn own_suite(spec: &EpisodeSpec) -> bool {
    [safety::SUITE, piper::SUITE].contains(&spec.task.suite.as_str())
}

/// The records the main benchmark's tables take: all but those of the studies' own suites.
pub fn main_records(records: &[EpisodeRecord]) -> Vec<EpisodeRecord> {
    records.iter().filter(|r| !own_suite(&r.spec)).cloned().collect()
}

/// Writes the tables and charts of every study whose episodes `records` hold into `dir`;
/// returns their Markdown (empty when none).
pub fn write_reports(records: &[EpisodeRecord], vqa: &objects::FormVqa, dir: &Path) -> std::io::Result<String> {
    let mut markdown = String::new();
    let table = objects::build(records, vqa);
    if !table.rows.is_empty() {
        markdown += &table.write(dir)?;
    }
    let safety = safety::build(records);
    if !safety.rows.is_empty() {
        markdown += "\n";
        markdown += &safety.write(dir)?;
    }
    let piper = piper::table(records);
    if !piper.is_empty() {
        crate::runner::create_dir(dir)?;
        let text = piper::markdown(&piper);
        let json = serde_json::to_string_pretty(&piper).map_err(std::io::Error::other)?;
        for (file, content) in [("piper.md", text.clone()), ("piper.csv", piper::csv(&piper)), ("piper.json", json)] {
            std::fs::write(dir.join(file), content)?;
        }
        std::fs::write(dir.join("chart_piper.png"), piper::chart(&piper).map_err(std::io::Error::other)?)?;
        markdown += "\n";
        markdown += &text;
    }
    Ok(markdown)
}
