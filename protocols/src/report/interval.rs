//! 95 % intervals for the tables' rates, so that a reader can tell a difference between two
//! models, or between our Orig. SR and a model's published LIBERO figure, from the noise of a
//! few dozen episodes.
//!
//! A rate is a mean of `m` proportions: one for Orig. SR (its original episodes), one per cue
//! family with data for the cue and VQA columns (the unweighted family mean the tables show).
//! Each proportion gets `2/m` successes and `4/m` trials added, and the interval is the normal
//! one around the mean of the adjusted proportions (Price and Bonett, 2004, "An improved
//! confidence interval for a linear function of binomial proportions"). With one proportion
//! that is Agresti and Coull's interval (two successes and two failures added), which keeps its
//! 95 % coverage at 0 or 100 % and a handful of episodes, where the textbook interval shrinks to
//! nothing. Only `sqrt` is used: the same bits on every architecture.

use serde::{Deserialize, Serialize};

use crate::vqa::Accuracy;

/// What a single rate's interval is, for the notes under the studies' tables.
pub const ONE_RATE_NOTE: &str = "the 95 % interval of a rate: where its true value plausibly lies given its episodes \
(Agresti and Coull's: two successes and two failures added, the normal interval around the adjusted rate)";

/// The normal distribution's 97.5th percentile.
const Z95: f64 = 1.959_963_984_540_054;

/// A 95 % interval in percent, within 0–100 (a [`PairedChange`]'s in points, within ±100).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    pub low: f64,
    pub high: f64,
}

impl Interval {
    /// The interval of the unweighted mean of the rates with data (`total > 0`); `None` where none
    /// has any.
    pub fn of_mean<'a>(rates: impl IntoIterator<Item = &'a Accuracy>) -> Option<Interval> {
        let rates: Vec<&Accuracy> = rates.into_iter().filter(|a| a.total > 0).collect();
        if rates.is_empty() {
            return None;
        }
        let m = rates.len() as f64;
        let (mut sum, mut variance) = (0.0, 0.0);
        for a in rates {
            let trials = a.total as f64 + 4.0 / m;
            let p = (a.correct as f64 + 2.0 / m) / trials;
            sum += p;
            variance += p * (1.0 - p) / trials;
        }
        let (centre, half) = (sum / m, Z95 * variance.sqrt() / m);
        Some(Interval { low: 100.0 * (centre - half).max(0.0), high: 100.0 * (centre + half).min(1.0) })
    }

    /// The interval of one rate.
    pub fn of(rate: &Accuracy) -> Option<Interval> {
        Interval::of_mean([rate])
    }

    /// `83.5–98.4`, as the tables' cells.
    pub fn text(&self) -> String {
        format!("{:.1}–{:.1}", self.low, self.high)
    }

    /// `,83.47,98.41` after a CSV row's other columns (`,,` without an interval).
    pub fn csv(interval: Option<Interval>) -> String {
        interval.map_or(",,".to_string(), |i| format!(",{:.2},{:.2}", i.low, i.high))
    }
}

/// A change between two rates measured on the same episodes (the objects study's object −
/// overlay, one policy's rate less another's), or a weighted mean of such changes (over cue
/// families, over policies). Kept as the counts of each table of pairs, so that a mean's interval
/// is made from them as one: Agresti and Min (2005) add half a pair to each of a table's four
/// outcomes; a mean of m tables adds 1/(2m) to each of each table's, as Price and Bonett spread
/// Agresti and Coull's adjustment over a mean of rates, so that a table of one or two pairs does
/// not pull a mean of eight towards 0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairedChange {
    /// (weight, [gained, lost, pairs]) per table; the weights sum to 1.
    tables: Vec<(f64, [usize; 3])>,
}

impl PairedChange {
    /// From `pairs` episodes run both ways, `gained` of which succeeded only the second way and
    /// `lost` only the first; `None` without pairs.
    pub fn of(gained: usize, lost: usize, pairs: usize) -> Option<PairedChange> {
        (pairs > 0).then(|| PairedChange { tables: vec![(1.0, [gained, lost, pairs])] })
    }

    /// From episodes run both ways, each `(first, second)`: whether it succeeded the first way and
    /// the second; `None` without any.
    pub fn of_pairs(pairs: impl IntoIterator<Item = (bool, bool)>) -> Option<PairedChange> {
        let [mut gained, mut lost, mut n] = [0; 3];
        for (first, second) in pairs {
            gained += usize::from(second && !first);
            lost += usize::from(first && !second);
            n += 1;
        }
        PairedChange::of(gained, lost, n)
    }

