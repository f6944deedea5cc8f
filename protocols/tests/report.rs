//! Tables 1 and 2 from synthetic records with known rates, and the written files.

use std::collections::BTreeMap;

use vifo_cues::{Family, SetName};
use vifo_protocols::report::{self, Metric, Table1Row, family_of};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec, Outcome, Protocol, RESULTS_VERSION, TaskRef};
use vifo_protocols::vqa::{Accuracy, Stage, VqaScores};

fn record(policy: &str, protocol: Protocol, family: &str, n: usize, outcome: Outcome) -> EpisodeRecord {
    let task = TaskRef { suite: "libero_goal".into(), index: 1 };
    EpisodeRecord {
        version: RESULTS_VERSION,
        spec: EpisodeSpec {
            task: task.clone(),
            protocol,
            instance: protocol.uses_cue().then(|| format!("libero_goal/1/{family}/some_variant")),
            init: n,
            episode: 0,
            instruction: String::new(),
            language_task: None,
            cue_task: None,
            seed: n as u64,
            cue_form: Default::default(),
        },
        policy: policy.into(),
        outcome,
        wall_ms: 1.0,
        set: SetName::Paper,
        look: String::new(),
    }
}

fn done(language: Option<bool>, cue: Option<bool>) -> Outcome {
    Outcome::Completed { language_success: language, cue_success: cue, steps: 10 }
}

fn error() -> Outcome {
    Outcome::Error { message: "dropped".into() }
}

fn records() -> Vec<EpisodeRecord> {
    let mut r = Vec::new();
    // pi: Orig. SR 3/4; one error first, then completed on resume (counts once, as success).
    for (n, ok) in [true, true, false, true].into_iter().enumerate() {
        r.push(record("pi", Protocol::Original, "-", n, done(Some(ok), None)));
    }
    r.push(record("pi", Protocol::Original, "-", 4, error()));
    // AVF: F1 2/2, F2 0/2 and one F2 error that stays an error.
    for n in 0..2 {
        r.push(record("pi", Protocol::Authorized, "F1", n, done(None, Some(true))));
        r.push(record("pi", Protocol::Authorized, "F2", 10 + n, done(None, Some(false))));
    }
    r.push(record("pi", Protocol::Authorized, "F2", 20, error()));
    // Conflict: language followed 2/2, cue never.
    for n in 0..2 {
        r.push(record("pi", Protocol::Conflict, "F7", n, done(Some(true), Some(false))));
    }
    // No language: UVI 25 % (F7 1/2, F8 0/3), though 1 of 5 pooled; one record lacks its cue flag.
    for (n, ok) in [true, false].into_iter().enumerate() {
        r.push(record("pi", Protocol::NoLanguage, "F7", n, done(None, Some(ok))));
        r.push(record("pi", Protocol::NoLanguage, "F8", 10 + n, done(None, Some(false))));
    }
    r.push(record("pi", Protocol::NoLanguage, "F8", 12, done(None, Some(false))));
    r.push(record("pi", Protocol::NoLanguage, "F8", 30, done(None, None)));
    // The resumed original episode 4: an error line, then a completed success.
    r.push(record("pi", Protocol::Original, "-", 4, done(Some(true), None)));
    // A second policy with only original episodes.
    r.push(record("oft", Protocol::Original, "-", 0, done(Some(true), None)));
    r
}

fn vqa() -> BTreeMap<String, VqaScores> {
    let acc = |correct, total| Accuracy { correct, total };
    let mut s = VqaScores { model: "pi".into(), fca: acc(1, 10), ..VqaScores::default() };
    // Per stage, F1 right c1 of 4 and F2 c2 of 6: pooled 50, 60, 70, 80 %; by family 58.3,
    // 62.5, 66.7, 83.3 %.
    for (stage, (c1, c2)) in Stage::ALL.into_iter().zip([(4, 1), (3, 3), (2, 5), (4, 4)]) {
        s.stages.insert(stage, acc(c1 + c2, 10));
        s.family_stages.entry(Family::F1).or_default().insert(stage, acc(c1, 4));
        s.family_stages.entry(Family::F2).or_default().insert(stage, acc(c2, 6));
    }
    s.family_fca = BTreeMap::from([(Family::F1, acc(1, 4)), (Family::F2, acc(0, 6))]);
    s.families.insert(Family::F1, acc(3, 4));
    s.families.insert(Family::F2, acc(1, 4));
    BTreeMap::from([("pi".to_string(), s), ("vlm-only".to_string(), VqaScores::default())])
}

