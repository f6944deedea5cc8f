//! Markdown and CSV renderings of the two tables and the rows per suite and per task. Markdown
//! marks the best value of each column (Table 1, respecting ↑/↓; per suite or task, within
//! each) or of each row (Table 2, highest, as the paper does) in bold and the second best
//! underlined.

use vifo_cues::Family;

use super::{FamilyMean, Interval, Part, PartRow, Report, Table1Row, pairs, paper};
use crate::vqa::Accuracy;

fn pct(a: Option<&FamilyMean>) -> Option<f64> {
    a.and_then(FamilyMean::percent)
}

fn ci(a: Option<&FamilyMean>) -> Option<Interval> {
    a.and_then(|m| m.ci95)
}

/// A Table 1 column: its Markdown header and CSV name, whether higher is better, and a row's
/// value and 95 % interval.
struct Column {
    header: &'static str,
    csv: &'static str,
    up: bool,
    value: fn(&Table1Row) -> Option<f64>,
    /// `None` for VTR, a ratio of two rates: see theirs.
    interval: Option<fn(&Table1Row) -> Option<Interval>>,
}

const fn column(header: &'static str, csv: &'static str, up: bool, value: fn(&Table1Row) -> Option<f64>, interval: fn(&Table1Row) -> Option<Interval>) -> Column {
    Column { header, csv, up, value, interval: Some(interval) }
}

const COLUMNS: [Column; 11] = [
    column("Det.↑", "Det", true, |r| pct(r.det.as_ref()), |r| ci(r.det.as_ref())),
    column("Sem.↑", "Sem", true, |r| pct(r.sem.as_ref()), |r| ci(r.sem.as_ref())),
    column("Gnd.↑", "Gnd", true, |r| pct(r.gnd.as_ref()), |r| ci(r.gnd.as_ref())),
    column("Dec.↑", "Dec", true, |r| pct(r.dec.as_ref()), |r| ci(r.dec.as_ref())),
    column("FCA↑", "FCA", true, |r| pct(r.fca.as_ref()), |r| ci(r.fca.as_ref())),
    column("Orig. SR↑", "Orig_SR", true, |r| r.orig_sr.percent(), |r| r.orig_sr_ci95),
    column("AVF↑", "AVF", true, |r| r.avf.percent(), |r| r.avf.ci95),
    Column { header: "VTR↑", csv: "VTR", up: true, value: |r| r.vtr, interval: None },
    column("LFR↑", "LFR", true, |r| r.lfr.percent(), |r| r.lfr.ci95),
    column("UVF↓", "UVF", false, |r| r.uvf.percent(), |r| r.uvf.ci95),
    column("UVI↓", "UVI", false, |r| r.uvi.percent(), |r| r.uvi.ci95),
];

/// Table 1's columns measured on episodes (Orig. SR onwards): the columns per suite and task.
const EPISODE_COLUMNS: std::ops::RangeFrom<usize> = 5..;

/// What the columns measure (the paper's §3.3), under the table where a reader meets them.
const COLUMN_LEGEND: &str = "\nColumns. Part I-A (VQA, `vifo vqa`): accuracy on the cue's detection (Det.), its meaning \
(Sem.), its grounding in the scene (Gnd.) and the action it asks for (Dec.); FCA: all four of one cue instance right. \
Part I-B (authorized): Orig. SR, language success without cues; AVF, the cue's task done when the language says \
to follow the cue; VTR = AVF / Orig. SR × 100. Part II-A (conflict: language and cue name different tasks): LFR, the \
language's task done; UVF, the cue's. Part II-B (no language): UVI, the cue's task done. `episodes` counts this \
table's episodes (the original protocol's and the cue protocols', not the extended studies').\n";

/// Cells with the best value bold and the second best underlined (only where the values differ:
/// a column of equal values, such as a family every model fails, ranks nothing).
pub(crate) fn ranked_cells(values: &[Option<f64>], higher_is_better: bool) -> Vec<String> {
    let key = |v: f64| if higher_is_better { v } else { -v };
    let mut distinct: Vec<f64> = values.iter().flatten().map(|&v| round1(key(v))).collect();
    distinct.sort_by(|a, b| b.total_cmp(a));
    distinct.dedup();
    let marked = distinct.len() >= 2;
    values
        .iter()
        .map(|v| match v {
            None => "–".to_string(),
            Some(v) => {
                let text = format!("{v:.1}");
                let k = round1(key(*v));
                if marked && distinct.first() == Some(&k) {
                    format!("**{text}**")
                } else if marked && distinct.get(1) == Some(&k) {
                    format!("<u>{text}</u>")
                } else {
                    text
                }
            }
        })
        .collect()
}

