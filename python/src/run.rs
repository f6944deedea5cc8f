//! Benchmark runs from Python (`libero_vifo.ray`): the episode list of a selection, episodes
//! run by the same code as `vifo run` (`env::rollout::run_episodes`), and the results file
//! written through the runner's own lock, checks and record writer, so `vifo report` and
//! `vifo run --resume` read what Python wrote.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use vifo_cues::{Family, SetName};
use vifo_protocols::benchmark::records::{check_record, check_spec, read_checked};
use vifo_protocols::benchmark::specs::{self, Selection};
use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::serving::{PolicySpec, Profile, ServingOptions};
use vifo_protocols::runner::{OpenResults, RunError, RunOptions, read_records};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec};
use vifo_protocols::{Policy, report, studies};
use vifo_scenes::view::CameraName;

use crate::callable::{PyPolicy, interruptible};

fn value_err(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn run_err(e: RunError) -> PyErr {
    PyRuntimeError::new_err(e.to_string())
}

fn parse_set(set: &str) -> PyResult<SetName> {
    set.parse().map_err(|e: String| PyValueError::new_err(e))
}

/// The episodes of a selection (`vifo run`'s options: `--set --suite --protocol --family
/// --per-family --episodes --sample`), as `(key, spec JSON)` in `vifo run`'s order.
#[pyfunction]
#[pyo3(signature = (set = "paper", suites = Vec::new(), protocols = Vec::new(), families = Vec::new(), per_family = None, episodes = 1, sample = None))]
pub fn episode_specs(
    set: &str,
    suites: Vec<String>,
    protocols: Vec<String>,
    families: Vec<String>,
    per_family: Option<usize>,
    episodes: usize,
    sample: Option<usize>,
) -> PyResult<Vec<(String, String)>> {
    let mut selection = Selection::all(episodes);
    selection.set = parse_set(set)?;
    selection.suites = suites;
    if !protocols.is_empty() && !protocols.iter().any(|p| p == "all") {
        selection.protocols = protocols.iter().map(|p| crate::protocol(p, "protocol")).collect::<PyResult<_>>()?;
    }
    selection.families = families
        .iter()
        .map(|f| {
            Family::ALL
                .into_iter()
                .find(|x| x.to_string().eq_ignore_ascii_case(f))
                .ok_or_else(|| PyValueError::new_err(format!("unknown cue family {f:?}: expected F1 to F8")))
        })
        .collect::<PyResult<_>>()?;
    selection.per_family = per_family;
    let mut specs = specs::specs(&selection).map_err(value_err)?;
    if let Some(n) = sample {
        if n == 0 {
            return Err(PyValueError::new_err("sample 0: expected 1 or more episodes"));
        }
        specs = specs::sample(&specs, n);
    }
    specs.iter().map(|s| Ok((s.key(), serde_json::to_string(s).map_err(value_err)?))).collect()
}

/// A policy as `vifo run --policy URL --model-profile P [--policy-name NAME]` takes it (plain
/// `ws://` without a profile is openpi's pi0.5 client), frames of side `size`.
fn policy_spec(policy: &str, model_profile: Option<&str>, size: u32, name: Option<String>) -> PyResult<PolicySpec> {
    let profile = model_profile
        .map(|n| Profile::named(n).ok_or_else(|| value_err(format!("unknown model_profile {n:?}: expected one of {}", Profile::names().join(", ")))))
        .transpose()?;
    if let Some(name) = &name {
        check_name(name)?;
    }
    let given = name.is_some();
    let serving = ServingOptions { profile, format: None, frame_size: size, request_timeout: None, name };
    let spec = PolicySpec::new(policy, || Ok::<_, vifo_protocols::PolicyError>(serving)).map_err(value_err)?;
    if let (true, Some(p)) = (spec.is_builtin(), profile) {
        return Err(value_err(format!("model_profile {:?} says how to talk to a policy server; {policy} is built-in", p.name)));
    }
    // As `vifo run --policy-name`: a built-in's records pass for no other policy's.
    if spec.is_builtin() && given {
        return Err(value_err(format!("name= names a served policy's records; {policy} is built-in and its records carry its own name")));
    }
    Ok(spec)
}

/// A name given to a served or Python policy (`name=`), as `vifo run --policy-name` takes it.
fn check_name(name: &str) -> PyResult<()> {
    vifo_protocols::policies::check_name(name).map_err(|e| value_err(format!("name {e}")))
}

/// Checks a policy as `vifo run --policy` takes it (a built-in or a server URL, with the
/// server's `model_profile` and the `name` its records carry instead of `<profile>@<url>`, as
/// `--policy-name`); returns `(the name its records carry, the label its results file is named
/// by, whether its server holds one client at a time)`.
#[pyfunction]
#[pyo3(signature = (policy, model_profile = None, name = None))]
pub fn check_policy(policy: &str, model_profile: Option<&str>, name: Option<String>) -> PyResult<(String, String, bool)> {
    let spec = policy_spec(policy, model_profile, 256, name)?;
    Ok((spec.record_name(), spec.results_label().to_string(), spec.serves_one_client()))
}

/// The results file name `vifo run` gives the policy labelled `label` (its given name, else
/// the `--policy` string): `results-<label, file-safe>.jsonl`.
#[pyfunction]
pub fn results_file_name(label: &str) -> String {
    vifo_protocols::runner::results::file_name(label)
}

/// The name `policy`'s records carry (`vifo run`'s): a built-in's, or `<profile>@<url>`
/// (`openpi@<url>` for plain ws://).
#[pyfunction]
#[pyo3(signature = (policy, model_profile = None))]
pub fn policy_name(policy: &str, model_profile: Option<&str>) -> PyResult<String> {
    Ok(policy_spec(policy, model_profile, 256, None)?.record_name())
}

/// Runs the episodes `specs` (JSON, from `episode_specs`) with `policy` into the results file
/// `output` exactly as `vifo run` does (threads, resume, the cameras only for policies that
/// look, fast-forward, the look `vifo run` would find with `--assets`, `--robot-assets` and
/// `--builtin-look` as given: see `look`), cues facing as `cue_facing` says (`vifo run
/// --cue-facing`); returns `(ran, errors, already_done)`. `policy` is a name `vifo run --policy`
/// takes, or a Python callable (`callable::PyPolicy`; then `name` is required, and it runs on
/// one worker); `name` also names a server's records, as `--policy-name`. A Ctrl-C stops the run
/// after the episodes running, which are written.
#[pyfunction]
#[pyo3(signature = (specs, policy, output, set = "paper", threads = 1, resume = false, size = 256, quiet = true, assets = None, robot_assets = None, builtin_look = false, cue_facing = "upright", name = None, model_profile = None))]
#[allow(clippy::too_many_arguments)]
pub fn run_specs(
    py: Python<'_>,
    specs: Vec<String>,
    policy: &Bound<'_, PyAny>,
    output: PathBuf,
    set: &str,
    threads: usize,
    resume: bool,
    size: i64,
    quiet: bool,
    assets: Option<PathBuf>,
    robot_assets: Option<PathBuf>,
    builtin_look: bool,
    cue_facing: &str,
    name: Option<String>,
    model_profile: Option<&str>,
) -> PyResult<(usize, usize, usize)> {
    let size = crate::check_size(size)?;
    let driver = Driver::new(policy, name, model_profile, size)?;
    let cue_facing = crate::parse_cue_facing(cue_facing)?;
    let specs: Vec<EpisodeSpec> =
        specs.iter().map(|s| serde_json::from_str(s).map_err(|e| value_err(format!("episode spec: {e}")))).collect::<PyResult<_>>()?;
    // An edited spec would run, and its record would be refused by every report.
    for spec in &specs {
        check_spec(spec).map_err(value_err)?;
    }
    let render = driver.uses_images();
    // The look matters only where cameras draw (and is recorded only there), as in `vifo run`.
    if render {
        crate::look::use_look(py, assets, robot_assets, builtin_look, quiet)?;
    }
    let config = EnvConfig { size, cameras: if render { CameraName::ALL.to_vec() } else { Vec::new() }, cue_facing, ..EnvConfig::default() };
    let stop = Arc::new(AtomicBool::new(false));
    // The name the policy's records carry, which a resumed file must hold.
    let options = RunOptions {
        // The GIL serialises a Python policy's calls, and one object serves every episode; a
        // server that holds one client would mix two workers' episodes up.
        threads: if driver.one_worker() { 1 } else { threads },
        resume,
        quiet,
        policy: driver.name(),
        set: parse_set(set)?,
        stop: Some(stop.clone()),
        ..RunOptions::new(output)
    };
    if resume {
        // A record this benchmark does not write would be kept as done.
        read_checked(&options.output).map_err(run_err)?;
    }
    let raised = Arc::new(Mutex::new(None));
    let make = || -> Result<Box<dyn Policy>, String> {
        match &driver {
            Driver::Named(spec) => spec.connect().map_err(|e| e.to_string()),
            Driver::Python { callable, name } => {
                let callable = Python::attach(|py| callable.clone_ref(py));
                Ok(Box::new(PyPolicy::new(callable, name.clone(), raised.clone(), stop.clone())))
            }
        }
    };
    let summary = interruptible(py, &stop, || run_episodes(&specs, make, config, &RolloutOptions::default(), &options))?.map_err(run_err)?;
    // The policy's own exception, with its traceback, after its episode was written.
    if let Some(e) = raised.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(e);
    }
    Ok((summary.ran, summary.errors, summary.already_done))
}

