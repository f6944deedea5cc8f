//! `vifo run --sample N`: time a representative part of a selection and extrapolate the time
//! of all of it (the gate measurement of the whole benchmark in ≤ 60 min on 2 cores).

use std::collections::BTreeMap;
use std::path::Path;

use vifo_protocols::runner::{final_records, read_records};
use vifo_protocols::spec::{EpisodeSpec, Outcome};
use vifo_protocols::Protocol;

/// Prints per protocol the sample's mean episode time and the extrapolated time of `all`
/// on `threads` threads (0: every core), assuming episodes keep the cores busy.
pub fn print(all: &[EpisodeSpec], sample: &[EpisodeSpec], results: &Path, threads: usize) -> anyhow::Result<()> {
    let threads = if threads == 0 { rayon::current_num_threads() } else { threads };
    let keys: std::collections::BTreeSet<String> = sample.iter().map(EpisodeSpec::key).collect();
    let records = final_records(read_records(results)?.records);
    let mut measured: BTreeMap<Protocol, (f64, usize, usize)> = BTreeMap::new();
    for r in records.values().filter(|r| keys.contains(&r.spec.key())) {
        let m = measured.entry(r.spec.protocol).or_default();
        m.0 += r.wall_ms;
        m.1 += 1;
        if let Outcome::Completed { steps, .. } = r.outcome {
            m.2 += steps;
        }
    }
    let mut counts: BTreeMap<Protocol, usize> = BTreeMap::new();
    for s in all {
        *counts.entry(s.protocol).or_default() += 1;
    }
    println!("  time estimate for all {} episodes on {threads} thread(s):", all.len());
    println!("  | protocol | episodes | sampled | mean s/episode | mean steps | estimate (min) |");
    println!("  |---|---|---|---|---|---|");
    let mut total = 0.0;
    for (protocol, count) in &counts {
        let Some(&(ms, n, steps)) = measured.get(protocol).filter(|m| m.1 > 0) else { continue };
        let mean = ms / n as f64 / 1e3;
        let minutes = mean * *count as f64 / threads as f64 / 60.0;
        total += minutes;
        println!(
            "  | {} | {count} | {n} | {mean:.2} | {:.0} | {minutes:.1} |",
            protocol.name(),
            steps as f64 / n as f64
        );
    }
    println!("  | all | {} | {} | | | **{total:.1}** |", all.len(), keys.len());
    Ok(())
}