/// `v` as its one-decimal cell shows it (`{:.1}` rounds a tie to even: 6.25 shows as 6.2), so
/// that two cells that read alike rank alike.
fn round1(v: f64) -> f64 {
    format!("{v:.1}").parse().unwrap_or(v)
}

fn frac(a: &Accuracy) -> String {
    format!("{}/{}", a.correct, a.total)
}

/// The lines naming the instance set(s) the episodes come from and the look(s) they were
/// drawn with.
fn provenance(report: &Report) -> String {
    let sets = match &report.sets[..] {
        [] => String::new(),
        [one] => format!("Instance set: {one}.\n\n"),
        many => {
            let names: Vec<String> = many.iter().map(ToString::to_string).collect();
            format!("Instance sets: {} (one row per policy and set; sets are not pooled).\n\n", names.join(", "))
        }
    };
    let looks = match &report.looks[..] {
        [] => String::new(),
        [one] => format!("Look: {one}.\n\n"),
        many => format!("Looks: {} (mixed on request; their rows are not comparable).\n\n", many.join(", ")),
    };
    let blind = match &report.no_images[..] {
        [] => String::new(),
        rows => format!("Sent no images (they read the simulator), so the same with any look: {}.\n\n", rows.join(", ")),
    };
    sets + &looks + &blind
}

/// A table's heading, the provenance lines and its header rows: the `lead` columns, then
/// `columns`, then `episodes` and `errors`.
fn table_head(title: &str, report: &Report, lead: &[&str], columns: &[Column]) -> String {
    let mut out = format!("### {title}\n\n{}|", provenance(report));
    for name in lead.iter().copied().chain(columns.iter().map(|c| c.header)).chain(["episodes", "errors"]) {
        out += &format!(" {name} |");
    }
    out += "\n|";
    out += &"---|".repeat(lead.len() + columns.len() + 2);
    out.push('\n');
    out
}

/// Table 1 in Markdown, with the episode counts behind each rate below it.
pub fn table1_markdown(report: &Report) -> String {
    let rows = &report.table1;
    let mut out = table_head("Table 1: overall results (%)", report, &["Model"], &COLUMNS);
    let columns: Vec<Vec<String>> =
        COLUMNS.iter().map(|c| ranked_cells(&rows.iter().map(c.value).collect::<Vec<_>>(), c.up)).collect();
    for (i, row) in rows.iter().enumerate() {
        out += &format!("| {} |", row.policy);
        for column in &columns {
            out += &format!(" {} |", column[i]);
        }
        out += &format!(" {} | {} |\n", row.episodes, row.errors);
    }
    // The paper's caption says "highest"; its UVF column marks the lowest, its UVI the highest.
    out += "\nBold: the best value of each column by its arrow (↓: the lowest), underlined: the second.\n";
    out += "\nEach column but Orig. SR is the unweighted mean of the cue families' rates, as Table 2's Avg.\n";
    out += COLUMN_LEGEND;
    let partial: Vec<String> = rows.iter().filter_map(partial_means).collect();
    if !partial.is_empty() {
        out += &format!(
            "\nMeans over fewer than the {} families (not comparable with a run over all of them): {}.\n",
            Family::ALL.len(),
            partial.join("; ")
        );
    }
    out += "\nSuccesses / scored episodes, all families together (errors excluded):\n\n| Model | Orig. SR | AVF | LFR | UVF | UVI | errors by protocol | unscored |\n|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let errors: Vec<String> = r.errors_by_protocol.iter().map(|(p, n)| format!("{} {n}", p.name())).collect();
        out += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.policy,
            frac(&r.orig_sr),
            frac(&r.avf.pooled),
            frac(&r.lfr.pooled),
            frac(&r.uvf.pooled),
            frac(&r.uvi.pooled),
            if errors.is_empty() { "–".to_string() } else { errors.join(", ") },
            r.unscored
        );
    }
    let with_interval: Vec<&Column> = COLUMNS.iter().filter(|c| c.interval.is_some()).collect();
    out += &format!("\n{INTERVALS_NOTE}\n\n| Model |");
    for c in &with_interval {
        out += &format!(" {} |", c.header);
    }
    out += &format!("\n|---|{}\n", "---|".repeat(with_interval.len()));
    for r in rows {
        out += &format!("| {} |", r.policy);
        for c in &with_interval {
            let cell = c.interval.and_then(|interval| interval(r)).map_or("–".to_string(), |i| i.text());
            out += &format!(" {cell} |");
        }
        out.push('\n');
    }
    out
}

