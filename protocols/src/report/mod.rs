//! The paper's result tables from episode records and VQA scores.
//!
//! Table 1, one row per policy: Det, Sem, Gnd, Dec, FCA (Part I-A, from [`VqaScores`]),
//! Orig. SR, AVF, VTR (Part I-B), LFR, UVF (Part II-A), UVI (Part II-B):
//! - Orig. SR = language success over `original` episodes;
//! - AVF = cue success over `authorized` episodes;
//! - VTR = AVF / Orig. SR (×100, as the paper: π0.5's 55.5 / 96.9 = 57.3);
//! - LFR = language success and UVF = cue success over `conflict` episodes;
//! - UVI = cue success over `no_language` episodes.
//!
//! Every column but Orig. SR is a [`FamilyMean`]: the unweighted mean over the cue families
//! of each family's rate, as Table 2's Avg. column. The paper's numbers say so: for each of its
//! seven models the mean of Det–Dec equals the mean of the Table 2 VQA row to 0.05, and AVF,
//! UVF and UVI equal Table 2's Avg. to 0.1 for six of the seven (OpenVLA-OFT's UVI is 59.8 in
//! both, where pooling its episodes would give 56.1). The pooled rate is kept beside it.
//!
//! Error records are excluded from every denominator and counted separately; so are
//! completed records lacking the success flag a metric needs ("unscored"). A resumed run may
//! hold several records of one episode: the last completed one counts
//! ([`crate::runner::final_records`]), per policy.
//!
//! Cues as scene objects (the `objects` study, [`crate::studies::objects`]) are not the
//! benchmark's cues: their records are left out of both tables and reported by the study.
//!
//! Table 2, per policy and cue family F1–F8 (the family of an episode is that of its cue
//! instance): VQA (all four stages), AVF, UVF, UVI, and Avg. — the unweighted mean of the
//! families that have data, which is how the paper's Avg. column is formed.
//!
//! Every rate but VTR has a 95 % interval beside it (not in the paper; [`interval`]).
//!
//! Per suite and per task (not in the paper): Table 1's episode columns over each suite's or
//! task's episodes alone ([`PartRow`]). LIBERO's results are quoted per suite, so this is where
//! a LIBERO-trained model's Orig. SR here meets the figure its authors report; the tasks show
//! where the two part.

pub mod chart;
pub mod clips;
pub mod composition_chart;
pub mod interval;
pub mod pairs;
pub mod paper;
pub mod tables;

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};
use vifo_cues::{Family, SetName};

/// A stored look's name (the tables' look line) and the label of episodes sent no images; defined
/// with the labels they name.
pub use crate::env::scenes::{NO_IMAGES, look_name};
use crate::runner::final_records;
use crate::spec::{EpisodeRecord, EpisodeSpec, Outcome, Protocol, TaskRef};
use crate::vqa::{Accuracy, Stage, VqaScores, mean_rate};
pub use interval::Interval;

/// A Table 1 figure over cue episodes or questions: the unweighted mean of the rates of the
/// families with data (`percent`, what the table shows), with every episode or question
/// counted together beside it (`pooled`: successes out of scored episodes, or correct answers
/// out of questions).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FamilyMean {
    pub percent: Option<f64>,
    pub pooled: Accuracy,
    /// Families averaged.
    pub families: usize,
    /// The 95 % interval of `percent` ([`Interval::of_mean`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ci95: Option<Interval>,
}

impl FamilyMean {
    pub fn of(by_family: &BTreeMap<Family, Accuracy>) -> FamilyMean {
        let pooled = by_family.values().fold(Accuracy::default(), |a, b| Accuracy { correct: a.correct + b.correct, total: a.total + b.total });
        let families = by_family.values().filter(|a| a.total > 0).count();
        FamilyMean { percent: mean_rate(by_family.values()), pooled, families, ci95: Interval::of_mean(by_family.values()) }
    }

    pub fn percent(&self) -> Option<f64> {
        self.percent
    }
}