#[test]
fn rates_follow_the_paper_definitions() {
    let report = report::build(&records(), &vqa());
    let names: Vec<&str> = report.table1.iter().map(|r| r.policy.as_str()).collect();
    assert_eq!(names, ["oft", "pi", "vlm-only"]);
    let pi = &report.table1[1];
    assert_eq!((pi.orig_sr.correct, pi.orig_sr.total), (4, 5));
    assert_eq!((pi.avf.pooled.correct, pi.avf.pooled.total, pi.avf.percent()), (2, 4, Some(50.0)));
    assert!((pi.vtr.unwrap() - 50.0 / 80.0 * 100.0).abs() < 1e-9);
    assert_eq!((pi.lfr.pooled.correct, pi.lfr.pooled.total, pi.uvf.pooled.correct, pi.uvf.pooled.total), (2, 2, 0, 2));
    // Table 1 averages the families' rates, as the paper's Table 1 equals its Table 2's Avg.
    assert_eq!((pi.uvi.pooled.correct, pi.uvi.pooled.total, pi.uvi.families), (1, 5, 2));
    assert_eq!(pi.uvi.percent(), Some(25.0), "the mean of F7's 50 % and F8's 0 %, not 1 of 5");
    assert_eq!((pi.errors, pi.unscored), (1, 1));
    assert_eq!(pi.errors_by_protocol[&Protocol::Authorized], 1);
    assert_eq!(pi.episodes, 5 + 5 + 2 + 6);
    let det = pi.det.as_ref().unwrap();
    assert_eq!((det.pooled.correct, det.pooled.total), (5, 10));
    assert!((det.percent().unwrap() - (100.0 + 100.0 / 6.0) / 2.0).abs() < 1e-9, "{det:?}");
    assert_eq!(pi.fca.as_ref().unwrap().percent(), Some(12.5));
    assert!(report.table1[0].det.is_none() && report.table1[0].avf.pooled.total == 0);
    // A mean over fewer than the eight families is said to be one.
    let table = report::tables::table1_markdown(&report);
    assert!(
        table.contains("Means over fewer than the 8 families (not comparable with a run over all of them): pi: Det. 2/8, Sem. 2/8, Gnd. 2/8, Dec. 2/8, FCA 2/8, AVF 2/8, LFR 1/8, UVF 1/8, UVI 2/8.\n"),
        "{table}"
    );

    let row = |metric| report.table2.iter().find(|r| r.policy == "pi" && r.metric == metric).unwrap();
    assert_eq!(row(Metric::Avf).families[&Family::F1].percent(), Some(100.0));
    assert_eq!(row(Metric::Avf).avg, Some(50.0), "unweighted mean of F1 100 and F2 0");
    assert_eq!(row(Metric::Uvi).avg, Some(25.0));
    assert_eq!(row(Metric::Vqa).avg, Some(50.0));
    assert_eq!(row(Metric::Uvf).families.len(), 1);
    let counts = report.family_counts.iter().find(|c| c.policy == "pi").unwrap();
    assert_eq!((counts.episodes[&Family::F2], counts.errors[&Family::F2]), (3, 1));
    assert_eq!(family_of("libero_10/4/F6/sign_zone_target"), Some(Family::F6));
    assert_eq!(family_of("libero_10/4"), None);
}