/// What the intervals are, where a reader meets them.
const INTERVALS_NOTE: &str = "95 % intervals: where each figure's true value plausibly lies given how many episodes (or \
questions) it rests on; two models whose intervals overlap widely are not told apart by this run. For a mean of m rates (the \
cue families'; Orig. SR is one rate) each rate gets 2/m successes and 4/m trials added, and the interval is the normal \
one around the mean of the adjusted rates (Price and Bonett 2004; for one rate, Agresti and Coull's). VTR, a ratio, has \
none of its own.";

/// The row's family means over some but not all families (`pi: AVF 2/8, UVI 3/8`), if any.
fn partial_means(row: &Table1Row) -> Option<String> {
    let means = [
        ("Det.", row.det.as_ref()),
        ("Sem.", row.sem.as_ref()),
        ("Gnd.", row.gnd.as_ref()),
        ("Dec.", row.dec.as_ref()),
        ("FCA", row.fca.as_ref()),
        ("AVF", Some(&row.avf)),
        ("LFR", Some(&row.lfr)),
        ("UVF", Some(&row.uvf)),
        ("UVI", Some(&row.uvi)),
    ];
    let all = Family::ALL.len();
    let short: Vec<String> = means
        .iter()
        .filter_map(|(name, m)| m.filter(|m| (1..all).contains(&m.families)).map(|m| format!("{name} {}/{all}", m.families)))
        .collect();
    (!short.is_empty()).then(|| format!("{}: {}", row.policy, short.join(", ")))
}

/// Table 1 as CSV (percentages to two decimals, empty where undefined).
pub fn table1_csv(report: &Report) -> String {
    let mut out = format!("policy{},episodes,errors,unscored{}\n", csv_names(&COLUMNS), csv_interval_names(&COLUMNS));
    for row in &report.table1 {
        out += &csv_field(&row.policy);
        out += &csv_values(&COLUMNS, row);
        out += &format!(",{},{},{}", row.episodes, row.errors, row.unscored);
        out += &csv_intervals(&COLUMNS, row);
        out.push('\n');
    }
    out
}

/// `,Det,Sem,…`: the columns' CSV names.
fn csv_names(columns: &[Column]) -> String {
    columns.iter().map(|c| format!(",{}", c.csv)).collect()
}

/// `,Det_low,Det_high,…` for the columns with intervals, after every other column (a script that
/// reads the columns before them by position still reads the same).
fn csv_interval_names(columns: &[Column]) -> String {
    columns.iter().filter(|c| c.interval.is_some()).map(|c| format!(",{0}_low,{0}_high", c.csv)).collect()
}

/// A row's values under [`csv_names`] (percentages to two decimals, empty where undefined).
fn csv_values(columns: &[Column], row: &Table1Row) -> String {
    columns.iter().map(|c| format!(",{}", (c.value)(row).map_or(String::new(), |v| format!("{v:.2}")))).collect()
}

/// A row's intervals under [`csv_interval_names`].
fn csv_intervals(columns: &[Column], row: &Table1Row) -> String {
    columns.iter().filter_map(|c| c.interval).map(|interval| Interval::csv(interval(row))).collect()
}

