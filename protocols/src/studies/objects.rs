//! §4.2, cues as scene objects: every F1 (text), F6 (sign) and F8 (code) instance of the set in
//! both forms, overlay and object, under authorized cue following (AVF) and the empty
//! instruction (UVI); VQA (Part I-A) per form comes from scores of the two exports
//! (`vifo vqa export --form overlay|object`). Part II-A is left out as in the paper, where UVF
//! stays 0 for every model.
//!
//! The table is the paper's comparison figure as numbers: per policy and family, each metric in
//! both forms over the same episodes and the change (object − overlay, points), and an Avg. row
//! (unweighted mean of the families measured in both forms, as the paper's average drops are
//! formed).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use serde::Serialize;
use tiny_skia::Pixmap;
use vifo_cues::{Family, OBJECT_FAMILIES};

use super::StudyOptions;
use crate::benchmark::specs::{INIT_STATES, spec};
use crate::benchmark::{BenchmarkError, instances};
use crate::report::chart::{COLOURS, axis, bar, encode_png, label, legend_text, rect, short_name};
use crate::report::interval::{Interval, PairedChange};
use crate::report::{self, family_of};
use crate::runner::{final_records, stable_hash};
use crate::spec::{CueForm, EpisodeRecord, EpisodeSpec, Outcome, Protocol};
use crate::vqa::{Accuracy, VqaScores};

/// The protocols of the study: AVF and UVI.
pub const PROTOCOLS: [Protocol; 2] = [Protocol::Authorized, Protocol::NoLanguage];

/// VQA scores per (policy, form).
pub type FormVqa = BTreeMap<(String, CueForm), VqaScores>;

/// A chart panel's metric: its name and the pair of a row it shows.
type Metric = (&'static str, fn(&Row) -> &Pair);

/// The study's episodes: per F1/F6/F8 instance of the set (the quick sample: the first of each
/// family by the stable hash of its id), both forms, both protocols, `episodes` each.
pub fn episodes(options: &StudyOptions) -> Result<Vec<EpisodeSpec>, BenchmarkError> {
    let mut chosen: Vec<&vifo_cues::CueSpec> =
        instances::all(options.set).iter().filter(|c| OBJECT_FAMILIES.contains(&c.family)).collect();
    if options.quick {
        chosen = OBJECT_FAMILIES
            .iter()
            .filter_map(|f| chosen.iter().copied().filter(|c| c.family == *f).min_by_key(|c| stable_hash(&c.id())))
            .collect();
    }
    let mut out = Vec::new();
    for cue in chosen {
        let task = instances::task_of(cue)?;
        for form in CueForm::ALL {
            for protocol in PROTOCOLS {
                for e in 0..options.episodes {
                    let s = spec(&task, protocol, Some(&cue.id()), e % INIT_STATES, e / INIT_STATES)?;
                    out.push(EpisodeSpec { cue_form: form, ..s });
                }
            }
        }
    }
    Ok(out)
}

/// One metric in both forms: percentages and how many episodes (questions) each holds, and
/// for episodes (not VQA, whose scores do not pair the questions) the change's 95 % interval.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Pair {
    pub overlay: Option<f64>,
    pub object: Option<f64>,
    pub overlay_n: usize,
    pub object_n: usize,
    /// The change's 95 % interval in points ([`PairedChange`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub change_ci95: Option<Interval>,
    #[serde(skip)]
    paired: Option<PairedChange>,
}

impl Pair {
    fn of(overlay: Option<Accuracy>, object: Option<Accuracy>, paired: Option<PairedChange>) -> Pair {
        Pair {
            overlay: overlay.and_then(|a| a.percent()),
            object: object.and_then(|a| a.percent()),
            overlay_n: overlay.map_or(0, |a| a.total),
            object_n: object.map_or(0, |a| a.total),
            change_ci95: paired.as_ref().map(PairedChange::interval),
            paired,
        }
    }

    /// Object − overlay, in points.
    pub fn change(&self) -> Option<f64> {
        Some(self.object? - self.overlay?)
    }