    /// The unweighted mean of `changes` (each a table or itself a mean); `None` for none.
    pub fn mean(changes: &[PairedChange]) -> Option<PairedChange> {
        let m = changes.len() as f64;
        let tables = changes.iter().flat_map(|c| c.tables.iter().map(|&(w, counts)| (w / m, counts))).collect();
        (!changes.is_empty()).then_some(PairedChange { tables })
    }

    /// The change, in points (the second way's rate less the first's over each table's pairs,
    /// weighted).
    pub fn points(&self) -> f64 {
        100.0 * self.tables.iter().map(|&(w, [gained, lost, pairs])| w * (gained as f64 - lost as f64) / pairs as f64).sum::<f64>()
    }

    /// The 95 % interval, in points.
    pub fn interval(&self) -> Interval {
        let half_pair = 0.5 / self.tables.len() as f64;
        let (mut centre, mut variance) = (0.0, 0.0);
        for &(w, [gained, lost, pairs]) in &self.tables {
            let (c, b, n) = (gained as f64 + half_pair, lost as f64 + half_pair, pairs as f64 + 4.0 * half_pair);
            centre += w * (c - b) / n;
            variance += w * w * ((b + c) - (c - b) * (c - b) / n) / (n * n);
        }
        let half = Z95 * variance.sqrt();
        Interval { low: 100.0 * (centre - half).max(-1.0), high: 100.0 * (centre + half).min(1.0) }
    }
}