/// Rows per suite or per task in Markdown, part by part, ranked within each part; Orig. SR
/// with its successes out of scored episodes (LIBERO's papers quote it per suite), and a task
/// with its instruction.
pub fn parts_markdown(report: &Report, part: Part, rows: &[PartRow]) -> String {
    let whose = part.noun();
    let header = whose[..1].to_uppercase() + &whose[1..];
    let columns = &COLUMNS[EPISODE_COLUMNS];
    let mut out = table_head(&format!("Per {whose} (%)"), report, &["Model", &header], columns);
    for group in rows.chunk_by(|a, b| a.part == b.part) {
        let cells: Vec<Vec<String>> =
            columns.iter().map(|c| ranked_cells(&group.iter().map(|p| (c.value)(&p.row)).collect::<Vec<_>>(), c.up)).collect();
        let name = match part {
            Part::Suite => group[0].part.clone(),
            Part::Task => with_instruction(&group[0].part),
        };
        for (i, p) in group.iter().enumerate() {
            out += &format!("| {} | {name} |", p.row.policy);
            for (k, column) in cells.iter().enumerate() {
                let counts = match p.row.orig_sr_ci95 {
                    Some(ci) if k == 0 => format!(" ({}; {})", frac(&p.row.orig_sr), ci.text()),
                    _ => String::new(),
                };
                out += &format!(" {}{counts} |", column[i]);
            }
            out += &format!(" {} | {} |\n", p.row.episodes, p.row.errors);
        }
    }
    out += &format!("\nBold: the best value of each column within a {whose} by its arrow (↓: the lowest), underlined: the second.\n");
    out += &format!(
        "\nTable 1's columns over each {whose}'s episodes alone: Orig. SR pooled over its original episodes (successes / \
         scored episodes, then its 95 % interval; LIBERO's results are quoted per suite, 50 episodes of each task), the cue \
         columns the unweighted mean of the cue families' rates within the {whose}. Every column's interval is in the \
         CSV and JSON files.\n\n{INTERVALS_NOTE}\n"
    );
    out
}

/// `libero_goal/3 (put the wine bottle on top of the cabinet)` for a built-in task.
fn with_instruction(task: &str) -> String {
    let instruction = task
        .parse::<crate::spec::TaskRef>()
        .ok()
        .and_then(|t| vifo_scenes::task(&t.suite, t.index))
        .map(|t| t.instruction.clone());
    match instruction {
        Some(i) => format!("{task} ({i})"),
        None => task.to_string(),
    }
}

/// Rows per suite or per task as CSV (percentages to two decimals, empty where undefined).
pub fn parts_csv(part: Part, rows: &[PartRow]) -> String {
    let column = part.noun();
    let columns = &COLUMNS[EPISODE_COLUMNS];
    let mut out = format!(
        "policy,{column}{},Orig_SR_successes,Orig_SR_scored,episodes,errors,unscored{}\n",
        csv_names(columns),
        csv_interval_names(columns)
    );
    for p in rows {
        let r = &p.row;
        out += &format!("{},{}", csv_field(&r.policy), csv_field(&p.part));
        out += &csv_values(columns, r);
        out += &format!(",{},{},{},{},{}", r.orig_sr.correct, r.orig_sr.total, r.episodes, r.errors, r.unscored);
        out += &csv_intervals(columns, r);
        out.push('\n');
    }
    out
}