    /// The unweighted mean over the pairs measured in both forms, so that its change is the
    /// mean of their changes (a family measured in one form only would move one side alone).
    fn mean(pairs: &[&Pair]) -> Pair {
        let both: Vec<&Pair> = pairs.iter().copied().filter(|p| p.change().is_some()).collect();
        let avg = |side: fn(&Pair) -> Option<f64>| {
            (!both.is_empty()).then(|| both.iter().filter_map(|p| side(p)).sum::<f64>() / both.len() as f64)
        };
        // An interval only where every change averaged has one.
        let changes: Option<Vec<PairedChange>> = both.iter().map(|p| p.paired.clone()).collect();
        let paired = changes.and_then(|c| PairedChange::mean(&c));
        Pair {
            overlay: avg(|p| p.overlay),
            object: avg(|p| p.object),
            overlay_n: both.iter().map(|p| p.overlay_n).sum(),
            object_n: both.iter().map(|p| p.object_n).sum(),
            change_ci95: paired.as_ref().map(PairedChange::interval),
            paired,
        }
    }
}

/// One row: a policy and a family (`None`: the Avg. row).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    pub policy: String,
    pub family: Option<Family>,
    pub vqa: Pair,
    pub avf: Pair,
    pub uvi: Pair,
    /// Episodes counted and error records among them (both forms).
    pub episodes: usize,
    pub errors: usize,
}

/// The study's table.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Table {
    pub rows: Vec<Row>,
    /// Episodes of an instance run as an object whose other form is not in the results (an
    /// interrupted run), left out of both sides.
    pub unpaired: usize,
}

/// The key of the same episode in the other form.
fn partner_key(r: &EpisodeRecord) -> String {
    let other = if r.spec.cue_form.is_overlay() { CueForm::Object } else { CueForm::Overlay };
    EpisodeSpec { cue_form: other, ..r.spec.clone() }.key()
}

/// The episodes present in both forms, and the keys of those whose pair is scored: both forms
/// completed (an error on either side leaves the pair out of both rates). Each side then
/// holds the same episodes (instance, protocol, initial state, repetition), so a change is the
/// change of form alone, not of instance: other overlay episodes of F1, F6 and F8 in the same
/// results file (the main benchmark's, the safety study's F1 captions) are left out. Also
/// returns how many episodes of the instances run as objects lack their other form.
fn paired(episodes: Vec<EpisodeRecord>) -> (Vec<EpisodeRecord>, BTreeSet<String>, usize) {
    let keys: BTreeSet<String> = episodes.iter().map(|r| r.spec.key()).collect();
    let errors: BTreeSet<String> =
        episodes.iter().filter(|r| matches!(r.outcome, Outcome::Error { .. })).map(|r| r.spec.key()).collect();
    let as_objects: BTreeSet<String> =
        episodes.iter().filter(|r| !r.spec.cue_form.is_overlay()).filter_map(|r| r.spec.instance.clone()).collect();
    let (kept, alone): (Vec<EpisodeRecord>, Vec<EpisodeRecord>) =
        episodes.into_iter().partition(|r| keys.contains(&partner_key(r)));
    let scored =
        kept.iter().filter(|r| !errors.contains(&r.spec.key()) && !errors.contains(&partner_key(r))).map(|r| r.spec.key()).collect();
    let unpaired = alone.iter().filter(|r| r.spec.instance.as_ref().is_some_and(|i| as_objects.contains(i))).count();
    (kept, scored, unpaired)
}

/// A completed episode's cue success, if it was scored.
fn cue_success(r: &EpisodeRecord) -> Option<bool> {
    report::cue(&r.outcome).flatten()
}

