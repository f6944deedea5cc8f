//! The two named instance sets: `full` (everything the library makes for the tasks) and
//! `paper` (the size and family shares the paper reports: 1,347 instances of 33 variants,
//! geometric 23.8 %, highlights 20.8 %, pictorial 20.0 %).
//!
//! The paper states its total, its variant count and three family shares, and that seven
//! families cover all 40 tasks and ghosts 38; it does not list its variants or instances. The
//! `paper` set is chosen from the `full` set by this rule (no list of ids):
//!
//! 1. **Variants.** The three families with a stated share keep every variant (their shares
//!    need them all). The other five keep their first two variants in catalogue order ("each
//!    family includes multiple variants"); the slots left up to 33 go one at a time to those
//!    five in order of how many variants the catalogue has (most first, ties in family order).
//! 2. **Quotas.** A stated family gets its share of 1,347, rounded; the other five split the
//!    rest in proportion to the instances their kept variants make (largest remainder, ties in
//!    family order).
//! 3. **Instances.** Within a family, instances of the kept variants are taken in this order
//!    until the quota is filled: for each task the first-step instance with the smallest
//!    FNV-1a hash of its id (so every task the family can serve keeps one), then the other
//!    first-step instances, then the later-step (`@n`) ones, each group by that hash.
//!
//! The set keeps the `full` set's order. The rule is checked, not assumed: [`select`] fails
//! with the reason when the full set cannot fill a quota.

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use super::InstanceSet;
use crate::hash::fnv1a64;
use crate::spec::{CueSpec, Family};
use crate::variants::{self, Variant};

/// Which instance set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SetName {
    /// The paper's size and stated shares (the default of `vifo run`, `vifo vqa export`).
    Paper,
    /// Every instance the library makes.
    Full,
}

impl SetName {
    pub const ALL: [SetName; 2] = [SetName::Paper, SetName::Full];

    pub fn name(self) -> &'static str {
        match self {
            SetName::Paper => "paper",
            SetName::Full => "full",
        }
    }
}

impl std::fmt::Display for SetName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for SetName {
    type Err = String;

    fn from_str(s: &str) -> Result<SetName, String> {
        SetName::ALL
            .into_iter()
            .find(|n| n.name() == s)
            .ok_or_else(|| format!("unknown instance set {s:?}: expected paper or full"))
    }
}

/// Instances of the paper's benchmark.
pub const INSTANCES: usize = 1347;
/// Cue variants of the paper's benchmark.
pub const VARIANTS: usize = 33;
/// VQA questions of the paper's benchmark (four per instance).
pub const QUESTIONS: usize = 5388;
/// The family shares the paper states (appendix A).
pub const STATED_SHARES: [(Family, f64); 3] = [(Family::F2, 0.238), (Family::F7, 0.208), (Family::F4, 0.200)];
/// Variants a family without a stated share keeps at least.
const MIN_VARIANTS: usize = 2;

fn stated(f: Family) -> Option<f64> {
    STATED_SHARES.iter().find(|(g, _)| *g == f).map(|(_, s)| *s)
}

/// The paper set's variants (rule 1), in catalogue order.
pub fn kept_variants() -> Vec<&'static Variant> {
    let in_catalogue = |f: Family| variants::of_family(f).count();
    let mut keep: BTreeMap<Family, usize> = Family::ALL
        .iter()
        .map(|&f| (f, if stated(f).is_some() { in_catalogue(f) } else { MIN_VARIANTS.min(in_catalogue(f)) }))
        .collect();
    let mut open: Vec<Family> = Family::ALL.into_iter().filter(|&f| stated(f).is_none()).collect();
    open.sort_by_key(|&f| std::cmp::Reverse(in_catalogue(f)));
    let mut i = 0;
    while keep.values().sum::<usize>() < VARIANTS && open.iter().any(|&f| keep[&f] < in_catalogue(f)) {
        let f = open[i % open.len()];
        if keep[&f] < in_catalogue(f) {
            *keep.entry(f).or_default() += 1;
        }
        i += 1;
    }
    Family::ALL.iter().flat_map(|&f| variants::of_family(f).take(keep[&f])).collect()
}