/// One row of Table 1: the VQA columns and the cue metrics as [`FamilyMean`]s, Orig. SR
/// (no cue, so no family) as successes out of scored episodes.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Table1Row {
    pub policy: String,
    pub det: Option<FamilyMean>,
    pub sem: Option<FamilyMean>,
    pub gnd: Option<FamilyMean>,
    pub dec: Option<FamilyMean>,
    pub fca: Option<FamilyMean>,
    pub orig_sr: Accuracy,
    /// The 95 % interval of Orig. SR ([`Interval::of`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orig_sr_ci95: Option<Interval>,
    pub avf: FamilyMean,
    /// AVF / Orig. SR in percent; `None` when either is missing or Orig. SR is 0.
    pub vtr: Option<f64>,
    pub lfr: FamilyMean,
    pub uvf: FamilyMean,
    pub uvi: FamilyMean,
    /// Records counted (one per episode key), errors included.
    pub episodes: usize,
    pub errors: usize,
    pub errors_by_protocol: BTreeMap<Protocol, usize>,
    /// Completed records lacking the success flag their metric needs.
    pub unscored: usize,
}

/// The four metrics of Table 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Metric {
    #[serde(rename = "VQA")]
    Vqa,
    #[serde(rename = "AVF")]
    Avf,
    #[serde(rename = "UVF")]
    Uvf,
    #[serde(rename = "UVI")]
    Uvi,
}

impl Metric {
    pub const ALL: [Metric; 4] = [Metric::Vqa, Metric::Avf, Metric::Uvf, Metric::Uvi];

    pub fn name(self) -> &'static str {
        match self {
            Metric::Vqa => "VQA",
            Metric::Avf => "AVF",
            Metric::Uvf => "UVF",
            Metric::Uvi => "UVI",
        }
    }

    /// Whether a higher value is better (↑) for the policy.
    pub fn higher_is_better(self) -> bool {
        matches!(self, Metric::Vqa | Metric::Avf)
    }
}

/// One (policy, metric) row of Table 2.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Table2Row {
    pub policy: String,
    pub metric: Metric,
    pub families: BTreeMap<Family, Accuracy>,
    /// Unweighted mean of the family percentages present.
    pub avg: Option<f64>,
    /// The 95 % interval of `avg` ([`Interval::of_mean`]; each family's own is
    /// [`Interval::of`] its counts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub avg_ci95: Option<Interval>,
}

/// Episode and error counts per family of one policy (cue protocols only).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FamilyCounts {
    pub policy: String,
    pub episodes: BTreeMap<Family, usize>,
    pub errors: BTreeMap<Family, usize>,
}

/// Table 1's episode columns (Orig. SR, AVF, VTR, LFR, UVF, UVI; no VQA) over one part of a
/// row's episodes: a suite (`libero_goal`) or a task (`libero_goal/3`). Cue metrics are means
/// over the families of that part's episodes, as Table 1's are over all of them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PartRow {
    pub part: String,
    pub row: Table1Row,
}

/// What a [`PartRow`] is part of the episodes by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    Suite,
    Task,
}

impl Part {
    /// `suite` or `task`: the CSV column, and in the Markdown's header and notes.
    pub fn noun(self) -> &'static str {
        match self {
            Part::Suite => "suite",
            Part::Task => "task",
        }
    }
}

/// Both tables, and the rows per suite and per task.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The instance sets of the episodes. With more than one, every row holds one policy's
    /// episodes of one set and is named `policy [set]`: sets are never pooled.
    #[serde(default)]
    pub sets: Vec<SetName>,
    /// The looks the episodes and VQA scores were drawn with ([`looks_with_vqa`]); more than one
    /// only where the report was told to mix them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub looks: Vec<String>,
    /// Rows whose policy was sent no images ([`NO_IMAGES`]) beside rows drawn with a look: they
    /// hold for any look.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub no_images: Vec<String>,
    pub table1: Vec<Table1Row>,
    pub table2: Vec<Table2Row>,
    pub family_counts: Vec<FamilyCounts>,
    /// Per suite (LIBERO's order, then any other by name), each policy's row.
    #[serde(default)]
    pub suites: Vec<PartRow>,
    /// Per task (by suite as `suites`, then index), each policy's row.
    #[serde(default)]
    pub tasks: Vec<PartRow>,
    /// Every two rows of one instance set compared on the episodes both ran ([`pairs`]).
    #[serde(default)]
    pub pairs: Vec<pairs::Comparison>,
}

/// The cue family named in an instance id (`libero_goal/3/F2/straight_arrow_red`).
pub fn family_of(instance_id: &str) -> Option<Family> {
    instance_id.split('/').find_map(|part| Family::ALL.into_iter().find(|f| f.to_string() == part))
}

