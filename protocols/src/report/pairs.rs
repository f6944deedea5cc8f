//! Two policies compared on the episodes both ran: the question a reader of Table 1 asks ("is A
//! better than B here, or is it this run's luck?") answered with the runs' own pairing. Every
//! policy runs the same episodes (task, cue instance, initial state and seed come from the
//! episode's key), so each metric's difference is taken over the episodes both completed, and
//! its 95 % interval is that of a change on the same episodes ([`PairedChange`]), per cue
//! family and then their unweighted mean, as Table 1's columns are formed. Pairing makes the
//! interval narrower than two rates' intervals side by side would suggest.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::interval::{Interval, PairedChange};
use super::{Flag, cue, family_of, language};
use crate::spec::{EpisodeRecord, Protocol};

/// One metric's difference, A − B, in points.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Difference {
    pub points: f64,
    pub ci95: Interval,
    /// Episodes both completed with the metric's flag.
    pub pairs: usize,
}

impl Difference {
    /// Whether the interval leaves out 0: the two differ beyond this run's noise (each comparison
    /// on its own; among many, some do by chance).
    pub fn clear(&self) -> bool {
        self.ci95.low > 0.0 || self.ci95.high < 0.0
    }
}

/// Policy `a` against policy `b` on the episodes both ran: Table 1's episode columns but VTR.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    pub a: String,
    pub b: String,
    pub orig_sr: Option<Difference>,
    pub avf: Option<Difference>,
    pub lfr: Option<Difference>,
    pub uvf: Option<Difference>,
    pub uvi: Option<Difference>,
}

/// A metric compared: its Markdown header (with Table 1's arrow) and CSV name, protocol, success
/// flag, and whether it is a mean over cue families.
pub(crate) type Metric = (&'static str, &'static str, Protocol, Flag, bool);

pub(crate) const METRICS: [Metric; 5] = [
    ("Orig. SR↑", "Orig_SR", Protocol::Original, language, false),
    ("AVF↑", "AVF", Protocol::Authorized, cue, true),
    ("LFR↑", "LFR", Protocol::Conflict, language, true),
    ("UVF↓", "UVF", Protocol::Conflict, cue, true),
    ("UVI↓", "UVI", Protocol::NoLanguage, cue, true),
];

impl Comparison {
    /// The differences in Table 1's order: Orig. SR, AVF, LFR, UVF, UVI.
    pub fn differences(&self) -> [Option<Difference>; 5] {
        [self.orig_sr, self.avf, self.lfr, self.uvf, self.uvi]
    }
}

/// A row's name and its episodes by key, as Table 1's rows hold them.
pub type KeyedRow = (String, BTreeMap<String, EpisodeRecord>);

/// Every pair of `rows`, in their order, that shares at least one scored episode.
pub fn compare_all(rows: &[KeyedRow]) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (i, (a, of_a)) in rows.iter().enumerate() {
        for (b, of_b) in &rows[i + 1..] {
            let [orig_sr, avf, lfr, uvf, uvi] = METRICS.map(|(_, _, protocol, flag, families)| difference(of_a, of_b, protocol, flag, families));
            let c = Comparison { a: a.clone(), b: b.clone(), orig_sr, avf, lfr, uvf, uvi };
            if c.differences().iter().any(Option::is_some) {
                out.push(c);
            }
        }
    }
    out
}

