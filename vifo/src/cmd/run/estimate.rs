//! `vifo run --sample N`: time a representative part of a selection and extrapolate the time
//! of all of it (the gate measurement of the whole benchmark in ≤ 60 min on 2 cores).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use vifo_protocols::runner::{final_records, read_records};
use vifo_protocols::spec::{EpisodeSpec, Outcome};
use vifo_protocols::Protocol;

/// Prints per protocol the sample's mean episode time and the extrapolated time of `all`
/// on `threads` threads (0: every core), assuming episodes keep the cores busy. The sample's
/// `filmed` episodes (spec keys; the report's clips) are left out of the means: a whole run
/// films one episode per cue family too, not a share of every episode, so what filming cost
/// over an unfilmed episode is added once.
pub fn print(all: &[EpisodeSpec], sample: &[EpisodeSpec], filmed: &BTreeSet<String>, results: &Path, threads: usize) -> anyhow::Result<()> {
    let threads = if threads == 0 { rayon::current_num_threads() } else { threads };
    let keys: BTreeSet<String> = sample.iter().map(EpisodeSpec::key).collect();
    let records = final_records(read_records(results)?.records);
    let sampled: Vec<_> = records.values().filter(|r| keys.contains(&r.spec.key())).collect();
    let mut measured: BTreeMap<Protocol, Measured> = BTreeMap::new();
    for r in &sampled {
        measured.entry(r.spec.protocol).or_default().add(r.wall_ms, &r.outcome, filmed.contains(&r.spec.key()));
    }
    let mut counts: BTreeMap<Protocol, usize> = BTreeMap::new();
    for s in all {
        *counts.entry(s.protocol).or_default() += 1;
    }
    println!("  time estimate for all {} episodes on {threads} thread(s):", all.len());
    println!("  | protocol | episodes | sampled | mean s/episode | mean steps | estimate (min) |");
    println!("  |---|---|---|---|---|---|");
    let mut total = 0.0;
    let mut surplus_ms = 0.0;
    let (mut filmed_count, mut filmed_only, mut unsampled) = (0, false, false);
    for (protocol, count) in &counts {
        let Some(m) = measured.get(protocol) else {
            unsampled = true;
            println!("  | {} | {count} | 0 | – | – | not sampled |", protocol.name());
            continue;
        };
        // A protocol whose only sampled episodes were filmed is timed by them: too high, not 0.
        let (mean_ms, note) = match m.mean_ms() {
            Some(mean) => {
                surplus_ms += m.filmed_surplus_ms(mean);
                filmed_count += m.filmed.len();
                (mean, "")
            }
            None => {
                filmed_only = true;
                (m.filmed.iter().sum::<f64>() / m.filmed.len() as f64, " (filmed)")
            }
        };
        let minutes = mean_ms / 1e3 * *count as f64 / threads as f64 / 60.0;
        total += minutes;
        let sampled = m.n + if note.is_empty() { 0 } else { m.filmed.len() };
        let steps = if m.n > 0 { format!("{:.0}", m.steps as f64 / m.n as f64) } else { "–".into() };
        println!("  | {} | {count} | {sampled}{note} | {:.2} | {steps} | {minutes:.1} |", protocol.name(), mean_ms / 1e3);
    }
    if filmed_count > 0 {
        let minutes = surplus_ms / 1e3 / threads as f64 / 60.0;
        total += minutes;
        println!("  | filming the clips, once | {filmed_count} | | | | {minutes:.1} |");
    }
    println!("  | all | {} | {} | | | **{total:.1}** |", all.len(), keys.len());
    if filmed_only {
        println!("  (a protocol sampled only by filmed episodes is timed by them, clip frames included: an overestimate; a larger --sample times it without)");
    }
    if unsampled {
        println!("  (a protocol without a sampled episode is left out of the total: an underestimate)");
    }
    Ok(())
}

/// One protocol's sampled episodes: unfilmed ones summed, filmed ones kept apart.
#[derive(Default)]
struct Measured {
    ms: f64,
    n: usize,
    steps: usize,
    filmed: Vec<f64>,
}

impl Measured {
    fn add(&mut self, wall_ms: f64, outcome: &Outcome, filmed: bool) {
        if filmed {
            self.filmed.push(wall_ms);
            return;
        }
        self.ms += wall_ms;
        self.n += 1;
        if let Outcome::Completed { steps, .. } = outcome {
            self.steps += steps;
        }
    }

    /// The unfilmed episodes' mean, if there are any.
    fn mean_ms(&self) -> Option<f64> {
        (self.n > 0).then(|| self.ms / self.n as f64)
    }

    /// What the filmed episodes took beyond an unfilmed episode's mean `mean_ms`.
    fn filmed_surplus_ms(&self, mean_ms: f64) -> f64 {
        self.filmed.iter().map(|w| w - mean_ms).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filmed_episodes_stay_out_of_the_mean_and_count_their_surplus_once() {
        let done = Outcome::Completed { language_success: Some(true), cue_success: None, steps: 100 };
        let mut m = Measured::default();
        for wall in [800.0, 1000.0, 1200.0] {
            m.add(wall, &done, false);
        }
        m.add(2500.0, &done, true);
        assert_eq!((m.n, m.steps, m.filmed.len()), (3, 300, 1));
        assert_eq!(m.mean_ms(), Some(1000.0));
        assert_eq!(m.filmed_surplus_ms(1000.0), 1500.0);
        let mut only_filmed = Measured::default();
        only_filmed.add(2500.0, &done, true);
        assert_eq!(only_filmed.mean_ms(), None);
    }
}