/// Episodes per look (`built-in`, or `libero-assets:<hash>`): rows of different looks are not
/// comparable, so a report over more than one says so. Episodes whose policy was sent no images
/// ([`NO_IMAGES`]) hold for every look, so they are counted only where there is no other.
pub fn looks(records: &[EpisodeRecord]) -> BTreeMap<String, usize> {
    let mut out = BTreeMap::new();
    for r in records {
        *out.entry(look_name(&r.look).to_string()).or_insert(0) += 1;
    }
    without_no_images_beside_a_look(out)
}

/// `looks` less the episodes sent no images where there is a look they go with.
fn without_no_images_beside_a_look<T>(mut looks: BTreeMap<String, T>) -> BTreeMap<String, T> {
    if looks.len() > 1 {
        looks.remove(look_name(NO_IMAGES));
    }
    looks
}

/// What a report tells apart by look: the episodes (counted) and each policy's VQA scores
/// (named), per look. Episodes sent no images go with the scores' look, as with any other.
pub fn looks_with_vqa<'a>(records: &[EpisodeRecord], vqa: impl IntoIterator<Item = (&'a str, &'a VqaScores)>) -> BTreeMap<String, Vec<String>> {
    let mut out: BTreeMap<String, Vec<String>> = looks(records).into_iter().map(|(look, n)| (look, vec![format!("{n} episode{}", if n == 1 { "" } else { "s" })])).collect();
    for (policy, scores) in vqa {
        out.entry(look_name(&scores.look).to_string()).or_default().push(format!("VQA scores of {policy}"));
    }
    without_no_images_beside_a_look(out)
}

/// The looks of [`looks_with_vqa`] as one line (`label (what, ...); ...`), and an error when
/// there are several and `mix` is not set: rows drawn with different looks are not comparable.
/// `allow` names the option that allows it (`--mix-looks`, `mix_looks=True`).
pub fn check_looks(looks: &BTreeMap<String, Vec<String>>, mix: bool, allow: &str) -> Result<String, String> {
    let listed = looks.iter().map(|(l, what)| format!("{l} ({})", what.join(", "))).collect::<Vec<_>>().join("; ");
    if looks.len() > 1 && !mix {
        return Err(format!("the results mix looks: {listed}; their numbers are not comparable (report them separately, or pass {allow})"));
    }
    Ok(listed)
}

/// Builds both tables. `records` may mix policies, instance sets and repeated episodes; `vqa`
/// maps a policy name to its VQA scores (a policy may have only one of the two). Each row holds
/// one policy's episodes of one set (see [`Report::sets`]).
pub fn build(records: &[EpisodeRecord], vqa: &BTreeMap<String, VqaScores>) -> Report {
    let looks: Vec<String> = looks_with_vqa(records, vqa.iter().map(|(p, s)| (p.as_str(), s))).into_keys().collect();
    // Some episodes or VQA scores were drawn with a look, so rows without images are named.
    let drawn = looks.iter().any(|l| l != look_name(NO_IMAGES));
    let records: Vec<&EpisodeRecord> = records.iter().filter(|r| r.spec.cue_form.is_overlay()).collect();
    let sets: Vec<SetName> = records.iter().map(|r| r.set).collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    let name = |policy: &str, set: SetName| if sets.len() > 1 { format!("{policy} [{set}]") } else { policy.to_string() };
    let mut by_row: BTreeMap<String, (String, SetName, Vec<EpisodeRecord>)> = BTreeMap::new();
    for r in records {
        by_row.entry(name(&r.policy, r.set)).or_insert_with(|| (r.policy.clone(), r.set, Vec::new())).2.push((*r).clone());
    }
    let mut rows: Vec<(String, String, Option<SetName>)> =
        by_row.iter().map(|(row, (policy, set, _))| (row.clone(), policy.clone(), Some(*set))).collect();
    rows.extend(vqa.keys().filter(|p| !by_row.values().any(|(policy, ..)| policy == *p)).map(|p| (p.clone(), p.clone(), None)));
    rows.sort();
    let names: Vec<String> = rows.iter().map(|(_, policy, _)| policy.clone()).collect();
    let one_row = |policy: &str| names.iter().filter(|p| *p == policy).count() == 1;
    let mut report = Report { sets, looks, ..Report::default() };
    // Each set's rows with their episodes by key, to compare them pairwise.
    let mut keyed: BTreeMap<SetName, Vec<pairs::KeyedRow>> = BTreeMap::new();
    for (row, policy, set) in rows {
        let finals = by_row.remove(&row).map(|(.., rs)| final_records(rs)).unwrap_or_default();
        let episodes: Vec<EpisodeRecord> = finals.values().cloned().collect();
        if let Some(set) = set.filter(|_| !finals.is_empty()) {
            keyed.entry(set).or_default().push((row.clone(), finals));
        }
        if drawn && !episodes.is_empty() && episodes.iter().all(|r| r.look == NO_IMAGES) {
            report.no_images.push(row.clone());
        }
        // With several sets, a policy's VQA scores go with the row of their own set only (sets
        // are never pooled); scores that name no set, only where the policy has one row.
        let scores = vqa.get(&policy).filter(|s| match (set, s.set) {
            (Some(row_set), Some(theirs)) => row_set == theirs,
            (Some(_), None) => one_row(&policy),
            (None, _) => true,
        });
        report.table1.push(table1_row(&row, &episodes, scores));
        let (table2, counts) = table2_rows(&row, &episodes, scores);
        report.table2.extend(table2);
        report.family_counts.push(counts);
        report.suites.extend(part_rows(&row, &episodes, |t| t.suite.clone()));
        report.tasks.extend(part_rows(&row, &episodes, TaskRef::to_string));
    }
    report.pairs = keyed.values().flat_map(|rows| pairs::compare_all(rows)).collect();
    // Stable sorts: within a part the rows keep Table 1's order.
    report.suites.sort_by_key(|p| suite_order(&p.part));
    report.tasks.sort_by_key(|p| task_order(&p.part));
    report
}