#[test]
fn files_are_written() {
    let report = report::build(&records(), &vqa());
    let scratch = tempfile::tempdir().unwrap();
    let dir = scratch.path().join("report");
    let markdown = report.write(&dir).unwrap();
    println!("{markdown}");
    // Orig. SR is the only column with two values: best bold, second underlined.
    assert!(markdown.contains("| oft | – | – | – | – | – | **100.0** |"), "{markdown}");
    assert!(markdown.contains("| 12.5 | <u>80.0</u> | 50.0 |"), "{markdown}");
    assert!(markdown.contains("| pi | AVF↑ | **100.0** | <u>0.0</u> | – |"), "{markdown}");
    for name in ["table1.md", "table1.csv", "table1.json", "table2.md", "table2.csv", "table2.json"] {
        assert!(dir.join(name).exists(), "{name}");
    }
    let csv = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
    assert!(
        csv.lines()
            .nth(2)
            .unwrap()
            .starts_with("pi,58.33,62.50,66.67,83.33,12.50,80.00,50.00,62.50,100.00,0.00,25.00,18,1,1,"),
        "{csv}"
    );
    // 95 % intervals: Orig. SR 4/5 (Agresti–Coull: 6/9 ± 1.96·√(6/9·3/9/9)), AVF F1 2/2 and F2 0/2
    // (each with one success and one failure added: 0.5 ± 1.96·√(2·0.75·0.25/4)/2); VTR has none.
    assert!(csv.lines().next().unwrap().ends_with(",unscored,Det_low,Det_high,Sem_low,Sem_high,Gnd_low,Gnd_high,Dec_low,Dec_high,FCA_low,FCA_high,Orig_SR_low,Orig_SR_high,AVF_low,AVF_high,LFR_low,LFR_high,UVF_low,UVF_high,UVI_low,UVI_high"), "{csv}");
    assert!(csv.lines().nth(2).unwrap().contains(",35.87,97.46,19.99,80.01,"), "{csv}");
    assert!(csv.lines().nth(1).unwrap().ends_with(",,,,,,,,,,,17.06,100.00,,,,,,,,"), "{csv}");
    assert!(markdown.contains("| oft | – | – | – | – | – | 17.1–100.0 | – | – | – | – |\n"), "{markdown}");
    assert!(markdown.contains("| 35.9–97.5 | 20.0–80.0 |"), "{markdown}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("table1.json")).unwrap()).unwrap();
    let pi = &json[1];
    assert!((pi["orig_sr_ci95"]["low"].as_f64().unwrap() - 35.8688).abs() < 1e-3, "{pi}");
    assert!((pi["avf"]["ci95"]["high"].as_f64().unwrap() - 80.0057).abs() < 1e-3, "{pi}");
    assert!(pi.get("vtr_ci95").is_none());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("table2.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), 3 * 4);
    // Pairwise: oft and pi share one original episode (both succeeded); vlm-only ran none.
    let [pair] = &report.pairs[..] else { panic!("{:?}", report.pairs) };
    assert_eq!((pair.a.as_str(), pair.b.as_str(), pair.orig_sr.map(|d| (d.points, d.pairs)), pair.avf), ("oft", "pi", Some((0.0, 1)), None));
    let pairs_md = std::fs::read_to_string(dir.join("pairs.md")).unwrap();
    let d = pair.orig_sr.unwrap().ci95;
    assert!(pairs_md.contains(&format!("| oft | pi | +0.0 [{:+.1}, {:+.1}] (n=1) | – | – | – | – |\n", d.low, d.high)), "{pairs_md}");
    let pairs_csv = std::fs::read_to_string(dir.join("pairs.csv")).unwrap();
    assert_eq!(pairs_csv.lines().nth(1), Some(format!("oft,pi,0.00,{:.2},{:.2},1{}", d.low, d.high, ",,,,".repeat(4)).as_str()));
    assert!(dir.join("pairs.json").exists());
    // Table 2's intervals: AVF F1 2/2 and F2 0/2 (Agresti–Coull), their mean as Table 1's AVF.
    let csv = std::fs::read_to_string(dir.join("table2.csv")).unwrap();
    let avf = format!("pi,AVF,100.00,0.00{},50.00,28.95,100.00,0.00,71.05{},19.99,80.01", ",".repeat(6), ",,".repeat(6));
    assert!(csv.lines().any(|l| l == avf), "{csv}");
    assert!(csv.lines().next().unwrap().ends_with(",Avg,F1_low,F1_high,F2_low,F2_high,F3_low,F3_high,F4_low,F4_high,F5_low,F5_high,F6_low,F6_high,F7_low,F7_high,F8_low,F8_high,Avg_low,Avg_high"), "{csv}");
    assert!(csv.lines().any(|l| l == format!("pi,episodes,2,3,0,0,0,0,4,4,13{}", ",,".repeat(9))), "{csv}");
    for metric in ["vqa", "avf", "uvf", "uvi"] {
        let png = std::fs::read(dir.join(format!("chart_{metric}.png"))).unwrap();
        let img = image::load_from_memory(&png).unwrap();
        assert_eq!((img.width(), img.height()), (960, 440));
    }
    // Same input, same bytes.
    let again = scratch.path().join("again");
    report.write(&again).unwrap();
    for name in ["table1.md", "table2.csv", "chart_avf.png"] {
        assert_eq!(std::fs::read(dir.join(name)).unwrap(), std::fs::read(again.join(name)).unwrap(), "{name}");
    }
}

#[test]
fn a_row_of_a_paper_model_is_set_beside_the_papers_row() {
    let mut records = records();
    for r in records.iter_mut().filter(|r| r.policy == "pi") {
        r.policy = "pi05@ws://gpu:8000".into();
        r.look = "libero-assets:0123".into();
    }
    records.retain(|r| r.policy != "oft");
    let report = report::build(&records, &BTreeMap::new());
    let md = report::tables::paper_markdown(&report);
    // Orig. SR 4/5 (35.9–97.5) and AVF 50.0 (20.0–80.0) hold the paper's 96.9 and 55.5.
    assert!(md.contains("| pi05@ws://gpu:8000 | this run | – | – | – | – | – | 80.0 | 50.0 | 62.5 | 100.0 | 0.0 | 25.0 |\n"), "{md}");
    assert!(md.contains("| | 95 % interval | – | – | – | – | – | 35.9–97.5 | 20.0–80.0 | – |"), "{md}");
    assert!(md.contains("| | paper: π0.5 | 19.9 | 11.4 | 40.9 | 54.6 | 1.2 | 96.9 (within) | 55.5 (within) | 57.3 | "), "{md}");
    assert!(!md.contains("built-in look"), "{md}");
    // 20 more failed original episodes: Orig. SR 4/25, whose interval lies well below 96.9.
    let failed = records.iter().find(|r| r.spec.protocol == Protocol::Original).unwrap().clone();
    for init in 100..120 {
        let mut r = failed.clone();
        r.spec.init = init;
        r.outcome = done(Some(false), None);
        records.push(r);
    }
    let md = report::tables::paper_markdown(&report::build(&records, &BTreeMap::new()));
    assert!(md.contains("| | paper: π0.5 | 19.9 | 11.4 | 40.9 | 54.6 | 1.2 | **96.9** (above) | 55.5 (within) |"), "{md}");
    // No paper model, no rows: how to name one.
    let none = report::tables::paper_markdown(&report::build(&self::records(), &BTreeMap::new()));
    assert!(none.contains("No row names one of the paper's models") && none.contains("pi05, molmoact2"), "{none}");
}

#[test]
fn a_selection_says_how_precise_its_rates_will_be() {
    let spec = |protocol, family: &str, n| record("p", protocol, family, n, done(None, None)).spec;
    // 50 original episodes: 25 of 50 gives 27/54 ± 1.96·√(0.25/54) = ±13.3 points.
    let mut specs: Vec<EpisodeSpec> = (0..50).map(|n| spec(Protocol::Original, "-", n)).collect();
    // AVF: 10 episodes in each of two families, a mean of two rates of 5/10.
    specs.extend((0..20).map(|n| spec(Protocol::Authorized, if n < 10 { "F1" } else { "F2" }, n)));
    let refs: Vec<&EpisodeSpec> = specs.iter().collect();
    let half = |a: &[Accuracy]| {
        let i = vifo_protocols::report::Interval::of_mean(a).unwrap();
        (i.high - i.low) / 2.0
    };
    let avf = half(&[Accuracy { correct: 5, total: 10 }, Accuracy { correct: 5, total: 10 }]);
    assert_eq!(
        report::precision(&refs).unwrap(),
        format!("Orig. SR ±13 (50 episodes), AVF ±{avf:.0} (20 episodes in 2 families)")
    );
    assert!((half(&[Accuracy { correct: 25, total: 50 }]) - 13.3).abs() < 0.05);
    assert_eq!(report::precision(&[]), None);
}

/// `r` moved to task `suite/index` (its cue instance with it).
fn in_task(mut r: EpisodeRecord, suite: &str, index: usize) -> EpisodeRecord {
    r.spec.task = TaskRef { suite: suite.into(), index };
    r.spec.instance = r.spec.instance.map(|id| id.replacen("libero_goal/1", &format!("{suite}/{index}"), 1));
    r
}

#[test]
fn suites_and_tasks_are_reported_one_by_one_in_liberos_order() {
    // pi on libero_goal: the records above. pi on libero_spatial: Orig. SR 1/2, AVF F1 1/1 and
    // F2 0/2 (a mean of 50 %), one error; oft there: Orig. SR 2/2.
    let mut all_suites = records();
    for (n, ok) in [true, false].into_iter().enumerate() {
        all_suites.push(in_task(record("pi", Protocol::Original, "-", 100 + n, done(Some(ok), None)), "libero_spatial", 3));
        all_suites.push(in_task(record("oft", Protocol::Original, "-", 100 + n, done(Some(true), None)), "libero_spatial", 3));
    }
    all_suites.push(in_task(record("pi", Protocol::Authorized, "F1", 100, done(None, Some(true))), "libero_spatial", 3));
    for n in 0..2 {
        all_suites.push(in_task(record("pi", Protocol::Authorized, "F2", 110 + n, done(None, Some(false))), "libero_spatial", 3));
    }
    all_suites.push(in_task(record("pi", Protocol::Conflict, "F7", 100, error()), "libero_spatial", 3));
    // And one more libero_spatial task, for the rows per task.
    all_suites.push(in_task(record("pi", Protocol::Original, "-", 200, done(Some(true), None)), "libero_spatial", 0));
    let report = report::build(&all_suites, &BTreeMap::new());
    let rows: Vec<(&str, &str)> = report.suites.iter().map(|s| (s.part.as_str(), s.row.policy.as_str())).collect();
    assert_eq!(rows, [("libero_spatial", "oft"), ("libero_spatial", "pi"), ("libero_goal", "oft"), ("libero_goal", "pi")]);
    let row = |suite: &str, policy: &str| &report.suites.iter().find(|s| s.part == suite && s.row.policy == policy).unwrap().row;
    // Each suite from its own episodes only; libero_goal's rows are Table 1's without the new ones.
    let spatial = row("libero_spatial", "pi");
    assert_eq!((spatial.orig_sr.correct, spatial.orig_sr.total), (2, 3));
    assert_eq!(spatial.avf.percent(), Some(50.0));
    assert_eq!((spatial.avf.pooled.correct, spatial.avf.pooled.total), (1, 3));
    assert_eq!(spatial.vtr, Some(75.0));
    assert_eq!((spatial.episodes, spatial.errors), (7, 1));
    // Per task: by suite in LIBERO's order, then by index.
    let tasks: Vec<(&str, &str)> = report.tasks.iter().map(|t| (t.part.as_str(), t.row.policy.as_str())).collect();
    assert_eq!(
        tasks,
        [("libero_spatial/0", "pi"), ("libero_spatial/3", "oft"), ("libero_spatial/3", "pi"), ("libero_goal/1", "oft"), ("libero_goal/1", "pi")]
    );
    let task3 = &report.tasks[2].row;
    assert_eq!((task3.orig_sr.correct, task3.orig_sr.total, task3.episodes), (1, 2, 6));
    let alone = report::build(&records(), &BTreeMap::new());
    let goal = Table1Row { det: None, sem: None, gnd: None, dec: None, fca: None, ..alone.table1.iter().find(|r| r.policy == "pi").unwrap().clone() };
    assert_eq!(row("libero_goal", "pi"), &goal);
    // Table 1 holds both suites.
    let all = report.table1.iter().find(|r| r.policy == "pi").unwrap();
    assert_eq!((all.orig_sr.correct, all.orig_sr.total), (6, 8));

    let scratch = tempfile::tempdir().unwrap();
    report.write(scratch.path()).unwrap();
    let markdown = std::fs::read_to_string(scratch.path().join("suites.md")).unwrap();
    // Ranked within a suite: on libero_spatial oft's 100.0 is best, pi's 50.0 second.
    // Orig. SR with its counts and 95 % interval (2 of 2: (2+2)/(2+4) ± 1.96·√(4/6·2/6/6)).
    assert!(markdown.contains("| oft | libero_spatial | **100.0** (2/2; 28.9–100.0) |"), "{markdown}");
    assert!(markdown.contains("| pi | libero_spatial | <u>66.7</u> (2/3; 20.5–93.8) | 50.0 |"), "{markdown}");
    let csv = std::fs::read_to_string(scratch.path().join("suites.csv")).unwrap();
    assert!(csv.lines().any(|l| l.starts_with("pi,libero_spatial,66.67,50.00,75.00,,,,2,3,7,1,0,20.48,93.80,")), "{csv}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(scratch.path().join("suites.json")).unwrap()).unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), 4);
    // Tasks carry their instruction in Markdown, their id alone in CSV and JSON.
    let markdown = std::fs::read_to_string(scratch.path().join("tasks.md")).unwrap();
    let instruction = &vifo_scenes::task("libero_spatial", 3).unwrap().instruction;
    assert!(markdown.contains(&format!("| pi | libero_spatial/3 ({instruction}) | <u>50.0</u> (1/2; 10.0–90.0) |")), "{markdown}");
    let csv = std::fs::read_to_string(scratch.path().join("tasks.csv")).unwrap();
    assert!(csv.lines().any(|l| l == "pi,libero_spatial/0,100.00,,,,,,1,1,1,0,0,17.06,100.00,,,,,,,,"), "{csv}");
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(scratch.path().join("tasks.json")).unwrap()).unwrap();
    assert_eq!(json["rows"][0]["part"], "libero_spatial/0");
    // The chart's bars stand as tall as the rates: libero_spatial's (first colour) 100 + 66.7,
    // libero_goal's (second) 100 + 80.
    let chart = image::load_from_memory(&std::fs::read(scratch.path().join("chart_suites.png")).unwrap()).unwrap().to_rgb8();
    assert_eq!(chart.dimensions(), (960, 440));
    let pixels = |colour: [u8; 3]| chart.pixels().filter(|p| p.0 == colour).count() as f64;
    let ratio = pixels([242, 142, 43]) / pixels([78, 121, 167]);
    assert!((ratio - 180.0 / 166.67).abs() < 0.02, "{ratio}");
    // Whiskers span the bars' 95 % intervals: the highest ends reach 100 % (2 of 2, 1 of 1), the
    // lowest is oft's 1 of 1 on libero_goal at 17.06 %. The frame's 100 % is at y = 72, 0 at 370.
    let rows: Vec<u32> = chart.enumerate_pixels().filter(|(.., p)| p.0 == [70, 70, 70]).map(|(_, y, _)| y).collect();
    let (top, bottom) = (*rows.iter().min().unwrap(), *rows.iter().max().unwrap());
    let lowest = 370.0 - 0.1706 * 298.0;
    assert!((71..=74).contains(&top) && (bottom as f64 - lowest).abs() < 2.5, "whiskers from y {top} to {bottom}, expected 72 to {lowest}");
}

#[test]
fn sets_are_reported_apart() {
    let mut records = records();
    let one = report::build(&records, &BTreeMap::new());
    assert_eq!(one.sets, [SetName::Paper]);
    assert!(report::tables::table1_markdown(&one).contains("Instance set: paper."));
    records.push(EpisodeRecord { set: SetName::Full, ..record("oft", Protocol::Original, "-", 1, done(Some(false), None)) });
    let two = report::build(&records, &BTreeMap::new());
    let names: Vec<&str> = two.table1.iter().map(|r| r.policy.as_str()).collect();
    assert_eq!(names, ["oft [full]", "oft [paper]", "pi [paper]"]);
    assert_eq!((two.table1[0].orig_sr.correct, two.table1[0].orig_sr.total), (0, 1));
    assert_eq!((two.table1[1].orig_sr.correct, two.table1[1].orig_sr.total), (1, 1));
    // Rows are compared within a set only (oft [full]'s episode has the key of one pi ran).
    let pairs: Vec<(&str, &str)> = two.pairs.iter().map(|c| (c.a.as_str(), c.b.as_str())).collect();
    assert_eq!(pairs, [("oft [paper]", "pi [paper]")]);
    // VQA scores go with the row of their own set; scores naming no set, with neither of two.
    let mut scores = VqaScores::default();
    scores.stages.insert(Stage::Detection, Accuracy { correct: 1, total: 2 });
    scores.families.insert(Family::F1, Accuracy { correct: 1, total: 2 });
    scores.family_stages.insert(Family::F1, [(Stage::Detection, Accuracy { correct: 1, total: 2 })].into());
    let with = |set| BTreeMap::from([("oft".to_string(), VqaScores { set, ..scores.clone() })]);
    let scored = |r: &report::Table1Row| r.det.is_some();
    let full = report::build(&records, &with(Some(SetName::Full)));
    assert_eq!(full.table1.iter().map(scored).collect::<Vec<_>>(), [true, false, false]);
    let unnamed = report::build(&records, &with(None));
    assert_eq!(unnamed.table1.iter().map(scored).collect::<Vec<_>>(), [false, false, false]);
    records.retain(|r| r.policy != "oft" || r.set == SetName::Full);
    let single = report::build(&records, &with(None));
    assert_eq!(single.table1.iter().map(scored).collect::<Vec<_>>(), [true, false]);
}

#[test]
fn looks_count_episodes_per_look_with_empty_as_built_in() {
    let plain = record("pi", Protocol::Original, "F1", 0, Outcome::Error { message: String::new() });
    let looked = EpisodeRecord { look: "libero-assets:0123".into(), ..plain.clone() };
    let looks = report::looks(&[plain.clone(), plain.clone(), looked.clone()]);
    assert_eq!(looks.into_iter().collect::<Vec<_>>(), vec![("built-in".to_string(), 2), ("libero-assets:0123".to_string(), 1)]);
    // The tables name the look they were drawn with, or, mixed on request, every look.
    let one = report::build(std::slice::from_ref(&plain), &BTreeMap::new());
    for markdown in [report::tables::table1_markdown(&one), report::tables::table2_markdown(&one)] {
        assert!(markdown.contains("Look: built-in.\n"), "{markdown}");
    }
    // Table 2's columns are named as the paper's.
    assert!(report::tables::table2_markdown(&one).contains("| Model | Metric | F1 Text | F2 Geom. | F3 Ghost | F4 Pict. | F5 Gest. | F6 Sign | F7 Light. | F8 Code | Avg. |"));
    let mixed = report::build(&[plain, looked], &BTreeMap::new());
    assert!(report::tables::table1_markdown(&mixed).contains("Looks: built-in, libero-assets:0123 (mixed on request"));
}

/// The built-in policies read the simulator: their rows hold for any look, so they sit beside a
/// served model's rows drawn with LIBERO's look (a report once refused that as mixed looks).
#[test]
fn rows_of_policies_sent_no_images_go_with_any_look_and_are_named() {
    let blind = EpisodeRecord { look: report::NO_IMAGES.into(), ..record("expert-cue", Protocol::Authorized, "F1", 0, done(None, Some(true))) };
    let looked = EpisodeRecord { look: "libero-assets:0123".into(), ..record("pi", Protocol::Authorized, "F1", 0, done(None, Some(false))) };
    let both = [blind.clone(), looked.clone()];
    let looks = report::looks_with_vqa(&both, std::iter::empty());
    assert_eq!(report::check_looks(&looks, false, "--mix-looks"), Ok("libero-assets:0123 (1 episode)".to_string()));
    let table = report::tables::table1_markdown(&report::build(&both, &BTreeMap::new()));
    assert!(table.contains("Look: libero-assets:0123.\n\nSent no images (they read the simulator), so the same with any look: expert-cue.\n"), "{table}");
    // Beside VQA scores drawn with a look, they take that look.
    let scores = VqaScores { look: "libero-assets:0123".into(), ..VqaScores::default() };
    let with_vqa = report::looks_with_vqa(std::slice::from_ref(&blind), [("pi", &scores)]);
    assert_eq!(report::check_looks(&with_vqa, false, "--mix-looks"), Ok("libero-assets:0123 (VQA scores of pi)".to_string()));
    let table = report::tables::table1_markdown(&report::build(std::slice::from_ref(&blind), &BTreeMap::from([("pi".to_string(), scores)])));
    assert!(table.contains("Look: libero-assets:0123.\n\nSent no images (they read the simulator), so the same with any look: expert-cue.\n"), "{table}");
    // Alone, they say so; beside the built-in look they are not a second look either.
    let alone = report::tables::table1_markdown(&report::build(std::slice::from_ref(&blind), &BTreeMap::new()));
    assert!(alone.contains("Look: none (the policies were sent no images).\n") && !alone.contains("Sent no images"), "{alone}");
    let built_in = EpisodeRecord { look: String::new(), ..looked };
    assert_eq!(report::looks(&[blind.clone(), built_in]).into_iter().collect::<Vec<_>>(), vec![("built-in".to_string(), 1)]);
    // A row with some episodes drawn (here in the built-in look) is not listed as sent none.
    let mixed_row = record("expert-cue", Protocol::Authorized, "F1", 1, done(None, Some(true)));
    let table = report::tables::table1_markdown(&report::build(&[blind, mixed_row], &BTreeMap::new()));
    assert!(!table.contains("Sent no images"), "{table}");
}

#[test]
fn vqa_scores_carry_their_look_and_count_beside_the_episodes() {
    // Built-in scores serialise as they did before looks (no field), and such files read back
    // as built-in; a look survives the round trip.
    let built_in = VqaScores { model: "m".into(), ..VqaScores::default() };
    let json = serde_json::to_string(&built_in).unwrap();
    assert!(!json.contains("look"), "{json}");
    let assets = VqaScores { look: "libero-assets:0123".into(), ..built_in.clone() };
    let back: VqaScores = serde_json::from_str(&serde_json::to_string(&assets).unwrap()).unwrap();
    assert_eq!(back, assets);
    // One look for episodes and scores alike, or two that the report must not mix.
    let plain = record("pi", Protocol::Original, "F1", 0, Outcome::Error { message: String::new() });
    let same = report::looks_with_vqa(std::slice::from_ref(&plain), [("pi", &built_in)]);
    assert_eq!(same.clone().into_iter().collect::<Vec<_>>(), vec![("built-in".to_string(), vec!["1 episode".to_string(), "VQA scores of pi".to_string()])]);
    let mixed = report::looks_with_vqa(&[plain], [("pi", &assets)]);
    assert_eq!(mixed.keys().collect::<Vec<_>>(), ["built-in", "libero-assets:0123"]);
    assert_eq!(mixed["libero-assets:0123"], ["VQA scores of pi"]);
    // The report refuses them unless the option that allows it is given, and names both.
    assert_eq!(report::check_looks(&same, false, "--mix-looks"), Ok("built-in (1 episode, VQA scores of pi)".to_string()));
    let refused = report::check_looks(&mixed, false, "--mix-looks").unwrap_err();
    assert!(refused.starts_with("the results mix looks: built-in (1 episode); libero-assets:0123 (VQA scores of pi);"), "{refused}");
    assert!(refused.ends_with("pass --mix-looks)"), "{refused}");
    assert_eq!(report::check_looks(&mixed, true, "--mix-looks"), Ok("built-in (1 episode); libero-assets:0123 (VQA scores of pi)".to_string()));
}