/// Each row that names one of the paper's models beside the paper's Table 1 row: this run's
/// figures, their 95 % intervals, and the paper's with whether each lies within the interval.
pub fn paper_markdown(report: &Report) -> String {
    let mut out = format!("### Beside the paper's Table 1 (%)\n\n{}", provenance(report));
    let matched: Vec<(&Table1Row, &paper::PaperRow)> = report.table1.iter().filter_map(|r| Some((r, paper::paper_row(r)?))).collect();
    if matched.is_empty() {
        let profiles: Vec<&str> = paper::TABLE1.iter().map(|p| p.profile).collect();
        return out
            + &format!(
                "No row names one of the paper's models. A served model's rows carry its profile ({}) by default \
                 (`<profile>@<url>`), or name it so with `--policy-name` (`pi05`, `pi05-30k`), and its row appears here \
                 beside the paper's.\n",
                profiles.join(", ")
            );
    }
    out += "| Model | |";
    for c in &COLUMNS {
        out += &format!(" {} |", c.header);
    }
    out += &format!("\n|---|---|{}\n", "---|".repeat(COLUMNS.len()));
    for (row, paper) in &matched {
        let ours: Vec<String> = COLUMNS.iter().map(|c| (c.value)(row).map_or("–".to_string(), |v| format!("{v:.1}"))).collect();
        out += &format!("| {} | this run | {} |\n", row.policy, ours.join(" | "));
        let intervals: Vec<String> =
            COLUMNS.iter().map(|c| c.interval.and_then(|i| i(row)).map_or("–".to_string(), |i| i.text())).collect();
        out += &format!("| | 95 % interval | {} |\n", intervals.join(" | "));
        let theirs: Vec<String> = COLUMNS
            .iter()
            .zip(paper.figures)
            .map(|(c, figure)| match c.interval.and_then(|i| i(row)) {
                Some(i) if figure < i.low => format!("**{figure:.1}** (below)"),
                Some(i) if figure > i.high => format!("**{figure:.1}** (above)"),
                Some(_) => format!("{figure:.1} (within)"),
                None => format!("{figure:.1}"),
            })
            .collect();
        out += &format!("| | paper: {} | {} |\n", paper.model, theirs.join(" | "));
    }
    out += "\nThe paper's figures come from the original MuJoCo LIBERO with each model served as its own LIBERO \
            evaluation script serves it, over the paper's instance set. \"within\": this run cannot tell its figure \
            from the paper's; \"above\" or \"below\" (bold): the paper's figure lies outside this run's 95 % interval, \
            a difference beyond this run's noise (the simulator, the look, the checkpoint or the serving differ). VQA \
            columns need `vifo report --vqa`.\n";
    if report.looks.iter().any(|l| l == vifo_scenes::look::BUILT_IN) {
        out += "\nSome rows were drawn with the built-in look: a LIBERO-trained model sees LIBERO's images only with \
                LIBERO's assets installed (README, \"LIBERO's own look\"), and scores far lower without them.\n";
    }
    out
}

/// The pairwise comparisons in Markdown: per pair of rows, each metric's difference with its
/// 95 % interval and the episodes it rests on, bold where the interval leaves out 0.
pub fn pairs_markdown(report: &Report) -> String {
    let mut out = format!("### Policies compared on the episodes both ran (A − B, points)\n\n{}", provenance(report));
    if report.pairs.is_empty() {
        return out + "No two policies ran the same episodes: nothing to compare.\n";
    }
    out += "| A | B |";
    for (header, ..) in pairs::METRICS {
        out += &format!(" {header} |");
    }
    out += &format!("\n|---|---|{}\n", "---|".repeat(pairs::METRICS.len()));
    for c in &report.pairs {
        out += &format!("| {} | {} |", c.a, c.b);
        for d in c.differences() {
            let cell = d.map_or("–".to_string(), |d| {
                let points = if d.clear() { format!("**{:+.1}**", d.points) } else { format!("{:+.1}", d.points) };
                format!("{points} [{:+.1}, {:+.1}] (n={})", d.ci95.low, d.ci95.high, d.pairs)
            });
            out += &format!(" {cell} |");
        }
        out.push('\n');
    }
    out += "\nEach cell is A's rate less B's over the n episodes both completed (every policy runs the same episodes: \
            task, cue instance, initial state and seed), the cue columns the unweighted mean over the cue families of \
            each family's difference, as Table 1's columns are formed. In brackets, its 95 % interval for changes on the \
            same episodes (Agresti and Min: half a pair added to each of the four outcomes; for a mean over m families, \
            1/(2m), and the normal interval around the mean of the adjusted changes). Bold: the interval leaves out 0, so the two differ \
            beyond this run's noise; that holds for each comparison on its own, and among many some are bold by chance. \
            The arrows are Table 1's: a positive AVF difference favours A, a positive UVF difference favours B.\n";
    out
}

/// The pairwise comparisons as CSV: per metric the difference, its interval and its pairs.
pub fn pairs_csv(report: &Report) -> String {
    let mut out = String::from("a,b");
    for (_, name, ..) in pairs::METRICS {
        out += &format!(",{name}_diff,{name}_low,{name}_high,{name}_pairs");
    }
    out.push('\n');
    for c in &report.pairs {
        out += &format!("{},{}", csv_field(&c.a), csv_field(&c.b));
        for d in c.differences() {
            out += &d.map_or(",,,,".to_string(), |d| format!(",{:.2},{:.2},{:.2},{}", d.points, d.ci95.low, d.ci95.high, d.pairs));
        }
        out.push('\n');
    }
    out
}