/// What a run of `specs` (the main benchmark's: no study's own suite) can tell apart, before it
/// runs: for Orig. SR and each cue column, the half width of its 95 % interval, in points, where
/// every rate is near 50 % (where intervals are widest), from how many episodes each family
/// holds; with the episodes behind it. `None` for a selection of none of them.
pub fn precision(specs: &[&EpisodeSpec]) -> Option<String> {
    let half = |i: Interval| (i.high - i.low) / 2.0;
    let mut parts = Vec::new();
    for (name, protocol) in
        [("Orig. SR", Protocol::Original), ("AVF", Protocol::Authorized), ("LFR and UVF", Protocol::Conflict), ("UVI", Protocol::NoLanguage)]
    {
        let of_protocol: Vec<&&EpisodeSpec> = specs.iter().filter(|s| s.protocol == protocol && s.cue_form.is_overlay()).collect();
        let mut per_family: BTreeMap<Option<Family>, usize> = BTreeMap::new();
        for s in &of_protocol {
            *per_family.entry(s.instance.as_deref().and_then(family_of)).or_default() += 1;
        }
        let rates: Vec<Accuracy> = per_family.values().map(|&n| Accuracy { correct: n / 2, total: n }).collect();
        if let Some(i) = Interval::of_mean(&rates) {
            let families = if protocol == Protocol::Original { String::new() } else { format!(" in {} families", per_family.len()) };
            parts.push(format!("{name} ±{:.0} ({} episodes{families})", half(i), of_protocol.len()));
        }
    }
    (!parts.is_empty()).then(|| parts.join(", "))
}

/// One [`PartRow`] per part (`part_of` an episode's task) among `episodes`.
fn part_rows(policy: &str, episodes: &[EpisodeRecord], part_of: impl Fn(&TaskRef) -> String) -> Vec<PartRow> {
    let mut by_part: BTreeMap<String, Vec<EpisodeRecord>> = BTreeMap::new();
    for r in episodes {
        by_part.entry(part_of(&r.spec.task)).or_default().push(r.clone());
    }
    by_part.into_iter().map(|(part, records)| PartRow { row: table1_row(policy, &records, None), part }).collect()
}

/// Where a suite goes in the per-suite rows: LIBERO's four in their order, then others by name.
fn suite_order(suite: &str) -> (usize, String) {
    let main = vifo_scenes::suite_names();
    (main.iter().position(|s| *s == suite).unwrap_or(main.len()), suite.to_string())
}

