//! The episodes of a run: which instances and tasks, under which protocols, from which
//! initial states.

use std::collections::{BTreeMap, BTreeSet};

use vifo_cues::{CueSpec, Family, SetName};

use super::{BenchmarkError, builtin_task, instances, language};
use crate::runner::{seed_for, stable_hash};
use crate::spec::{EpisodeSpec, Protocol, TaskRef};

/// Fixed initial states shipped per task; episode `e` starts from state `e % INIT_STATES`.
pub const INIT_STATES: usize = 50;

/// Most episodes per instance a selection takes: its specs are listed before anything runs,
/// so a mistyped count would fill the memory instead (the initial states repeat every 50).
pub const MAX_EPISODES: usize = 10_000;

/// Which part of the benchmark to run.
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// The instance set the cue instances come from.
    pub set: SetName,
    /// Suite names; empty means all four.
    pub suites: Vec<String>,
    pub protocols: Vec<Protocol>,
    /// Cue families; empty means all eight.
    pub families: Vec<Family>,
    /// At most this many instances per family, spread over suites and tasks (`None`: all).
    pub per_family: Option<usize>,
    /// Episodes per instance (or, for the original protocol, per task) and protocol.
    pub episodes: usize,
}

impl Selection {
    /// The whole benchmark over the paper set, `episodes` per instance and protocol.
    pub fn all(episodes: usize) -> Selection {
        Selection {
            set: SetName::Paper,
            suites: Vec::new(),
            protocols: Protocol::ALL.to_vec(),
            families: Vec::new(),
            per_family: None,
            episodes,
        }
    }

    /// `vifo run`'s quick default: one instance per family, one episode each, every protocol.
    pub fn quick() -> Selection {
        Selection { per_family: Some(1), ..Selection::all(1) }
    }
}

/// The spec of one episode, with its instruction, language and cue tasks and its seed.
pub fn spec(
    task: &TaskRef,
    protocol: Protocol,
    instance: Option<&str>,
    init: usize,
    episode: usize,
) -> Result<EpisodeSpec, BenchmarkError> {
    let builtin = builtin_task(task)?;
    let instance = match (protocol.uses_cue(), instance) {
        (false, _) => None,
        (true, None) => {
            return Err(BenchmarkError::MissingInstance { task: task.to_string(), protocol: protocol.name().into() });
        }
        (true, Some(id)) => {
            let cue = instances::find(id)?;
            if cue.task != task.to_string() {
                return Err(BenchmarkError::InstanceOfOtherTask {
                    instance: id.to_string(),
                    instance_task: cue.task.clone(),
                    task: task.to_string(),
                });
            }
            Some(id.to_string())
        }
    };
    let language = language::language_task(protocol, builtin)?;
    let mut spec = EpisodeSpec {
        task: task.clone(),
        protocol,
        instance,
        init: init % INIT_STATES,
        episode,
        instruction: language::instruction(protocol, builtin)?,
        language_task: language.and_then(|l| l.builtin),
        cue_task: protocol.uses_cue().then(|| task.clone()),
        seed: 0,
        cue_form: Default::default(),
    };
    spec.seed = seed_for(&spec);
    Ok(spec)
}

/// Every episode of a selection: per chosen instance the cue protocols, per task of a chosen
/// instance (all tasks of the suites when no family limit applies) the original protocol.
/// Episode `e` uses initial state `e % 50` and repetition `e / 50`.
pub fn specs(selection: &Selection) -> Result<Vec<EpisodeSpec>, BenchmarkError> {
    if selection.episodes > MAX_EPISODES {
        return Err(BenchmarkError::TooManyEpisodes(selection.episodes));
    }
    let suites = suite_list(&selection.suites)?;
    let chosen = choose_instances(selection.set, &suites, &selection.families, selection.per_family)?;
    let mut out = Vec::new();
    let episodes = |out: &mut Vec<EpisodeSpec>, task: &TaskRef, protocol: Protocol, instance: Option<&str>| {
        (0..selection.episodes)
            .try_for_each(|e| {
                out.push(spec(task, protocol, instance, e % INIT_STATES, e / INIT_STATES)?);
                Ok(())
            })
    };
    if selection.protocols.contains(&Protocol::Original) {
        let tasks: BTreeSet<TaskRef> = if selection.per_family.is_some() || !selection.families.is_empty() {
            chosen.iter().map(|c| instances::task_of(c)).collect::<Result<_, _>>()?
        } else {
            suites.iter().flat_map(|s| (0..10).map(|index| TaskRef { suite: s.clone(), index })).collect()
        };
        for task in &tasks {
            episodes(&mut out, task, Protocol::Original, None)?;
        }
    }
    for cue in &chosen {
        let task = instances::task_of(cue)?;
        for &protocol in selection.protocols.iter().filter(|p| p.uses_cue()) {
            episodes(&mut out, &task, protocol, Some(&cue.id()))?;
        }
    }
    Ok(out)
}

/// The suites of a selection, checked, in reporting order (an unknown name is an error).
pub fn suite_list(names: &[String]) -> Result<Vec<String>, BenchmarkError> {
    let all = vifo_scenes::suite_names();
    if names.is_empty() || names.iter().any(|n| n == "all") {
        return Ok(all.iter().map(|s| s.to_string()).collect());
    }
    for n in names {
        if !all.contains(&n.as_str()) {
            return Err(BenchmarkError::UnknownSuite(n.clone()));
        }
    }
    Ok(all.iter().filter(|s| names.iter().any(|n| n == *s)).map(|s| s.to_string()).collect())
}