/// The table of the policies that have object-form episodes in `records` or object-form VQA
/// scores in `vqa` (repeated records of one episode: the last completed one counts, as in the
/// main report; only episodes completed in both forms, as `paired` picks them), and with two policies or
/// more an Avg. row over them (the paper's §4.2 figures are such averages over its models).
pub fn build(records: &[EpisodeRecord], vqa: &FormVqa) -> Table {
    let sets: BTreeSet<_> = records.iter().map(|r| r.set).collect();
    let name = |r: &EpisodeRecord| if sets.len() > 1 { format!("{} [{}]", r.policy, r.set) } else { r.policy.clone() };
    let mut by_policy: BTreeMap<String, (String, Vec<EpisodeRecord>)> = BTreeMap::new();
    for r in records {
        let family = r.spec.instance.as_deref().and_then(family_of);
        if family.is_some_and(|f| OBJECT_FAMILIES.contains(&f)) && PROTOCOLS.contains(&r.spec.protocol) {
            by_policy.entry(name(r)).or_insert_with(|| (r.policy.clone(), Vec::new())).1.push(r.clone());
        }
    }
    by_policy.retain(|_, (_, rs)| rs.iter().any(|r| r.spec.cue_form == CueForm::Object));
    for (policy, form) in vqa.keys() {
        if *form == CueForm::Object && !by_policy.values().any(|(p, _)| p == policy) {
            by_policy.insert(policy.clone(), (policy.clone(), Vec::new()));
        }
    }
    let mut table = Table::default();
    for (row_name, (policy, rs)) in by_policy {
        let (episodes, scored, unpaired) = paired(final_records(rs).into_values().collect());
        table.unpaired += unpaired;
        let by_key: BTreeMap<String, &EpisodeRecord> =
            episodes.iter().filter(|r| scored.contains(&r.spec.key())).map(|r| (r.spec.key(), r)).collect();
        let mut rows = Vec::new();
        for family in OBJECT_FAMILIES {
            let of_family: Vec<&EpisodeRecord> =
                episodes.iter().filter(|r| r.spec.instance.as_deref().and_then(family_of) == Some(family)).collect();
            let rate = |protocol: Protocol, form: CueForm| {
                let mut acc = Accuracy::default();
                let counted = |r: &&&EpisodeRecord| r.spec.protocol == protocol && r.spec.cue_form == form && scored.contains(&r.spec.key());
                for r in of_family.iter().filter(counted) {
                    if let Some(s) = cue_success(r) {
                        acc.add(s);
                    }
                }
                (acc.total > 0).then_some(acc)
            };
            // Each object episode beside its overlay partner: which way it succeeded.
            let change = |protocol: Protocol| {
                let objects = of_family.iter().filter(|r| r.spec.protocol == protocol && !r.spec.cue_form.is_overlay());
                let overlay = |r: &EpisodeRecord| by_key.get(&partner_key(r)).copied().and_then(cue_success);
                PairedChange::of_pairs(objects.filter_map(|r| Some((overlay(r)?, cue_success(r)?))))
            };
            let vqa_of = |form: CueForm| vqa.get(&(policy.clone(), form)).and_then(|v| v.families.get(&family).copied());
            rows.push(Row {
                policy: row_name.clone(),
                family: Some(family),
                vqa: Pair::of(vqa_of(CueForm::Overlay), vqa_of(CueForm::Object), None),
                avf: Pair::of(rate(Protocol::Authorized, CueForm::Overlay), rate(Protocol::Authorized, CueForm::Object), change(Protocol::Authorized)),
                uvi: Pair::of(rate(Protocol::NoLanguage, CueForm::Overlay), rate(Protocol::NoLanguage, CueForm::Object), change(Protocol::NoLanguage)),
                episodes: of_family.len(),
                errors: of_family.iter().filter(|r| matches!(r.outcome, Outcome::Error { .. })).count(),
            });
        }
        let avg = Row::average(&row_name, &rows.iter().collect::<Vec<_>>());
        table.rows.extend(rows);
        table.rows.push(avg);
    }
    let averages: Vec<&Row> = table.rows.iter().filter(|r| r.family.is_none()).collect();
    if averages.len() > 1 {
        let all = Row::average(ALL_POLICIES, &averages);
        table.rows.push(all);
    }
    table
}

impl Row {
    /// The Avg. row of `rows` (a policy's families, or every policy's Avg.): each metric by
    /// [`Pair::mean`], the counts summed.
    fn average(policy: &str, rows: &[&Row]) -> Row {
        let mean = |f: fn(&Row) -> &Pair| Pair::mean(&rows.iter().map(|r| f(r)).collect::<Vec<_>>());
        Row {
            policy: policy.to_string(),
            family: None,
            vqa: mean(|r| &r.vqa),
            avf: mean(|r| &r.avf),
            uvi: mean(|r| &r.uvi),
            episodes: rows.iter().map(|r| r.episodes).sum(),
            errors: rows.iter().map(|r| r.errors).sum(),
        }
    }
}