/// What `run_specs` runs: a policy `vifo run --policy` names, or a Python callable.
enum Driver {
    Named(PolicySpec),
    Python { callable: Py<PyAny>, name: String },
}

impl Driver {
    fn new(policy: &Bound<'_, PyAny>, name: Option<String>, model_profile: Option<&str>, size: u32) -> PyResult<Driver> {
        if let Ok(policy) = policy.extract::<String>() {
            return Ok(Driver::Named(policy_spec(&policy, model_profile, size, name)?));
        }
        if model_profile.is_some() {
            return Err(PyValueError::new_err("model_profile= says how to talk to a policy server, not to a Python policy"));
        }
        if !policy.is_callable() {
            return Err(PyValueError::new_err(format!(
                "policy {}: expected a policy name, a server URL or a callable (obs, instruction) -> 7 numbers",
                policy.repr().map_or_else(|_| "?".to_string(), |r| r.to_string())
            )));
        }
        let name = name.ok_or_else(|| PyValueError::new_err("a Python policy needs name= (its records and report rows carry it)"))?;
        check_name(&name)?;
        Ok(Driver::Python { callable: policy.clone().unbind(), name })
    }

    fn uses_images(&self) -> bool {
        match self {
            Driver::Named(spec) => spec.uses_images(),
            Driver::Python { .. } => true,
        }
    }