/// Table 2 in Markdown: per policy the four metric rows and the cue-episode counts.
pub fn table2_markdown(report: &Report) -> String {
    let mut out = format!("### Table 2: results per cue family (%)\n\n{}| Model | Metric |", provenance(report));
    for f in Family::ALL {
        out += &format!(" {} |", super::chart::short_name(f));
    }
    out += " Avg. |\n|---|---|";
    out += &"---|".repeat(Family::ALL.len() + 1);
    out.push('\n');
    for counts in &report.family_counts {
        for row in report.table2.iter().filter(|r| r.policy == counts.policy) {
            let values: Vec<Option<f64>> = Family::ALL.iter().map(|f| row.families.get(f).and_then(Accuracy::percent)).collect();
            let cells = ranked_cells(&values, true);
            let arrow = if row.metric.higher_is_better() { "↑" } else { "↓" };
            let avg = row.avg.map_or("–".into(), |a| format!("{a:.1}"));
            out += &format!("| {} | {}{arrow} | {} | {avg} |\n", row.policy, row.metric.name(), cells.join(" | "));
        }
        for (label, map) in [("episodes", &counts.episodes), ("errors", &counts.errors)] {
            let cells: Vec<String> = Family::ALL.iter().map(|f| map.get(f).copied().unwrap_or(0).to_string()).collect();
            let total: usize = map.values().sum();
            out += &format!("| {} | {label} | {} | {total} |\n", counts.policy, cells.join(" | "));
        }
    }
    out
}

/// Table 2 as CSV: one line per (policy, metric), then episode and error counts; the rates'
/// 95 % intervals after every other column (empty on the count lines).
pub fn table2_csv(report: &Report) -> String {
    let columns: Vec<String> = Family::ALL.iter().map(ToString::to_string).chain(["Avg".to_string()]).collect();
    let mut out = format!("policy,metric,{}", columns.join(","));
    for c in &columns {
        out += &format!(",{c}_low,{c}_high");
    }
    out.push('\n');
    for row in &report.table2 {
        out += &format!("{},{}", csv_field(&row.policy), row.metric.name());
        for f in Family::ALL {
            out += &format!(",{}", row.families.get(&f).and_then(Accuracy::percent).map_or(String::new(), |v| format!("{v:.2}")));
        }
        out += &format!(",{}", row.avg.map_or(String::new(), |v| format!("{v:.2}")));
        for f in Family::ALL {
            out += &Interval::csv(row.families.get(&f).and_then(Interval::of));
        }
        out += &Interval::csv(row.avg_ci95);
        out.push('\n');
    }
    for counts in &report.family_counts {
        for (label, map) in [("episodes", &counts.episodes), ("errors", &counts.errors)] {
            out += &format!("{},{label}", csv_field(&counts.policy));
            for f in Family::ALL {
                out += &format!(",{}", map.get(&f).copied().unwrap_or(0));
            }
            out += &format!(",{}{}\n", map.values().sum::<usize>(), ",,".repeat(columns.len()));
        }
    }
    out
}

/// RFC 4180 quoting where needed.
pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_and_second_are_marked_in_the_right_direction() {
        let v = [Some(10.0), Some(30.0), None, Some(20.0)];
        assert_eq!(ranked_cells(&v, true), ["10.0", "**30.0**", "–", "<u>20.0</u>"]);
        assert_eq!(ranked_cells(&v, false), ["**10.0**", "30.0", "–", "<u>20.0</u>"]);
        assert_eq!(ranked_cells(&[Some(5.0)], true), ["5.0"]);
        assert_eq!(ranked_cells(&[Some(0.0), None, Some(0.0)], true), ["0.0", "–", "0.0"]);
        // 1/16 = 6.25 shows as 6.2, as 31/500 does: the two rank alike.
        assert_eq!(ranked_cells(&[Some(6.25), Some(6.2), Some(1.0)], true), ["**6.2**", "**6.2**", "<u>1.0</u>"]);
        assert_eq!(csv_field("a,b"), "\"a,b\"");
    }
}
