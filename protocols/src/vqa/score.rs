//! Accuracy per stage (Det, Sem, Gnd, Dec), per family and full-chain accuracy (FCA: all
//! four questions of an instance right). Unanswered, unparseable and refused answers are
//! wrong and counted separately.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use vifo_cues::Family;

use super::extract::{Extracted, extract};
use super::{Question, Stage};

/// Correct out of total.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Accuracy {
    pub correct: usize,
    pub total: usize,
}

impl Accuracy {
    pub fn add(&mut self, correct: bool) {
        self.total += 1;
        self.correct += usize::from(correct);
    }

    /// Percentage; `None` without questions.
    pub fn percent(&self) -> Option<f64> {
        (self.total > 0).then(|| 100.0 * self.correct as f64 / self.total as f64)
    }
}

/// The scores of one model on one question set (the `vqa` input of the reports).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VqaScores {
    pub model: String,
    pub stages: BTreeMap<Stage, Accuracy>,
    /// All four stages together, per family (Table 2's VQA row).
    pub families: BTreeMap<Family, Accuracy>,
    pub family_stages: BTreeMap<Family, BTreeMap<Stage, Accuracy>>,
    /// Instances with all four questions right, over instances with four questions.
    pub fca: Accuracy,
    pub family_fca: BTreeMap<Family, Accuracy>,
    pub overall: Accuracy,
    /// Questions without a prediction.
    pub unanswered: usize,
    /// Predictions without a single letter or option text.
    pub unparsed: usize,
    /// Refusals (VLMEvalKit's Z).
    pub refused: usize,
    /// Predictions for ids that are not in the question set (ignored).
    pub unknown_ids: usize,
}

/// Scores raw predictions (id → model text) against the questions.
pub fn score(model: &str, questions: &[Question], predictions: &BTreeMap<String, String>) -> VqaScores {
    let mut s = VqaScores { model: model.to_string(), ..VqaScores::default() };
    let mut chains: BTreeMap<&str, (Family, usize, bool)> = BTreeMap::new();
    for q in questions {
        let correct = match predictions.get(&q.id) {
            None => {
                s.unanswered += 1;
                false
            }
            Some(raw) => match extract(raw, &q.options) {
                Extracted::Letter(l) => q.answer.starts_with(l),
                Extracted::Refused => {
                    s.refused += 1;
                    false
                }
                Extracted::Unparsed => {
                    s.unparsed += 1;
                    false
                }
            },
        };
        s.stages.entry(q.stage).or_default().add(correct);
        s.families.entry(q.family).or_default().add(correct);
        s.family_stages.entry(q.family).or_default().entry(q.stage).or_default().add(correct);
        s.overall.add(correct);
        let chain = chains.entry(&q.instance_id).or_insert((q.family, 0, true));
        chain.1 += 1;
        chain.2 &= correct;
    }
    for (family, asked, all_right) in chains.into_values() {
        if asked == Stage::ALL.len() {
            s.fca.add(all_right);
            s.family_fca.entry(family).or_default().add(all_right);
        }
    }
    let known: std::collections::BTreeSet<&str> = questions.iter().map(|q| q.id.as_str()).collect();
    s.unknown_ids = predictions.keys().filter(|id| !known.contains(id.as_str())).count();
    s
}

fn pct(a: Option<&Accuracy>) -> String {
    a.and_then(Accuracy::percent).map_or("–".into(), |p| format!("{p:.1}"))
}

impl VqaScores {
    /// A Markdown table: one row per family and the total, columns Det, Sem, Gnd, Dec, all, FCA.
    pub fn markdown(&self) -> String {
        let mut out = format!("VQA scores of {}\n\n| family | Det | Sem | Gnd | Dec | all | FCA | questions |\n|---|---|---|---|---|---|---|---|\n", self.model);
        for (family, stages) in &self.family_stages {
            let cells: Vec<String> = Stage::ALL.iter().map(|st| pct(stages.get(st))).collect();
            out += &format!(
                "| {family} | {} | {} | {} | {} |\n",
                cells.join(" | "),
                pct(self.families.get(family)),
                pct(self.family_fca.get(family)),
                self.families.get(family).map_or(0, |a| a.total)
            );
        }
        let cells: Vec<String> = Stage::ALL.iter().map(|st| pct(self.stages.get(st))).collect();
        out += &format!(
            "| all | {} | {} | {} | {} |\n\nunanswered {}, unparseable {}, refused {}, unknown ids {}\n",
            cells.join(" | "),
            pct(Some(&self.overall)),
            pct(Some(&self.fca)),
            self.overall.total,
            self.unanswered,
            self.unparsed,
            self.refused,
            self.unknown_ids
        );
        out
    }
}