/// A − B for one metric over the episodes of `protocol` both completed with `flag` set; with
/// `families`, the unweighted mean over the cue families of each family's difference.
fn difference(
    a: &BTreeMap<String, EpisodeRecord>,
    b: &BTreeMap<String, EpisodeRecord>,
    protocol: Protocol,
    flag: Flag,
    families: bool,
) -> Option<Difference> {
    // Per family (or one group): each episode's (B's success, A's success).
    let mut groups: BTreeMap<Option<vifo_cues::Family>, Vec<(bool, bool)>> = BTreeMap::new();
    for (key, ra) in a.iter().filter(|(_, r)| r.spec.protocol == protocol) {
        let Some(rb) = b.get(key) else { continue };
        let (Some(Some(sa)), Some(Some(sb))) = (flag(&ra.outcome), flag(&rb.outcome)) else { continue };
        let group = match (families, ra.spec.instance.as_deref().and_then(family_of)) {
            (false, _) => None,
            (true, Some(family)) => Some(family),
            (true, None) => continue,
        };
        groups.entry(group).or_default().push((sb, sa));
    }
    let changes: Vec<PairedChange> = groups.values().filter_map(|pairs| PairedChange::of_pairs(pairs.iter().copied())).collect();
    let mean = PairedChange::mean(&changes)?;
    Some(Difference { points: mean.points(), ci95: mean.interval(), pairs: groups.values().map(Vec::len).sum() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{EpisodeSpec, Outcome, RESULTS_VERSION, TaskRef};

    fn record(policy: &str, protocol: Protocol, family: &str, init: usize, success: bool) -> EpisodeRecord {
        let language = matches!(protocol, Protocol::Original | Protocol::Conflict).then_some(success);
        let cue = protocol.uses_cue().then_some(success);
        EpisodeRecord {
            version: RESULTS_VERSION,
            spec: EpisodeSpec {
                task: TaskRef { suite: "libero_goal".into(), index: 1 },
                protocol,
                instance: protocol.uses_cue().then(|| format!("libero_goal/1/{family}/v")),
                init,
                episode: 0,
                instruction: String::new(),
                language_task: None,
                cue_task: None,
                seed: init as u64,
                cue_form: Default::default(),
            },
            policy: policy.into(),
            outcome: Outcome::Completed { language_success: language, cue_success: cue, steps: 1 },
            wall_ms: 1.0,
            set: vifo_cues::SetName::Paper,
            look: String::new(),
        }
    }

    fn keyed(records: Vec<EpisodeRecord>) -> BTreeMap<String, EpisodeRecord> {
        records.into_iter().map(|r| (r.spec.key(), r)).collect()
    }

    #[test]
    fn differences_are_taken_over_the_episodes_both_ran() {
        // Orig. SR: on 20 shared states A succeeds 18 times, B 10, and B alone never; A also ran
        // 5 states B did not (left out).
        let mut a: Vec<EpisodeRecord> = (0..25).map(|i| record("a", Protocol::Original, "-", i, !(18..20).contains(&i))).collect();
        let mut b: Vec<EpisodeRecord> = (0..20).map(|i| record("b", Protocol::Original, "-", i, i < 10)).collect();
        // AVF: F1 A 2/2 and B 0/2; F2 both 1/2 on the same episode: the mean of +100 and 0.
        for (family, a_ok, b_ok) in [("F1", [true, true], [false, false]), ("F2", [true, false], [true, false])] {
            for i in 0..2 {
                a.push(record("a", Protocol::Authorized, family, i, a_ok[i]));
                b.push(record("b", Protocol::Authorized, family, i, b_ok[i]));
            }
        }
        let rows = [("a".to_string(), keyed(a)), ("b".to_string(), keyed(b)), ("c".to_string(), BTreeMap::new())];
        let [c] = &compare_all(&rows)[..] else { panic!("one pair shares episodes") };
        let orig = c.orig_sr.unwrap();
        assert_eq!((orig.points, orig.pairs), (40.0, 20));
        assert_eq!(orig.ci95, PairedChange::of(8, 0, 20).unwrap().interval());
        assert!(orig.clear());
        let avf = c.avf.unwrap();
        assert_eq!((avf.points, avf.pairs), (50.0, 4));
        let expected = PairedChange::mean(&[PairedChange::of(2, 0, 2).unwrap(), PairedChange::of(0, 0, 2).unwrap()]).unwrap();
        assert_eq!(avf.ci95, expected.interval());
        assert!(!avf.clear(), "two episodes per family tell little: {avf:?}");
        assert_eq!((c.lfr, c.uvf, c.uvi), (None, None, None));
    }
}