/// Where a task (`suite/index`) goes in the per-task rows: by suite, then by index.
fn task_order(task: &str) -> ((usize, String), usize) {
    match task.parse::<TaskRef>() {
        Ok(t) => (suite_order(&t.suite), t.index),
        Err(_) => (suite_order(task), 0),
    }
}

/// The success flag a metric reads from an outcome.
pub(crate) type Flag = fn(&Outcome) -> Option<Option<bool>>;

pub(crate) fn language(o: &Outcome) -> Option<Option<bool>> {
    match o {
        Outcome::Completed { language_success, .. } => Some(*language_success),
        Outcome::Error { .. } => None,
    }
}

pub(crate) fn cue(o: &Outcome) -> Option<Option<bool>> {
    match o {
        Outcome::Completed { cue_success, .. } => Some(*cue_success),
        Outcome::Error { .. } => None,
    }
}

/// Tallies one metric over the completed records of one protocol; returns the unscored count.
pub(crate) fn tally<'a>(
    records: impl Iterator<Item = &'a EpisodeRecord>,
    protocol: Protocol,
    flag: Flag,
    into: &mut Accuracy,
) -> usize {
    let mut unscored = 0;
    for r in records.filter(|r| r.spec.protocol == protocol) {
        match flag(&r.outcome) {
            Some(Some(success)) => into.add(success),
            Some(None) => unscored += 1,
            None => {}
        }
    }
    unscored
}

fn table1_row(policy: &str, episodes: &[EpisodeRecord], vqa: Option<&VqaScores>) -> Table1Row {
    let stage = |s: Stage| {
        vqa.map(|v| FamilyMean::of(&v.family_stages.iter().filter_map(|(&f, stages)| Some((f, *stages.get(&s)?))).collect()))
    };
    let mut row = Table1Row {
        policy: policy.to_string(),
        det: stage(Stage::Detection),
        sem: stage(Stage::Semantic),
        gnd: stage(Stage::Grounding),
        dec: stage(Stage::Decision),
        fca: vqa.map(|v| FamilyMean::of(&v.family_fca)),
        episodes: episodes.len(),
        ..Table1Row::default()
    };
    row.unscored = tally(episodes.iter(), Protocol::Original, language, &mut row.orig_sr);
    row.orig_sr_ci95 = Interval::of(&row.orig_sr);
    let by_family = by_family(episodes);
    let metrics: [(Protocol, Flag, &mut FamilyMean); 4] = [
        (Protocol::Authorized, cue, &mut row.avf),
        (Protocol::Conflict, language, &mut row.lfr),
        (Protocol::Conflict, cue, &mut row.uvf),
        (Protocol::NoLanguage, cue, &mut row.uvi),
    ];
    for (protocol, flag, into) in metrics {
        let (rates, unscored) = family_rates(&by_family, protocol, flag);
        *into = FamilyMean::of(&rates);
        row.unscored += unscored;
    }
    for r in episodes.iter().filter(|r| matches!(r.outcome, Outcome::Error { .. })) {
        row.errors += 1;
        *row.errors_by_protocol.entry(r.spec.protocol).or_default() += 1;
    }
    row.vtr = match (row.avf.percent(), row.orig_sr.percent()) {
        (Some(avf), Some(orig)) if orig > 0.0 => Some(100.0 * avf / orig),
        _ => None,
    };
    row
}

/// The cue episodes of each family (the family of an episode is that of its cue instance).
fn by_family(episodes: &[EpisodeRecord]) -> BTreeMap<Family, Vec<&EpisodeRecord>> {
    let mut by_family: BTreeMap<Family, Vec<&EpisodeRecord>> = BTreeMap::new();
    for r in episodes {
        if let Some(f) = r.spec.instance.as_deref().and_then(family_of) {
            by_family.entry(f).or_default().push(r);
        }
    }
    by_family
}

/// One metric per family with scored episodes, and the unscored count over all of them.
fn family_rates(by_family: &BTreeMap<Family, Vec<&EpisodeRecord>>, protocol: Protocol, flag: Flag) -> (BTreeMap<Family, Accuracy>, usize) {
    let mut rates = BTreeMap::new();
    let mut unscored = 0;
    for (&family, records) in by_family {
        let mut acc = Accuracy::default();
        unscored += tally(records.iter().copied(), protocol, flag, &mut acc);
        if acc.total > 0 {
            rates.insert(family, acc);
        }
    }
    (rates, unscored)
}

