//! The paper's own Table 1, its seven models' rows as it prints them, so that a run of one of
//! those models here meets the figures it is meant to reproduce: a report row that names a paper
//! model (by its `--model-profile` name, which is what a served model's rows carry by default,
//! `<profile>@<url>`) gets its paper row beside it and, per column, whether the paper's figure
//! lies within this run's 95 % interval.

use super::Table1Row;

/// One of the paper's Table 1 rows: the model, the serving profile that runs it here, and its
/// eleven figures in Table 1's column order (Det., Sem., Gnd., Dec., FCA, Orig. SR, AVF, VTR,
/// LFR, UVF, UVI).
pub struct PaperRow {
    pub model: &'static str,
    pub profile: &'static str,
    pub figures: [f64; 11],
}

/// The paper's Table 1 (`tab:main-results`), in its order.
pub const TABLE1: [PaperRow; 7] = [
    PaperRow { model: "OpenVLA-OFT", profile: "openvla-oft", figures: [4.5, 14.1, 20.8, 35.2, 0.1, 97.1, 0.0, 0.0, 90.7, 0.0, 59.8] },
    PaperRow { model: "π0.5", profile: "pi05", figures: [19.9, 11.4, 40.9, 54.6, 1.2, 96.9, 55.5, 57.3, 94.6, 0.0, 49.7] },
    PaperRow { model: "MolmoAct2", profile: "molmoact2", figures: [65.1, 83.9, 45.8, 46.2, 16.6, 97.2, 33.5, 34.5, 95.4, 0.0, 35.6] },
    PaperRow { model: "Action-Sketcher", profile: "action-sketcher", figures: [36.1, 28.0, 25.5, 68.0, 1.9, 96.9, 61.2, 63.2, 83.6, 0.0, 60.1] },
    PaperRow { model: "InstructVLA", profile: "instructvla", figures: [55.2, 57.5, 62.7, 66.4, 17.6, 95.8, 50.9, 53.1, 93.0, 0.0, 32.2] },
    PaperRow { model: "InternVLA-A1.5", profile: "internvla", figures: [62.3, 42.1, 53.9, 61.8, 11.5, 98.9, 56.8, 57.4, 92.7, 0.0, 44.6] },
    PaperRow { model: "Xiaomi-Robotics-0", profile: "xiaomi", figures: [54.1, 43.6, 48.3, 41.0, 8.4, 98.7, 40.6, 41.1, 88.9, 0.0, 32.4] },
];

/// The paper row of the model a report row names: the row's name up to any `@` (a served
/// model's default name is `<profile>@<url>`; a `[set]` suffix is dropped) is the model's
/// profile, or begins with it and `-`, `_` or `.` (`pi05-30k`), case aside.
pub fn paper_row(row: &Table1Row) -> Option<&'static PaperRow> {
    let name = row.policy.split([' ', '@']).next().unwrap_or_default().to_lowercase();
    TABLE1.iter().find(|p| {
        name.strip_prefix(p.profile).is_some_and(|rest| rest.is_empty() || rest.starts_with(['-', '_', '.']))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(policy: &str) -> Table1Row {
        Table1Row { policy: policy.into(), ..Table1Row::default() }
    }

    #[test]
    fn rows_are_matched_by_profile_name() {
        let model = |p: &str| paper_row(&row(p)).map(|r| r.model);
        assert_eq!(model("pi05@ws://gpu:8000"), Some("π0.5"));
        assert_eq!(model("pi05"), Some("π0.5"));
        assert_eq!(model("PI05-30k [paper]"), Some("π0.5"));
        assert_eq!(model("openvla-oft@http://h:8777/act"), Some("OpenVLA-OFT"));
        assert_eq!(model("action-sketcher_v2"), Some("Action-Sketcher"));
        assert_eq!(model("pi05x"), None);
        assert_eq!(model("expert-cue"), None);
        assert_eq!(model("openpi@ws://h:8000"), None);
    }

    #[test]
    fn the_papers_vtr_is_its_avf_over_its_orig_sr() {
        // A check of the transcription: VTR = AVF / Orig. SR × 100, to the paper's rounding.
        for p in &TABLE1 {
            let [.., orig, avf, vtr, _, _, _] = p.figures;
            assert!((100.0 * avf / orig - vtr).abs() < 0.15, "{}: {avf} / {orig} against {vtr}", p.model);
        }
    }
}