/// The instances of the selection. With a per-family limit, each family takes its instances
/// from the suites in turn (starting at a different suite per family) and, within a suite,
/// in the order of a stable hash of the id, one per task.
fn choose_instances(
    set: SetName,
    suites: &[String],
    families: &[Family],
    per_family: Option<usize>,
) -> Result<Vec<&'static CueSpec>, BenchmarkError> {
    let in_scope = |c: &&CueSpec| {
        let suite = c.task.split('/').next().unwrap_or("");
        suites.iter().any(|s| s == suite) && (families.is_empty() || families.contains(&c.family))
    };
    let all: Vec<&'static CueSpec> = instances::all(set).iter().filter(in_scope).collect();
    let Some(limit) = per_family else { return Ok(all) };
    let mut out = Vec::new();
    for (f, family) in Family::ALL.iter().enumerate() {
        let per_suite: Vec<Vec<&CueSpec>> = suites
            .iter()
            .map(|s| {
                let mut list: Vec<&CueSpec> =
                    all.iter().copied().filter(|c| c.family == *family && c.task.starts_with(&format!("{s}/"))).collect();
                list.sort_by_key(|c| stable_hash(&c.id()));
                list
            })
            .collect();
        let mut used_tasks = BTreeSet::new();
        let mut taken = 0;
        let mut round = 0;
        while taken < limit && per_suite.iter().any(|l| l.iter().any(|c| !used_tasks.contains(&c.task))) {
            let list = &per_suite[(f + round) % suites.len()];
            round += 1;
            if let Some(c) = list.iter().find(|c| !used_tasks.contains(&c.task)) {
                used_tasks.insert(c.task.clone());
                out.push(*c);
                taken += 1;
            }
        }
    }
    Ok(out)
}

/// About `n` specs of `all`: per protocol a share in proportion to its count (at least one),
/// the ones with the smallest stable hash of their key, so the sample is the same on every
/// run and spread over suites, tasks and families.
pub fn sample(all: &[EpisodeSpec], n: usize) -> Vec<EpisodeSpec> {
    let mut by_protocol: BTreeMap<Protocol, Vec<&EpisodeSpec>> = BTreeMap::new();
    for s in all {
        by_protocol.entry(s.protocol).or_default().push(s);
    }
    let mut out = Vec::new();
    for list in by_protocol.values_mut() {
        let take = (n * list.len()).div_ceil(all.len().max(1)).clamp(1, list.len());
        list.sort_by_key(|s| stable_hash(&s.key()));
        out.extend(list[..take].iter().map(|s| (*s).clone()));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_whole_benchmark_has_every_instance_under_three_protocols_and_every_task_once() {
        let specs = specs(&Selection::all(1)).unwrap();
        let n = instances::all(SetName::Paper).len();
        assert_eq!(n, 1347);
        assert_eq!(specs.len(), 40 + 3 * n);
        let full = specs_of(SetName::Full);
        assert_eq!(full.len(), 40 + 3 * instances::all(SetName::Full).len());
        let keys: BTreeSet<String> = specs.iter().map(|s| s.key()).collect();
        assert_eq!(keys.len(), specs.len());
        for s in &specs {
            assert_eq!(s.seed, seed_for(s));
            assert_eq!(s.instance.is_some(), s.protocol.uses_cue());
        }
    }

    fn specs_of(set: SetName) -> Vec<EpisodeSpec> {
        specs(&Selection { set, ..Selection::all(1) }).unwrap()
    }

    #[test]
    fn quick_takes_one_instance_per_family_from_different_suites() {
        let specs = specs(&Selection::quick()).unwrap();
        let instances: BTreeSet<&str> = specs.iter().filter_map(|s| s.instance.as_deref()).collect();
        assert_eq!(instances.len(), 8);
        let suites: BTreeSet<&str> = specs.iter().map(|s| s.task.suite.as_str()).collect();
        assert_eq!(suites.len(), 4);
        let originals = specs.iter().filter(|s| s.protocol == Protocol::Original).count();
        assert!((1..=8).contains(&originals));
    }

    #[test]
    fn episodes_cycle_through_the_initial_states() {
        let sel = Selection { suites: vec!["libero_goal".into()], protocols: vec![Protocol::Original], episodes: 52, ..Selection::all(0) };
        let specs = specs(&sel).unwrap();
        assert_eq!(specs.len(), 520);
        let last = specs.iter().rfind(|s| s.task.index == 0).unwrap();
        assert_eq!((last.init, last.episode), (1, 1));
    }

    #[test]
    fn bad_selections_are_errors() {
        let sel = Selection { suites: vec!["libero_90".into()], ..Selection::quick() };
        assert!(specs(&sel).unwrap_err().to_string().contains("libero_90"));
        let task = TaskRef { suite: "libero_goal".into(), index: 3 };
        assert!(matches!(spec(&task, Protocol::Authorized, None, 0, 0), Err(BenchmarkError::MissingInstance { .. })));
        let other = "libero_goal/4/F2/straight_arrow_red";
        assert!(matches!(spec(&task, Protocol::Authorized, Some(other), 0, 0), Err(BenchmarkError::InstanceOfOtherTask { .. })));
        assert!(matches!(spec(&task, Protocol::Authorized, Some("nope"), 0, 0), Err(BenchmarkError::UnknownInstance { .. })));
        // A mistyped variant names the variants of its family that the task carries.
        let typo = spec(&task, Protocol::Authorized, Some("libero_goal/3/F2/straight_arow_red"), 0, 0).unwrap_err().to_string();
        assert!(typo.contains("straight_arrow_red") && typo.contains("vifo cues list --ids --task libero_goal/3"), "{typo}");
    }
}
