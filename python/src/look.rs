//! The look the wheel draws with, chosen once per process as `vifo` chooses it: LIBERO's asset
//! files where discovery finds them (`assets=`, `VIFO_LIBERO_ASSETS`, then the packages of the
//! interpreter the wheel runs in), the built-in look otherwise. `use_look` chooses it; the first
//! env that renders chooses the default. The choice is said once on stderr.

use std::ffi::{OsStr, OsString};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use vifo_protocols::env::{Env, EnvConfig, scenes};
use vifo_scenes::look::{self, Look};

/// What chose the look: `assets=`, `robot_assets=`, `builtin=`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LookKey {
    pub assets: Option<PathBuf>,
    pub robot_assets: Option<PathBuf>,
    pub builtin: bool,
}

/// The look of this process, once chosen.
struct Chosen {
    key: LookKey,
    label: String,
    /// `look_info()`'s answer, as JSON.
    info: String,
}

static CHOSEN: Mutex<Option<Chosen>> = Mutex::new(None);

/// Chooses the look for `key` (loading LIBERO's files: seconds, once) unless this process
/// already has one; asking again for the same look is fine, for another one an error. Returns the
/// look's label (`built-in` or `libero-assets:<hash>`). The GIL stays held while the lock is,
/// and no Python runs under the lock (a write to `sys.stderr` may let another thread take the
/// GIL, which then waits for the lock), so two threads cannot both load nor block each other.
pub fn choose(py: Python<'_>, key: LookKey, quiet: bool) -> PyResult<String> {
    let python = interpreter(py)?;
    let (label, lines) = choose_locked(key, &python)?;
    if !quiet && !lines.is_empty() {
        // A missing or closed stderr (`pythonw`) does not fail the env.
        if let Ok(stderr) = py.import("sys").and_then(|sys| sys.getattr("stderr")) {
            for line in lines {
                let _ = stderr.call_method1("write", (format!("libero_vifo look: {line}\n"),));
            }
        }
    }
    Ok(label)
}

/// [`choose`] under the lock: the label, and the lines to say (none when already chosen).
fn choose_locked(key: LookKey, python: &OsStr) -> PyResult<(String, Vec<String>)> {
    let mut chosen = CHOSEN.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(c) = chosen.as_ref() {
        // The same request, or builtin=True where the default search found no asset files.
        if c.key == key || (key.builtin && c.label == look::BUILT_IN) {
            return Ok((c.label.clone(), Vec::new()));
        }
        return Err(PyRuntimeError::new_err(format!(
            "this process already draws with look {} ({}); the look is chosen once per process, before its first env (start a new process for another)",
            c.label,
            describe(&c.key)
        )));
    }
    let (look, info) = if key.builtin {
        (None, serde_json::json!({ "look": look::BUILT_IN, "chosen": describe(&key) }))
    } else {
        let roots = look::discover_with(key.assets.as_deref(), key.robot_assets.as_deref(), python)
            .map_err(|e| PyValueError::new_err(format!("{}={}: {}", e.flag.trim_start_matches("--").replace('-', "_"), e.path.display(), e.problem)))?;
        let look = Look::load(roots);
        let info = serde_json::json!({
            "look": look.label(),
            "chosen": describe(&key),
            "roots": look.roots(),
            "categories": look.report(),
            "cache": look.cache(),
        });
        (Some(look), info)
    };
    let lines = match &look {
        Some(l) => l.announcement("libero_vifo.look_info()"),
        None => vec![format!("{} (builtin=True)", look::BUILT_IN)],
    };
    let look = look.filter(Look::is_used).map(Arc::new);
    let label = look.as_deref().map_or_else(|| look::BUILT_IN.to_string(), Look::label);
    scenes::use_look(look).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    *chosen = Some(Chosen { key, label: label.clone(), info: info.to_string() });
    Ok((label, lines))
}

/// A rendering env: the process's look chosen first (the default unless `use_look` chose one).
pub fn env(py: Python<'_>, config: EnvConfig) -> PyResult<Env> {
    ensure(py)?;
    Ok(Env::new(config))
}

/// Chooses the default look unless this process already has one.
pub fn ensure(py: Python<'_>) -> PyResult<String> {
    if let Some(c) = CHOSEN.lock().unwrap_or_else(|e| e.into_inner()).as_ref() {
        return Ok(c.label.clone());
    }
    choose(py, LookKey::default(), false)
}

/// How `key` chose: what the user passed, or the default search.
fn describe(key: &LookKey) -> String {
    if key.builtin {
        return "builtin=True".into();
    }
    let given: Vec<String> = [("assets", &key.assets), ("robot_assets", &key.robot_assets)]
        .into_iter()
        .filter_map(|(name, p)| p.as_ref().map(|p| format!("{name}={}", p.display())))
        .collect();
    if given.is_empty() { format!("the default search: {}, then this interpreter's packages", look::ENV_VAR) } else { given.join(", ") }
}

/// The interpreter this wheel runs in, asked for its installed asset packages.
fn interpreter(py: Python<'_>) -> PyResult<OsString> {
    let exe: Option<PathBuf> = py.import("sys")?.getattr("executable")?.extract()?;
    Ok(exe.filter(|p| !p.as_os_str().is_empty()).map_or_else(|| "python3".into(), PathBuf::into_os_string))
}

/// `libero_vifo.use_look`: chooses this process's look; returns its label.
#[pyfunction]
#[pyo3(signature = (assets = None, robot_assets = None, builtin = false, quiet = false))]
pub fn use_look(py: Python<'_>, assets: Option<PathBuf>, robot_assets: Option<PathBuf>, builtin: bool, quiet: bool) -> PyResult<String> {
    if builtin && (assets.is_some() || robot_assets.is_some()) {
        return Err(PyValueError::new_err("builtin=True draws no asset files: give it without assets= and robot_assets="));
    }
    choose(py, LookKey { assets, robot_assets, builtin }, quiet)
}

/// `libero_vifo.look_info`: the look of this process (chosen by default if not yet) as JSON.
#[pyfunction]
pub fn look_info(py: Python<'_>) -> PyResult<String> {
    ensure(py)?;
    let chosen = CHOSEN.lock().unwrap_or_else(|e| e.into_inner());
    Ok(chosen.as_ref().map_or_else(String::new, |c| c.info.clone()))
}