/// Why the paper set cannot be chosen from a full set.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the paper set cannot be chosen from this instance set: {0}")]
pub struct PaperSetError(pub String);

/// Per-family quotas (rule 2) for a full set.
pub fn quotas(full: &InstanceSet) -> Result<BTreeMap<Family, usize>, PaperSetError> {
    let kept: BTreeSet<&str> = kept_variants().iter().map(|v| v.name).collect();
    let pool = |f: Family| full.instances.iter().filter(|s| s.family == f && kept.contains(s.variant.as_str())).count();
    let mut out: BTreeMap<Family, usize> = BTreeMap::new();
    for (f, share) in STATED_SHARES {
        out.insert(f, (share * INSTANCES as f64).round() as usize);
    }
    let rest = INSTANCES - out.values().sum::<usize>();
    let others: Vec<(Family, usize)> =
        Family::ALL.into_iter().filter(|&f| stated(f).is_none()).map(|f| (f, pool(f))).collect();
    let total: usize = others.iter().map(|(_, n)| n).sum();
    if total < rest {
        return Err(PaperSetError(format!("the five unstated families make {total} instances, fewer than the {rest} needed")));
    }
    let mut remainders = Vec::new();
    for &(f, n) in &others {
        let exact = rest as f64 * n as f64 / total as f64;
        out.insert(f, exact.floor() as usize);
        remainders.push((f, exact - exact.floor()));
    }
    // Largest remainder first; the stable sort keeps family order among ties.
    remainders.sort_by(|a, b| b.1.total_cmp(&a.1));
    let short = INSTANCES - out.values().sum::<usize>();
    for (f, _) in remainders.into_iter().take(short) {
        *out.entry(f).or_default() += 1;
    }
    for (&f, &q) in &out {
        if pool(f) < q {
            return Err(PaperSetError(format!("{f} needs {q} instances, its kept variants make {}", pool(f))));
        }
    }
    Ok(out)
}

/// The paper set chosen from a full set (rule 3).
pub fn select(full: &InstanceSet) -> Result<InstanceSet, PaperSetError> {
    let kept: BTreeSet<&str> = kept_variants().iter().map(|v| v.name).collect();
    let quotas = quotas(full)?;
    let mut chosen: BTreeSet<String> = BTreeSet::new();
    for (family, quota) in quotas {
        let pool: Vec<(&CueSpec, String)> = full
            .instances
            .iter()
            .filter(|s| s.family == family && kept.contains(s.variant.as_str()))
            .map(|s| (s, s.id()))
            .collect();
        let mut first_of_task: BTreeMap<&str, (u64, &str)> = BTreeMap::new();
        for (spec, id) in pool.iter().filter(|(_, id)| !id.contains('@')) {
            let h = (fnv1a64(id.as_bytes()), id.as_str());
            let e = first_of_task.entry(spec.task.as_str()).or_insert(h);
            *e = (*e).min(h);
        }
        let firsts: BTreeSet<&str> = first_of_task.values().map(|(_, id)| *id).collect();
        let mut ranked: Vec<(u8, u64, &str)> = pool
            .iter()
            .map(|(_, id)| {
                let tier = if firsts.contains(id.as_str()) {
                    0
                } else if !id.contains('@') {
                    1
                } else {
                    2
                };
                (tier, fnv1a64(id.as_bytes()), id.as_str())
            })
            .collect();
        ranked.sort_unstable();
        chosen.extend(ranked.into_iter().take(quota).map(|(.., id)| id.to_string()));
    }
    let instances: Vec<CueSpec> = full.instances.iter().filter(|s| chosen.contains(&s.id())).cloned().collect();
    if instances.len() != INSTANCES {
        return Err(PaperSetError(format!("chose {} instances, not {INSTANCES} (repeated ids?)", instances.len())));
    }
    Ok(InstanceSet { instances })
}
