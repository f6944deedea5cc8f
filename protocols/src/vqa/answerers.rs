//! Reference answerers: the oracle (reads the key; checks the scoring pipeline end to end)
//! and text-only baselines that see the question and options but not the image. The
//! blind baselines measure how much of the answer leaks through wording, position or
//! length; the question generator is designed to keep each of them near chance (25 %).

use std::collections::{BTreeMap, BTreeSet};

use super::score::{Accuracy, score};
use super::{LETTERS, Prediction, Question, Stage};

/// Answers every question correctly.
pub fn oracle(questions: &[Question]) -> Vec<Prediction> {
    questions.iter().map(|q| Prediction { id: q.id.clone(), prediction: q.answer.clone() }).collect()
}

/// A text-only strategy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Blind {
    /// For each question wording, the letter most often correct in the set (an upper bound
    /// on what answer-position bias gives).
    LetterPrior,
    /// The longest option.
    Longest,
    /// The shortest option (the mirror check: distractors must not be systematically longer).
    Shortest,
    /// The option sharing the most words with the question.
    WordOverlap,
}

impl Blind {
    pub const ALL: [Blind; 4] = [Blind::LetterPrior, Blind::Longest, Blind::Shortest, Blind::WordOverlap];

    pub fn name(self) -> &'static str {
        match self {
            Blind::LetterPrior => "letter_prior",
            Blind::Longest => "longest_option",
            Blind::Shortest => "shortest_option",
            Blind::WordOverlap => "word_overlap",
        }
    }
}

/// The predictions of one blind strategy.
pub fn blind_predictions(questions: &[Question], strategy: Blind) -> Vec<Prediction> {
    let prior = letter_prior(questions);
    questions
        .iter()
        .map(|q| {
            let pick = match strategy {
                Blind::LetterPrior => prior[q.question.as_str()],
                Blind::Longest => first_max(q.options.iter().map(|o| o.chars().count())),
                Blind::Shortest => first_max(q.options.iter().map(|o| usize::MAX - o.chars().count())),
                Blind::WordOverlap => {
                    let asked = content_words(&q.question);
                    first_max(q.options.iter().map(|o| content_words(o).intersection(&asked).count()))
                }
            };
            Prediction { id: q.id.clone(), prediction: LETTERS[pick].to_string() }
        })
        .collect()
}

/// Per stage: each strategy's accuracy, and the best of them.
#[derive(Clone, Debug, PartialEq)]
pub struct BlindReport {
    pub strategies: BTreeMap<Blind, BTreeMap<Stage, Accuracy>>,
    pub best: BTreeMap<Stage, (Blind, Accuracy)>,
}

/// Runs every strategy.
pub fn blind(questions: &[Question]) -> BlindReport {
    let mut strategies = BTreeMap::new();
    let mut best: BTreeMap<Stage, (Blind, Accuracy)> = BTreeMap::new();
    for strategy in Blind::ALL {
        let predictions = blind_predictions(questions, strategy).into_iter().map(|p| (p.id, p.prediction)).collect();
        let stages = score(strategy.name(), questions, &predictions).stages;
        for (&stage, &acc) in &stages {
            let better = best.get(&stage).is_none_or(|(_, b)| acc.percent() > b.percent());
            if better {
                best.insert(stage, (strategy, acc));
            }
        }
        strategies.insert(strategy, stages);
    }
    BlindReport { strategies, best }
}

impl BlindReport {
    pub fn markdown(&self) -> String {
        let mut out = String::from("| strategy | Det | Sem | Gnd | Dec |\n|---|---|---|---|---|\n");
        let cell = |a: Option<&Accuracy>| a.and_then(Accuracy::percent).map_or("–".into(), |p| format!("{p:.1}"));
        for (strategy, stages) in &self.strategies {
            let cells: Vec<String> = Stage::ALL.iter().map(|s| cell(stages.get(s))).collect();
            out += &format!("| {} | {} |\n", strategy.name(), cells.join(" | "));
        }
        let cells: Vec<String> = Stage::ALL.iter().map(|s| cell(self.best.get(s).map(|(_, a)| a))).collect();
        out += &format!("| best | {} |\n", cells.join(" | "));
        out
    }
}

/// Question wording → its most frequent correct letter (ties: the earliest letter).
fn letter_prior(questions: &[Question]) -> BTreeMap<&str, usize> {
    let mut counts: BTreeMap<&str, [usize; 4]> = BTreeMap::new();
    for q in questions {
        let c = counts.entry(q.question.as_str()).or_default();
        if let Some(i) = LETTERS.iter().position(|l| q.answer.starts_with(*l)) {
            c[i] += 1;
        }
    }
    counts.into_iter().map(|(k, c)| (k, first_max(c.into_iter()))).collect()
}

/// Index of the first maximum.
fn first_max(values: impl Iterator<Item = usize>) -> usize {
    let mut best = (0, None);
    for (i, v) in values.enumerate() {
        if best.1.is_none_or(|b| v > b) {
            best = (i, Some(v));
        }
    }
    best.0
}

const STOPWORDS: [&str; 24] = [
    "the", "a", "an", "of", "in", "on", "to", "and", "or", "is", "are", "by", "at", "with", "what", "which", "does",
    "do", "should", "be", "it", "this", "that", "for",
];

fn content_words(s: &str) -> BTreeSet<String> {
    s.split(|c: char| !c.is_alphanumeric())
        .map(str::to_lowercase)
        .filter(|w| !w.is_empty() && !STOPWORDS.contains(&w.as_str()))
        .collect()
}
