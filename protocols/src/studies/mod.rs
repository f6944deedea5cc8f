//! The paper's extended studies (§4.2–§4.4) as selections of episodes for the benchmark's own
//! runner, results files and report: `vifo run --study objects` (others join as they land),
//! `--study all` for every one. Each study module gives its episodes and its tables, laid out
//! as the paper lays that study out.

pub mod objects;

use std::path::Path;

use vifo_cues::SetName;

use crate::benchmark::BenchmarkError;
use crate::spec::{EpisodeRecord, EpisodeSpec};

/// One extended study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Study {
    /// §4.2: text cards, signs and code tags as scene objects, against their overlays.
    Objects,
}

impl Study {
    pub const ALL: [Study; 1] = [Study::Objects];

    pub fn name(self) -> &'static str {
        match self {
            Study::Objects => "objects",
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

/// Writes the tables and charts of every study whose episodes `records` hold into `dir`;
/// returns their Markdown (empty when none).
pub fn write_reports(records: &[EpisodeRecord], vqa: &objects::FormVqa, dir: &Path) -> std::io::Result<String> {
    let mut markdown = String::new();
    let table = objects::build(records, vqa);
    if !table.rows.is_empty() {
        markdown += &table.write(dir)?;
    }
    Ok(markdown)
}