fn table2_rows(policy: &str, episodes: &[EpisodeRecord], vqa: Option<&VqaScores>) -> (Vec<Table2Row>, FamilyCounts) {
    let mut counts = FamilyCounts { policy: policy.to_string(), ..FamilyCounts::default() };
    let by_family = by_family(episodes);
    for (&f, records) in &by_family {
        counts.episodes.insert(f, records.len());
        let errors = records.iter().filter(|r| matches!(r.outcome, Outcome::Error { .. })).count();
        if errors > 0 {
            counts.errors.insert(f, errors);
        }
    }
    let mut rows = Vec::new();
    for metric in Metric::ALL {
        let families = match metric {
            Metric::Vqa => vqa.map(|v| v.families.clone()).unwrap_or_default(),
            Metric::Avf => family_rates(&by_family, Protocol::Authorized, cue).0,
            Metric::Uvf => family_rates(&by_family, Protocol::Conflict, cue).0,
            Metric::Uvi => family_rates(&by_family, Protocol::NoLanguage, cue).0,
        };
        let FamilyMean { percent: avg, ci95: avg_ci95, .. } = FamilyMean::of(&families);
        rows.push(Table2Row { policy: policy.to_string(), metric, families, avg, avg_ci95 });
    }
    (rows, counts)
}

impl Report {
    /// Writes `table1.{md,csv,json}`, `table2.{md,csv,json}`, `suites.{md,csv,json}`,
    /// `tasks.{md,csv,json}`, `pairs.{md,csv,json}`, `paper.md`, one bar chart per Table 2
    /// metric (`chart_vqa.png`, …) and Orig. SR per suite (`chart_suites.png`) into `dir`;
    /// returns the Markdown of both tables.
    pub fn write(&self, dir: &Path) -> std::io::Result<String> {
        crate::runner::create_dir(dir)?;
        let t1 = tables::table1_markdown(self);
        let t2 = tables::table2_markdown(self);
        std::fs::write(dir.join("table1.md"), &t1)?;
        std::fs::write(dir.join("table1.csv"), tables::table1_csv(self))?;
        std::fs::write(dir.join("table1.json"), json(&self.table1)?)?;
        std::fs::write(dir.join("table2.md"), &t2)?;
        std::fs::write(dir.join("table2.csv"), tables::table2_csv(self))?;
        let table2 = serde_json::json!({"sets": self.sets, "rows": self.table2, "counts": self.family_counts});
        std::fs::write(dir.join("table2.json"), json(&table2)?)?;
        for (part, rows) in [(Part::Suite, &self.suites), (Part::Task, &self.tasks)] {
            let name = format!("{}s", part.noun());
            std::fs::write(dir.join(format!("{name}.md")), tables::parts_markdown(self, part, rows))?;
            std::fs::write(dir.join(format!("{name}.csv")), tables::parts_csv(part, rows))?;
            std::fs::write(dir.join(format!("{name}.json")), json(&serde_json::json!({"sets": self.sets, "rows": rows}))?)?;
        }
        std::fs::write(dir.join("pairs.md"), tables::pairs_markdown(self))?;
        std::fs::write(dir.join("paper.md"), tables::paper_markdown(self))?;
        std::fs::write(dir.join("pairs.csv"), tables::pairs_csv(self))?;
        std::fs::write(dir.join("pairs.json"), json(&serde_json::json!({"sets": self.sets, "pairs": self.pairs}))?)?;
        for metric in Metric::ALL {
            let png = chart::family_chart(self, metric).map_err(std::io::Error::other)?;
            std::fs::write(dir.join(format!("chart_{}.png", metric.name().to_lowercase())), png)?;
        }
        std::fs::write(dir.join("chart_suites.png"), chart::suite_chart(self).map_err(std::io::Error::other)?)?;
        Ok(format!("{t1}\n{t2}"))
    }
}

/// Where the files [`Report::write`] writes beside the two tables are, for the line that says
/// where the report went.
pub const MORE_FILES: &str = "per suite and task: suites.md, tasks.md; every two policies compared on the same \
episodes: pairs.md; beside the paper's Table 1: paper.md";

pub(crate) fn json<T: Serialize>(v: &T) -> std::io::Result<String> {
    serde_json::to_string_pretty(v).map(|s| s + "\n").map_err(std::io::Error::other)
}