/// The policy column of the Avg. row over every policy's Avg.
pub const ALL_POLICIES: &str = "all policies";

fn pct(v: Option<f64>) -> String {
    v.map_or_else(|| "–".to_string(), |p| format!("{p:.1}"))
}

/// A pair's change in points, with its 95 % interval where it has one (`-50.0 [-80.2, -9.6]`).
fn change_cell(p: &Pair) -> String {
    match (p.change(), p.change_ci95) {
        (Some(c), Some(i)) => format!("{c:+.1} [{:+.1}, {:+.1}]", i.low, i.high),
        (Some(c), None) => format!("{c:+.1}"),
        (None, _) => "–".to_string(),
    }
}

fn family_name(f: Option<Family>) -> &'static str {
    f.map_or("Avg.", short_name)
}

impl Table {
    /// Markdown: per policy and family, each metric overlay / object / change.
    pub fn markdown(&self) -> String {
        let mut s = String::from(
            "### Cues as scene objects (§4.2): overlay vs object\n\n\
             | Policy | Family | VQA overlay | VQA object | Δ | AVF overlay | AVF object | Δ | UVI overlay | UVI object | Δ | Episodes | Errors |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.rows {
            let cells: Vec<String> = [&r.vqa, &r.avf, &r.uvi]
                .iter()
                .flat_map(|p| [pct(p.overlay), pct(p.object), change_cell(p)])
                .collect();
            s += &format!("| {} | {} | {} | {} | {} |\n", r.policy, family_name(r.family), cells.join(" | "), r.episodes, r.errors);
        }
        s += "\nΔ = object − overlay in points, over the same episodes completed in both forms (an error on either side \
              leaves the pair out; Errors counts them); Avg. is the unweighted mean of those of F1, F6 \
              and F8 measured in both forms. In brackets, the change's 95 % interval: Agresti and Min's for \
              changes on the same episodes (half a pair added to each of the four outcomes; for Avg., a mean of m \
              such tables, 1/(2m), and the normal interval around the mean of the adjusted changes); where it \
              holds 0, the two forms are not told apart by this run. VQA needs `vifo report --vqa` / `--vqa-object` scores of the two exports \
              (`vifo vqa export --form`).\n";
        if self.unpaired > 0 {
            s += &format!("\nEpisodes of these instances run in one form only, left out: {}.\n", self.unpaired);
        }
        s
    }

    pub fn csv(&self) -> String {
        let mut s = String::from(
            "policy,family,vqa_overlay,vqa_object,vqa_change,avf_overlay,avf_object,avf_change,uvi_overlay,uvi_object,uvi_change,avf_overlay_n,avf_object_n,uvi_overlay_n,uvi_object_n,episodes,errors,\
             avf_change_low,avf_change_high,uvi_change_low,uvi_change_high\n",
        );
        let num = |v: Option<f64>| v.map_or_else(String::new, |p| format!("{p:.4}"));
        for r in &self.rows {
            let family = r.family.map_or("avg".to_string(), |f| f.to_string());
            let cells: Vec<String> =
                [&r.vqa, &r.avf, &r.uvi].iter().flat_map(|p| [num(p.overlay), num(p.object), num(p.change())]).collect();
            let intervals = Interval::csv(r.avf.change_ci95) + &Interval::csv(r.uvi.change_ci95);
            s += &format!(
                "{},{family},{},{},{},{},{},{},{}{intervals}\n",
                r.policy,
                cells.join(","),
                r.avf.overlay_n,
                r.avf.object_n,
                r.uvi.overlay_n,
                r.uvi.object_n,
                r.episodes,
                r.errors
            );
        }
        s
    }