/// A rate with its counts and interval, `94.0 (47/50; 83.0–98.5)`, or `–` without episodes.
pub fn rate_cell(rate: &Accuracy) -> String {
    match (rate.percent(), Interval::of(rate)) {
        (Some(p), Some(i)) => format!("{p:.1} ({}/{}; {})", rate.correct, rate.total, i.text()),
        _ => "–".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn acc(correct: usize, total: usize) -> Accuracy {
        Accuracy { correct, total }
    }

    fn close(i: Interval, low: f64, high: f64) {
        assert!((i.low - low).abs() < 0.05 && (i.high - high).abs() < 0.05, "{i:?} against {low}–{high}");
    }

    #[test]
    fn one_rate_is_agresti_coull() {
        // Agresti and Coull (1998): 47 of 50 gives p̃ = 49/54, half width 1.96·√(p̃(1−p̃)/54).
        close(Interval::of(&acc(47, 50)).unwrap(), 83.01, 98.47);
        // At the edges the interval stays wide and within 0–100.
        close(Interval::of(&acc(0, 5)).unwrap(), 0.0, 49.38);
        close(Interval::of(&acc(5, 5)).unwrap(), 50.62, 100.0);
        assert_eq!(Interval::of(&acc(0, 0)), None);
    }

    #[test]
    fn a_mean_of_rates_narrows_with_more_families_and_episodes() {
        // Two families: Agresti and Caffo's adjustment (one success and one failure each).
        let two = Interval::of_mean(&[acc(8, 10), acc(2, 10)]).unwrap();
        let (p1, p2) = (9.0 / 12.0, 3.0 / 12.0);
        let half = Z95 * (p1 * (1.0 - p1) / 12.0 + p2 * (1.0 - p2) / 12.0f64).sqrt() / 2.0;
        close(two, 100.0 * (0.5 - half), 100.0 * (0.5 + half));
        let more = Interval::of_mean(&[acc(80, 100), acc(20, 100)]).unwrap();
        assert!(more.high - more.low < two.high - two.low);
        // Families without episodes are not part of the mean.
        assert_eq!(Interval::of_mean(&[acc(8, 10), acc(2, 10), acc(0, 0)]), Some(two));
        assert_eq!(Interval::of_mean(&[acc(0, 0)]), None);
        assert_eq!(two.text(), format!("{:.1}–{:.1}", two.low, two.high));
    }

    #[test]
    fn a_paired_change_is_agresti_min_and_means_of_changes_spread_the_adjustment() {
        // 20 pairs, 2 gained and 8 lost: (2.5 − 8.5) / 22 ± 1.96·√((11 − 36/22) / 22²).
        let one = PairedChange::of(2, 8, 20).unwrap();
        let (d, half) = (-6.0 / 22.0, Z95 * ((11.0 - 36.0 / 22.0) / 484.0f64).sqrt());
        close(one.interval(), 100.0 * (d - half), 100.0 * (d + half));
        assert!((one.points() + 30.0).abs() < 1e-9, "{}", one.points());
        // No discordant pair: centred on 0, still of some width; within ±100 at the extremes.
        let none = PairedChange::of(0, 0, 20).unwrap().interval();
        assert!((none.low + none.high).abs() < 1e-9 && none.high > 5.0, "{none:?}");
        let all_lost = PairedChange::of(0, 3, 3).unwrap().interval();
        assert!(all_lost.low >= -100.0 && all_lost.high < 0.0, "{all_lost:?}");
        assert_eq!(PairedChange::of(0, 0, 0), None);
        let outcomes = [(true, false), (false, true), (true, true), (false, false), (true, false)];
        assert_eq!(PairedChange::of_pairs(outcomes), PairedChange::of(1, 2, 5));
        assert_eq!(PairedChange::of_pairs([]), None);
        // A mean of two tables adds a quarter pair to each outcome of each: (2.25 − 8.25) / 21.
        let two = PairedChange::mean(&[one.clone(), one.clone()]).unwrap();
        let (d2, half2) = (-6.0 / 21.0, Z95 * ((10.5 - 36.0 / 21.0) / 441.0f64).sqrt() / 2f64.sqrt());
        close(two.interval(), 100.0 * (d2 - half2), 100.0 * (d2 + half2));
        assert!((PairedChange::mean(&[one.clone(), PairedChange::of(4, 0, 20).unwrap()]).unwrap().points() + 5.0).abs() < 1e-9);
        // Eight families of one pair each, every one gained: the interval holds the +100 it shows.
        let eight = vec![PairedChange::of(1, 0, 1).unwrap(); 8];
        let mean = PairedChange::mean(&eight).unwrap();
        assert!(mean.points() == 100.0 && mean.interval().high == 100.0 && mean.interval().low > 0.0, "{:?}", mean.interval());
        // A mean of means weighs each table as the means do: (a + (b + c) / 2) / 2.
        let nested = PairedChange::mean(&[one.clone(), PairedChange::mean(&[one.clone(), PairedChange::of(4, 0, 20).unwrap()]).unwrap()]).unwrap();
        assert!((nested.points() - (-30.0 + (-30.0 + 20.0) / 2.0) / 2.0).abs() < 1e-9);
        assert_eq!(PairedChange::mean(&[]), None);
    }

    /// How often the intervals hold the true value, over random rates and, for changes, two
    /// ways correlated at random: near the 95 % they claim, at 0 or 100 % and with one episode
    /// per family too (the textbook interval, without the adjustment, held the rate of 5
    /// episodes in 51 % of these trials).
    #[test]
    fn the_intervals_hold_the_true_value_about_95_times_in_100() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        const RATES: [f64; 7] = [0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 0.98];
        const TRIALS: usize = 2000;
        for (m, n) in [(1, 5), (1, 50), (8, 1), (8, 10)] {
            let (mut means, mut changes) = (0, 0);
            for _ in 0..TRIALS {
                let truth: Vec<f64> = (0..m).map(|_| RATES[rng.random_range(0..RATES.len())]).collect();
                let rates: Vec<Accuracy> =
                    truth.iter().map(|&p| Accuracy { correct: (0..n).filter(|_| rng.random::<f64>() < p).count(), total: n }).collect();
                let i = Interval::of_mean(&rates).unwrap();
                let mean = 100.0 * truth.iter().sum::<f64>() / m as f64;
                means += usize::from(i.low <= mean && mean <= i.high);
                let mut tables = Vec::new();
                let mut difference = 0.0;
                for _ in 0..m {
                    let (pa, pb, shared) = (RATES[rng.random_range(1..6)], RATES[rng.random_range(1..6)], rng.random::<f64>());
                    let (mut gained, mut lost) = (0, 0);
                    for _ in 0..n {
                        let u = rng.random::<f64>();
                        let b = if rng.random::<f64>() < shared { u < pb } else { rng.random::<f64>() < pb };
                        gained += usize::from(!b && u < pa);
                        lost += usize::from(b && u >= pa);
                    }
                    tables.push(PairedChange::of(gained, lost, n).unwrap());
                    difference += 100.0 * (pa - pb) / m as f64;
                }
                let c = PairedChange::mean(&tables).unwrap().interval();
                changes += usize::from(c.low <= difference && difference <= c.high);
            }
            let (means, changes) = (means as f64 / TRIALS as f64, changes as f64 / TRIALS as f64);
            assert!((0.92..=0.99).contains(&means), "{m} rates of {n}: a mean's interval held it {means}");
            assert!((0.92..=0.99).contains(&changes), "{m} tables of {n}: a change's interval held it {changes}");
        }
    }

    #[test]
    fn cells_show_the_rate_its_counts_and_interval() {
        assert_eq!(rate_cell(&acc(47, 50)), "94.0 (47/50; 83.0–98.5)");
        assert_eq!(rate_cell(&acc(0, 0)), "–");
        assert_eq!(Interval::csv(Interval::of(&acc(47, 50))), ",83.01,98.47");
        assert_eq!(Interval::csv(None), ",,");
    }
}