    fn name(&self) -> String {
        match self {
            Driver::Named(spec) => spec.record_name(),
            Driver::Python { name, .. } => name.clone(),
        }
    }

    fn one_worker(&self) -> bool {
        match self {
            Driver::Named(spec) => spec.serves_one_client(),
            Driver::Python { .. } => true,
        }
    }
}

/// A results file opened as `vifo run` opens it (locked while open, checked, a cut last line
/// removed), to which a driver appends records that were made elsewhere.
#[pyclass(module = "libero_vifo._native")]
pub struct ResultsFile {
    open: Option<OpenResults>,
    set: SetName,
    path: PathBuf,
}

#[pymethods]
impl ResultsFile {
    #[new]
    #[pyo3(signature = (path, set = "paper", resume = false, policy = ""))]
    fn new(path: PathBuf, set: &str, resume: bool, policy: &str) -> PyResult<ResultsFile> {
        let set = parse_set(set)?;
        // With a policy name, a resumed file's completed records must be that policy's.
        let options = RunOptions { resume, set, policy: policy.to_string(), ..RunOptions::new(&path) };
        if resume {
            read_checked(&path).map_err(run_err)?;
        }
        let open = vifo_protocols::runner::open_results(&options).map_err(run_err)?;
        Ok(ResultsFile { open: Some(open), set, path })
    }

    /// Keys of the episodes that already have a completed record (skipped on resume).
    fn done(&self) -> PyResult<Vec<String>> {
        Ok(self.opened()?.done.iter().cloned().collect())
    }

    /// Appends one record (a line `run_specs` wrote); it must be of this file's instance set.
    fn write(&mut self, line: &str) -> PyResult<()> {
        let record: EpisodeRecord =
            serde_json::from_str(line).map_err(|e| value_err(format!("{}: not an episode record: {e}", self.path.display())))?;
        if record.set != self.set {
            return Err(PyValueError::new_err(format!("record of the {} set, this file holds the {} set", record.set, self.set)));
        }
        // A record reports and resumes would refuse would make the whole file unreadable.
        check_record(&record).map_err(|e| value_err(format!("{}: {e}", self.path.display())))?;
        let open = self.open.as_mut().ok_or_else(|| PyRuntimeError::new_err("the results file is closed"))?;
        open.writer.write(&record).map_err(run_err)
    }

    /// Releases the lock.
    fn close(&mut self) {
        self.open = None;
    }
}

impl ResultsFile {
    fn opened(&self) -> PyResult<&OpenResults> {
        self.open.as_ref().ok_or_else(|| PyRuntimeError::new_err("the results file is closed"))
    }
}

/// The keys of the records in a results file, in file order (repeats kept), and whether each
/// is completed: what a check for missing and duplicate episodes reads.
#[pyfunction]
pub fn record_keys(path: PathBuf) -> PyResult<Vec<(String, bool)>> {
    let loaded = read_records(&path).map_err(run_err)?;
    Ok(loaded.records.iter().map(|r| (r.spec.key(), !matches!(r.outcome, vifo_protocols::spec::Outcome::Error { .. }))).collect())
}

/// `vifo report`: Tables 1 and 2 of the results files into `out` (Markdown, CSV, JSON,
/// charts); returns the Markdown. Refuses records of different looks unless `mix_looks`.
#[pyfunction]
#[pyo3(signature = (paths, out, mix_looks = false))]
pub fn write_report(paths: Vec<PathBuf>, out: PathBuf, mix_looks: bool) -> PyResult<String> {
    let mut records = Vec::new();
    for path in &paths {
        // A missing file reads as empty where a run resumes; a report of one is a typo.
        if !path.exists() {
            return Err(PyValueError::new_err(format!("{}: no such results file", path.display())));
        }
        records.extend(read_checked(path).map_err(run_err)?.records);
    }
    // As `vifo report`: rows drawn with different looks are not comparable.
    report::check_looks(&report::looks_with_vqa(&records, std::iter::empty()), mix_looks, "mix_looks=True").map_err(PyValueError::new_err)?;
    // As `vifo report`: the extended studies' episodes stay out of Tables 1 and 2.
    let report = report::build(&studies::main_records(&records), &Default::default());
    report.write(&out).map_err(|e| PyRuntimeError::new_err(format!("{}: {e}", out.display())))
}
