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
    /// The look the question images were drawn with, as episode records store it: empty for
    /// the built-in look (absent from the file, as in scores written before looks), else
    /// `libero-assets:<hash>`.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub look: String,
    /// The export's cue form and instance set (`form.txt`, `set.txt`); `None` in scores
    /// written before they were recorded. Reports check them against where they put the scores.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form: Option<crate::spec::CueForm>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub set: Option<vifo_cues::SetName>,
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
    cell(a.and_then(Accuracy::percent))
}

fn cell(percent: Option<f64>) -> String {
    percent.map_or("–".into(), |p| format!("{p:.1}"))
}

/// The unweighted mean of the rates of those with data: Table 1's figures over cue families,
/// and Table 2's Avg. (`None` when none has data).
pub fn mean_rate<'a>(rates: impl IntoIterator<Item = &'a Accuracy>) -> Option<f64> {
    let rates: Vec<f64> = rates.into_iter().filter_map(Accuracy::percent).collect();
    (!rates.is_empty()).then(|| rates.iter().sum::<f64>() / rates.len() as f64)
}

/// The sum of some counts.
fn total<'a>(parts: impl IntoIterator<Item = &'a Accuracy>) -> Accuracy {
    parts.into_iter().fold(Accuracy::default(), |a, b| Accuracy { correct: a.correct.saturating_add(b.correct), total: a.total.saturating_add(b.total) })
}

impl VqaScores {
    /// Whether these counts are ones [`score`] can make: no more right than asked, and every
    /// total the sum of its parts (an edited scores file otherwise put Det. 878.6 in Table 1).
    pub fn check(&self) -> Result<(), String> {
        let all = self.stages.values().chain(self.families.values()).chain(self.family_stages.values().flat_map(|m| m.values()));
        if let Some(a) = all.chain(self.family_fca.values()).chain([&self.fca, &self.overall]).find(|a| a.correct > a.total) {
            return Err(format!("{} right of {} asked", a.correct, a.total));
        }
        let sums_up = |what: String, whole: Option<&Accuracy>, parts: Accuracy| {
            if whole.copied().unwrap_or_default() == parts { Ok(()) } else { Err(format!("{what} is not the sum of its parts")) }
        };
        for (family, stages) in &self.family_stages {
            sums_up(format!("family {family}"), self.families.get(family), total(stages.values()))?;
        }
        for stage in Stage::ALL {
            sums_up(format!("stage {stage:?}"), self.stages.get(&stage), total(self.family_stages.values().filter_map(|m| m.get(&stage))))?;
        }
        sums_up("overall".into(), Some(&self.overall), total(self.families.values()))?;
        sums_up("fca".into(), Some(&self.fca), total(self.family_fca.values()))
    }

    /// A Markdown table: one row per family and the total, columns Det, Sem, Gnd, Dec, all, FCA.
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "VQA scores of {}\n\n| family | Det | Sem | Gnd | Dec | all | FCA | questions |\n|---|---|---|---|---|---|---|---|\n",
            self.model
        );
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
        let means: Vec<String> =
            Stage::ALL.iter().map(|st| cell(mean_rate(self.family_stages.values().filter_map(|f| f.get(st))))).collect();
        out += &format!(
            "| mean of families (Table 1) | {} | {} | {} | – |\n",
            means.join(" | "),
            cell(mean_rate(self.families.values())),
            cell(mean_rate(self.family_fca.values()))
        );
        let cells: Vec<String> = Stage::ALL.iter().map(|st| pct(self.stages.get(st))).collect();
        out += &format!(
            "| all questions | {} | {} | {} | {} |\n\nunanswered {}, unparseable {}, refused {}, unknown ids {}\n",
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

#[cfg(test)]
mod tests {
    use super::*;

    fn q(instance: &str, family: Family, stage: Stage, answer: &str) -> Question {
        Question {
            id: format!("{instance}/{}", stage.name()),
            instance_id: instance.into(),
            family,
            stage,
            image: String::new(),
            question: "?".into(),
            options: ["wall", "xray", "yard", "zinc"].iter().map(|s| s.to_string()).collect(),
            answer: answer.into(),
        }
    }

    #[test]
    fn counts_stages_families_chains_and_failures() {
        let mut qs = Vec::new();
        for (inst, family) in [("i1", Family::F1), ("i2", Family::F2)] {
            for stage in Stage::ALL {
                qs.push(q(inst, family, stage, "B"));
            }
        }
        qs.push(q("i3", Family::F2, Stage::Detection, "A"));
        let p: BTreeMap<String, String> = [
            ("i1/detection", "B"),
            ("i1/semantic", "(B) xray"),
            ("i1/grounding", "the xray"),
            ("i1/decision", "B."),
            ("i2/detection", "B"),
            ("i2/semantic", "maybe"),
            ("i2/grounding", "Z"),
            ("i3/detection", "A"),
            ("nobody", "A"),
        ]
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
        let s = score("m", &qs, &p);
        assert_eq!((s.overall.correct, s.overall.total), (6, 9));
        assert_eq!((s.fca.correct, s.fca.total), (1, 2), "i3 has one question only");
        assert_eq!((s.unanswered, s.unparsed, s.refused, s.unknown_ids), (1, 1, 1, 1));
        assert_eq!(s.stages[&Stage::Detection], Accuracy { correct: 3, total: 3 });
        assert_eq!(s.families[&Family::F2], Accuracy { correct: 2, total: 5 });
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<VqaScores>(&json).unwrap(), s);

        // What `score` makes passes its check; edited counts do not.
        assert_eq!(s.check(), Ok(()));
        type Edit = fn(&mut VqaScores);
        let edits: [(&str, Edit); 4] = [
            ("5000 right of 79 asked", |s| *s.family_stages.get_mut(&Family::F1).unwrap().get_mut(&Stage::Detection).unwrap() = Accuracy { correct: 5000, total: 79 }),
            ("family F1 is not the sum", |s| s.family_stages.get_mut(&Family::F1).unwrap().get_mut(&Stage::Detection).unwrap().total += 1),
            ("overall is not the sum", |s| s.overall.correct -= 1),
            ("fca is not the sum", |s| s.fca.total += 1),
        ];
        for (says, edit) in edits {
            let mut t = s.clone();
            edit(&mut t);
            let e = t.check().unwrap_err();
            assert!(e.contains(says), "{says}: {e}");
        }
        assert!(
            s.markdown().contains("| F1 | 100.0 | 100.0 | 100.0 | 100.0 | 100.0 | 100.0 | 4 |"),
            "{}",
            s.markdown()
        );
    }
}