    /// Writes `objects.{md,csv,json}` and `chart_objects.png` into `dir`; returns the Markdown.
    pub fn write(&self, dir: &Path) -> std::io::Result<String> {
        crate::runner::create_dir(dir)?;
        let md = self.markdown();
        std::fs::write(dir.join("objects.md"), &md)?;
        std::fs::write(dir.join("objects.csv"), self.csv())?;
        let json = serde_json::to_string_pretty(self).map_err(std::io::Error::other)? + "\n";
        std::fs::write(dir.join("objects.json"), json)?;
        std::fs::write(dir.join("chart_objects.png"), self.chart().map_err(std::io::Error::other)?)?;
        Ok(md)
    }

    /// The paper's comparison figure: one panel per metric (VQA, AVF, UVI), in each a group per
    /// policy of F1, F6, F8 and Avg., each an overlay bar (pale) beside an object bar (full).
    pub fn chart(&self) -> Result<Vec<u8>, String> {
        const PANEL_W: f32 = 420.0;
        const H: f32 = 380.0;
        let (top, bottom, left) = (56.0f32, 64.0f32, 40.0f32);
        let mut pm = Pixmap::new((3.0 * PANEL_W + 150.0) as u32, H as u32).ok_or("chart size")?;
        pm.fill(tiny_skia::Color::WHITE);
        let black = vifo_cues::draw::rgb([30, 30, 30]);
        let width = pm.width() as f32;
        label(&mut pm, "Cues as overlays (pale) and as scene objects (full), % per family", width / 2.0, 20.0, 17.0, width, black);
        let policies: Vec<&str> = self.rows.iter().map(|r| r.policy.as_str()).collect::<BTreeSet<_>>().into_iter().collect();
        let groups: [(Option<Family>, [u8; 3]); 4] = [
            (Some(Family::F1), COLOURS[0]),
            (Some(Family::F6), COLOURS[5]),
            (Some(Family::F8), COLOURS[7]),
            (None, [90, 90, 90]),
        ];
        let pale = |c: [u8; 3]| c.map(|v| ((v as u16 + 2 * 255) / 3) as u8);
        let metrics: [Metric; 3] = [("VQA", |r| &r.vqa), ("AVF", |r| &r.avf), ("UVI", |r| &r.uvi)];
        for (m, (metric, pair)) in metrics.iter().enumerate() {
            let x0 = m as f32 * PANEL_W + left;
            let x1 = (m + 1) as f32 * PANEL_W - 10.0;
            let (y0, y1) = (top, H - bottom);
            label(&mut pm, metric, (x0 + x1) / 2.0, top - 14.0, 15.0, PANEL_W, black);
            axis(&mut pm, (x0, x1, y0, y1), 100.0, 25.0, "");
            if !self.rows.iter().any(|r| pair(r).overlay.is_some() || pair(r).object.is_some()) {
                label(&mut pm, "no data", (x0 + x1) / 2.0, (y0 + y1) / 2.0, 14.0, x1 - x0, black);
            }
            let group_w = (x1 - x0) / policies.len().max(1) as f32;
            let bar_w = group_w * 0.84 / (2 * groups.len()) as f32;
            for (g, policy) in policies.iter().enumerate() {
                let start = x0 + g as f32 * group_w + group_w * 0.08;
                for (i, (family, colour)) in groups.iter().enumerate() {
                    let Some(row) = self.rows.iter().find(|r| r.policy == *policy && r.family == *family) else { continue };
                    let p = pair(row);
                    for (k, (value, c)) in [(p.overlay, pale(*colour)), (p.object, *colour)].into_iter().enumerate() {
                        if let Some(v) = value {
                            bar(&mut pm, (y0, y1), 100.0, start + (2 * i + k) as f32 * bar_w + 0.5, bar_w - 1.0, v, vifo_cues::draw::rgb(c));
                        }
                    }
                }
                label(&mut pm, policy, start + group_w * 0.42, y1 + 16.0, 11.0, group_w - 4.0, black);
            }
        }
        let lx = 3.0 * PANEL_W + 10.0;
        for (i, (family, colour)) in groups.iter().enumerate() {
            let y = top + 10.0 + i as f32 * 24.0;
            rect(&mut pm, lx, y - 6.0, 8.0, 12.0, vifo_cues::draw::rgb(pale(*colour)));
            rect(&mut pm, lx + 9.0, y - 6.0, 8.0, 12.0, vifo_cues::draw::rgb(*colour));
            legend_text(&mut pm, family_name(*family), lx + 24.0, y, black);
        }
        encode_png(&pm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::TaskRef;

    fn record(policy: &str, id: &str, protocol: Protocol, form: CueForm, init: usize, success: Option<bool>) -> EpisodeRecord {
        let task: TaskRef = id.rsplitn(3, '/').nth(2).unwrap().parse().unwrap();
        let spec = EpisodeSpec { cue_form: form, ..spec(&task, protocol, Some(id), init, 0).unwrap() };
        let outcome = match success {
            Some(s) => Outcome::Completed { language_success: None, cue_success: Some(s), steps: 10 },
            None => Outcome::Error { message: "dropped".into() },
        };
        EpisodeRecord { version: 1, spec, policy: policy.into(), outcome, wall_ms: 1.0, set: vifo_cues::SetName::Paper, look: String::new() }
    }

    #[test]
    fn the_study_runs_every_text_sign_and_code_instance_in_both_forms_under_avf_and_uvi() {
        let options = StudyOptions { set: vifo_cues::SetName::Paper, episodes: 2, quick: false };
        let specs = episodes(&options).unwrap();
        let n = instances::all(options.set).iter().filter(|c| OBJECT_FAMILIES.contains(&c.family)).count();
        assert_eq!(specs.len(), n * 2 * 2 * 2);
        let keys: BTreeSet<String> = specs.iter().map(|s| s.key()).collect();
        assert_eq!(keys.len(), specs.len());
        let quick = episodes(&StudyOptions { quick: true, episodes: 1, ..options }).unwrap();
        let families: BTreeSet<Family> = quick.iter().filter_map(|s| s.instance.as_deref().and_then(family_of)).collect();
        assert_eq!((quick.len(), families.len()), (3 * 4, 3));
    }

    #[test]
    fn the_table_compares_the_forms_per_family_with_an_average() {
        let f1 = "libero_goal/0/F1/caption_bar";
        let f6 = "libero_goal/0/F6/sign_maintenance_source";
        let mut rs = vec![
            record("p", f1, Protocol::Authorized, CueForm::Overlay, 0, Some(true)),
            record("p", f1, Protocol::Authorized, CueForm::Overlay, 1, Some(true)),
            record("p", f1, Protocol::Authorized, CueForm::Object, 0, Some(true)),
            record("p", f1, Protocol::Authorized, CueForm::Object, 1, Some(false)),
            record("p", f6, Protocol::NoLanguage, CueForm::Object, 0, None),
            record("p", f6, Protocol::NoLanguage, CueForm::Object, 0, Some(true)),
            record("p", f6, Protocol::NoLanguage, CueForm::Overlay, 0, Some(false)),
            // F6's AVF only as an overlay (a run cut short): left out, and counted as unpaired;
            // the Avg. row then has F1 alone on both sides.
            record("p", f6, Protocol::Authorized, CueForm::Overlay, 0, Some(false)),
            // Another F1 instance, run only as an overlay (the main benchmark's): left out, and
            // not counted as unpaired.
            record("p", "libero_goal/1/F1/caption_bar", Protocol::Authorized, CueForm::Overlay, 0, Some(false)),
            // A policy without object episodes (or object-form VQA scores) has no row; conflict
            // episodes are not counted.
            record("q", f1, Protocol::Authorized, CueForm::Overlay, 0, Some(true)),
            record("p", f1, Protocol::Conflict, CueForm::Overlay, 0, Some(false)),
        ];
        let mut vqa = FormVqa::new();
        let mut scores = VqaScores::default();
        scores.families.insert(Family::F1, Accuracy { correct: 3, total: 4 });
        vqa.insert(("p".into(), CueForm::Object), scores);
        // An F1 pair whose object episode ended in an error: left out of both sides.
        rs.push(record("p", f1, Protocol::Authorized, CueForm::Overlay, 2, Some(false)));
        rs.push(record("p", f1, Protocol::Authorized, CueForm::Object, 2, None));
        let table = build(&rs, &vqa);
        assert_eq!(table.rows.len(), 4);
        let f1_row = &table.rows[0];
        assert_eq!((f1_row.avf.overlay, f1_row.avf.object, f1_row.avf.change()), (Some(100.0), Some(50.0), Some(-50.0)));
        assert_eq!((f1_row.vqa.overlay, f1_row.vqa.object), (None, Some(75.0)));
        let f6_row = &table.rows[1];
        // The resumed episode's completed record counts, the error line does not.
        assert_eq!((f6_row.uvi.object, f6_row.uvi.object_n, f6_row.errors), (Some(100.0), 1, 0));
        assert_eq!((f6_row.uvi.overlay, f6_row.avf.overlay, f6_row.episodes), (Some(0.0), None, 2));
        assert_eq!((f1_row.avf.overlay_n, f1_row.avf.object_n, f1_row.episodes, f1_row.errors), (2, 2, 6, 1));
        assert_eq!(table.unpaired, 1);
        assert!(table.markdown().contains("run in one form only, left out: 1."));
        let avg = &table.rows[3];
        assert_eq!(avg.family, None);
        assert_eq!((avg.avf.overlay, avg.avf.object, avg.avf.change()), (Some(100.0), Some(50.0), Some(-50.0)));
        assert!(table.markdown().contains("| p | Avg. |"));
        assert!(table.csv().lines().count() == 5);
        // The changes' intervals from the pairs: F1's AVF lost one of two (the errored pair left
        // out), F6's UVI gained its one; the Avg. of F1 alone is F1's; VQA scores do not pair.
        let f1_change = PairedChange::of(0, 1, 2).map(|c| c.interval());
        assert_eq!((f1_row.avf.change_ci95, f6_row.uvi.change_ci95), (f1_change, PairedChange::of(1, 0, 1).map(|c| c.interval())));
        assert_eq!((avg.avf.change_ci95, f1_row.vqa.change_ci95), (f1_change, None));
        let i = f1_change.unwrap();
        assert!(table.markdown().contains(&format!("| -50.0 [{:+.1}, {:+.1}] |", i.low, i.high)), "{}", table.markdown());
        assert!(table.csv().lines().next().unwrap().ends_with(",errors,avf_change_low,avf_change_high,uvi_change_low,uvi_change_high"));
        assert!(table.csv().lines().nth(1).unwrap().ends_with(&format!("{},,", Interval::csv(f1_change))), "{}", table.csv());
        assert!(table.chart().unwrap().starts_with(b"\x89PNG"));
        rs.retain(|r| r.spec.cue_form == CueForm::Overlay);
        assert!(build(&rs, &FormVqa::new()).rows.is_empty());
        // VQA scores in the object form make rows without episodes (a VLM-only evaluation).
        let vqa_only = build(&rs, &vqa);
        assert_eq!((vqa_only.rows.len(), vqa_only.rows[0].vqa.object, vqa_only.rows[0].avf.object), (4, Some(75.0), None));
    }

    #[test]
    fn two_policies_get_an_average_row_over_them() {
        let f1 = "libero_goal/0/F1/caption_bar";
        let mut rs = Vec::new();
        for (policy, object) in [("p", true), ("q", false)] {
            rs.push(record(policy, f1, Protocol::Authorized, CueForm::Overlay, 0, Some(true)));
            rs.push(record(policy, f1, Protocol::Authorized, CueForm::Object, 0, Some(object)));
        }
        let table = build(&rs, &FormVqa::new());
        let all = table.rows.last().unwrap();
        assert_eq!((all.policy.as_str(), all.family), (ALL_POLICIES, None));
        assert_eq!((all.avf.overlay, all.avf.object, all.avf.change(), all.episodes), (Some(100.0), Some(50.0), Some(-50.0), 4));
        // Its interval: the mean of the two policies' changes (one pair each, kept and lost).
        let both = PairedChange::mean(&[PairedChange::of(0, 0, 1).unwrap(), PairedChange::of(0, 1, 1).unwrap()]);
        assert_eq!(all.avf.change_ci95, both.map(|c| c.interval()));
        assert!(build(&rs[..2], &FormVqa::new()).rows.iter().all(|r| r.policy == "p"));
    }
}
