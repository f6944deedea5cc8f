//! `libero_vifo._native`: the Rust environment ([`vifo_protocols::env::Env`]) as a Python
//! class, observations as numpy arrays in LIBERO's keys, shapes, dtypes and row order. The
//! LIBERO-compatible names (`benchmark`, `OffScreenRenderEnv`) are thin Python over this
//! (`pysrc/libero_vifo/libero`).
//!
//! The GIL is released while physics and rendering run, so Python threads step envs in
//! parallel. `vector`: N envs stepped on Rust threads in one call; `run`: benchmark runs
//! into `vifo run`'s results files (the Ray runner's native half).

mod callable;
mod look;
mod run;
mod vector;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vifo_cues::SetName;
use vifo_protocols::benchmark::{BenchmarkError, instances, specs};
use vifo_protocols::env::{CueFacing, Env, EnvConfig, EnvError};
use vifo_protocols::spec::{EpisodeSpec, Protocol, TaskRef};
use vifo_protocols::Observation;
use vifo_scenes::sim::Sim;
use vifo_scenes::view::{CameraName, ImageOrder};

/// Largest camera side accepted (a 4096² frame is 48 MiB per camera).
const MAX_SIZE: u32 = 4096;

/// Bad arguments are `ValueError`; using an env in the wrong state (closed, not started,
/// finished) and simulator faults are `RuntimeError`.
fn py_err(e: EnvError) -> PyErr {
    match e {
        EnvError::Action(_) | EnvError::Benchmark(_) | EnvError::NoInitState { .. } | EnvError::Instruction { .. } => {
            PyValueError::new_err(e.to_string())
        }
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

/// The protocol called `condition` (`original`, `authorized`, `conflict`, `no_language`),
/// given as the argument called `arg`.
fn protocol(condition: &str, arg: &str) -> PyResult<Protocol> {
    Protocol::ALL.into_iter().find(|p| p.name() == condition).ok_or_else(|| {
        PyValueError::new_err(format!("{arg} {condition:?}: expected one of original, authorized, conflict, no_language"))
    })
}

/// The episode of task `suite`/`index` from initial state `init` under `condition` with cue
/// instance `cue` (required by every condition but `original`, refused by it).
fn episode_spec(suite: &str, index: usize, condition: &str, cue: Option<&str>, init: usize) -> PyResult<EpisodeSpec> {
    let task = TaskRef { suite: suite.to_string(), index };
    let protocol = protocol(condition, "language_condition")?;
    if let (Protocol::Original, Some(id)) = (protocol, cue) {
        return Err(PyValueError::new_err(format!(
            "cue {id:?} with language_condition original: the original protocol shows no cue (use authorized, conflict or no_language)"
        )));
    }
    let spec = specs::spec(&task, protocol, cue, init, 0).map_err(|e| match e {
        BenchmarkError::UnknownInstance { .. } => PyValueError::new_err(format!("{e}; from Python, libero_vifo.cue_instances() lists the ids")),
        e => PyValueError::new_err(e.to_string()),
    })?;
    if init != spec.init {
        return Err(PyValueError::new_err(format!("initial state {init}: task {task} has 50 (0 to 49)")));
    }
    Ok(spec)
}

/// One environment of one built-in task, started unsettled as LIBERO's `set_init_state`
/// (the caller runs LIBERO's 10 dummy steps), images bottom-up as robosuite returns them.
#[pyclass(module = "libero_vifo._native")]
struct NativeEnv {
    /// `None` once closed.
    env: Option<Env>,
    task: TaskRef,
    condition: String,
    cue: Option<String>,
    /// The protocol's instruction (LIBERO's `language_instruction`).
    #[pyo3(get)]
    instruction: String,
}

impl NativeEnv {
    fn env(&mut self) -> PyResult<&mut Env> {
        self.env.as_mut().ok_or_else(|| PyRuntimeError::new_err("the env is closed"))
    }
}

/// `slf` for a call that changes it. The GIL is released while an env steps, so another
/// Python thread can call the same object meanwhile; PyO3's own refusal says only "Already
/// borrowed", this says what was wrong.
pub(crate) fn exclusive<'py, T: pyo3::PyClass<Frozen = pyo3::pyclass::boolean_struct::False>>(slf: &Bound<'py, T>) -> PyResult<PyRefMut<'py, T>> {
    slf.try_borrow_mut().map_err(|_| in_use(slf))
}

/// `slf` for a call that only reads it (refused while another thread's call changes it).
pub(crate) fn shared<'py, T: pyo3::PyClass>(slf: &Bound<'py, T>) -> PyResult<PyRef<'py, T>> {
    slf.try_borrow().map_err(|_| in_use(slf))
}

fn in_use<T: pyo3::PyClass>(slf: &Bound<'_, T>) -> PyErr {
    let name = slf.as_any().get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "env".to_string());
    PyRuntimeError::new_err(format!(
        "this {name} is in use by another thread's call: an env is used from one thread at a time (make one env per thread, or step many in one call with the vector env)"
    ))
}

#[pymethods]
impl NativeEnv {
    /// An env for task `index` of `suite` with `size`² cameras (`cameras`, LIBERO's names; both
    /// when `None`, none when empty), under protocol `condition` with cue instance `cue`, drawn
    /// facing `cue_facing` (`upright`, or `model`: readable after LIBERO's 180° rotation).
    #[new]
    #[pyo3(signature = (suite, index, size, condition = "original", cue = None, cameras = None, cue_facing = "upright"))]
    #[allow(clippy::too_many_arguments)]
    fn new(py: Python<'_>, suite: &str, index: usize, size: i64, condition: &str, cue: Option<String>, cameras: Option<Vec<String>>, cue_facing: &str) -> PyResult<NativeEnv> {
        let size = check_size(size)?;
        let cue_facing = parse_cue_facing(cue_facing)?;
        let spec = episode_spec(suite, index, condition, cue.as_deref(), 0)?;
        let cameras = match cameras {
            None => CameraName::ALL.to_vec(),
            Some(names) => camera_list(&names)?,
        };
        let env = look::env(py, EnvConfig { size, order: ImageOrder::BottomUp, cameras, cue_facing })?;
        Ok(NativeEnv { env: Some(env), task: spec.task, condition: condition.to_string(), cue, instruction: spec.instruction })
    }

    /// Loads initial state `init` (0..50) without settling; returns the observation.
    fn reset<'py>(slf: &Bound<'py, Self>, init: usize) -> PyResult<Bound<'py, PyDict>> {
        let (py, mut this) = (slf.py(), exclusive(slf)?);
        let spec = episode_spec(&this.task.suite, this.task.index, &this.condition, this.cue.as_deref(), init)?;
        let env = this.env()?;
        py.detach(|| env.reset_unsettled(&spec).map(|_| ())).map_err(py_err)?;
        observation(py, env)
    }

    /// One control step: `(obs, reward, done)`; reward 1.0 when the task is done, as LIBERO's
    /// sparse reward.
    fn step<'py>(slf: &Bound<'py, Self>, action: Vec<f64>) -> PyResult<(Bound<'py, PyDict>, f64, bool)> {
        let (py, mut this) = (slf.py(), exclusive(slf)?);
        let env = this.env()?;
        let done = py.detach(|| env.step(&action).map(|r| r.done)).map_err(py_err)?;
        let reward = if env.scored_success() { 1.0 } else { 0.0 };
        Ok((observation(py, env)?, reward, done))
    }

    /// Whether the task's goal holds as of the last step; before the first reset an error, as
    /// `step` (there is no episode to check).
    fn check_success(slf: &Bound<'_, Self>) -> PyResult<bool> {
        let mut this = exclusive(slf)?;
        let env = this.env()?;
        env.state().map_err(py_err)?;
        Ok(env.scored_success())
    }

    /// `(language task done, cue task done)` as of the last step, `None` where the protocol
    /// has no such task: under conflict `check_success` is either, these tell LFR from UVF.
    fn successes(slf: &Bound<'_, Self>) -> PyResult<(Option<bool>, Option<bool>)> {
        let mut this = exclusive(slf)?;
        let env = this.env()?;
        env.state().map_err(py_err)?;
        Ok(env.successes())
    }

    /// The positions of the state: arm joints (7), fingers (2), then per movable object its
    /// position (3) and quaternion (4, x y z w). Not LIBERO's MuJoCo layout.
    fn sim_state<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (py, mut this) = (slf.py(), exclusive(slf)?);
        let env = this.env()?;
        let state = env.state().map_err(py_err)?;
        let obs = env.observation();
        let mut out: Vec<f64> = obs.joint_pos.iter().chain(&obs.gripper_qpos).copied().collect();
        for (_, pos, quat) in objects(state.sim) {
            out.extend(pos.iter().chain(&quat));
        }
        Ok(PyArray1::from_vec(py, out))
    }

    fn close(slf: &Bound<'_, Self>) -> PyResult<()> {
        exclusive(slf)?.env = None;
        Ok(())
    }

    #[getter]
    fn closed(slf: &Bound<'_, Self>) -> PyResult<bool> {
        Ok(shared(slf)?.env.is_none())
    }
}

/// The cameras named (LIBERO's `camera_names`), each once, in the order given.
fn camera_list(names: &[String]) -> PyResult<Vec<CameraName>> {
    let mut cameras = Vec::new();
    for name in names {
        let camera: CameraName = name.parse().map_err(|e| PyValueError::new_err(format!("camera_names: {e}")))?;
        if !cameras.contains(&camera) {
            cameras.push(camera);
        }
    }
    Ok(cameras)
}

/// `cue_facing` as `vifo run --cue-facing` takes it.
fn parse_cue_facing(name: &str) -> PyResult<CueFacing> {
    match name {
        "upright" => Ok(CueFacing::Upright),
        "model" => Ok(CueFacing::Model),
        other => Err(PyValueError::new_err(format!("cue_facing {other:?}: expected 'upright' or 'model'"))),
    }
}

/// The camera side `size` (taken signed, so that a negative one is this `ValueError` too).
#[pyfunction]
fn check_size(size: i64) -> PyResult<u32> {
    u32::try_from(size).ok().filter(|s| (1..=MAX_SIZE).contains(s)).ok_or_else(|| {
        PyValueError::new_err(format!("camera size {size}: expected 1 to {MAX_SIZE} pixels"))
    })
}

/// Movable objects: name, position, quaternion (x, y, z, w).
fn objects(sim: &Sim) -> Vec<(String, [f64; 3], [f64; 4])> {
    let model = sim.model();
    model
        .entities
        .iter()
        .enumerate()
        .filter(|(_, e)| e.movable())
        .map(|(i, e)| {
            let pose = sim.entity_pose(i);
            let [w, x, y, z] = pose.quat_wxyz();
            (e.name.clone(), [pose.pos.x, pose.pos.y, pose.pos.z], [x, y, z, w])
        })
        .collect()
}

/// LIBERO's observation dict of the env's latest observation: `<camera>_image` for each
/// camera the env draws, then the robot's and the objects' vectors.
fn observation<'py>(py: Python<'py>, env: &Env) -> PyResult<Bound<'py, PyDict>> {
    let d = robot_observation(py, env.observation(), &env.config().cameras)?;
    let f = |v: &[f64]| PyArray1::from_slice(py, v);
    let state = env.state().map_err(py_err)?;
    let (arm, fingers) = state.sim.model().robot.joint_velocities(state.sim.world());
    d.set_item("robot0_joint_vel", f(&arm))?;
    d.set_item("robot0_gripper_qvel", f(&fingers))?;
    for (name, pos, quat) in objects(state.sim) {
        d.set_item(format!("{name}_pos"), f(&pos))?;
        d.set_item(format!("{name}_quat"), f(&quat))?;
    }
    Ok(d)
}

/// What a policy is given of `obs`: `<camera>_image` for each of `cameras`, then the robot's
/// vectors (LIBERO's keys).
fn robot_observation<'py>(py: Python<'py>, obs: &Observation, cameras: &[CameraName]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for &camera in cameras {
        let image = obs.image(camera);
        let shape = [image.height as usize, image.width as usize, 3];
        d.set_item(format!("{camera}_image"), PyArray1::from_slice(py, &image.data).reshape(shape)?)?;
    }
    let f = |v: &[f64]| PyArray1::from_slice(py, v);
    d.set_item("robot0_eef_pos", f(&obs.eef_pos))?;
    d.set_item("robot0_eef_quat", f(&obs.eef_quat_xyzw))?;
    d.set_item("robot0_gripper_qpos", f(&obs.gripper_qpos))?;
    d.set_item("robot0_joint_pos", f(&obs.joint_pos))?;
    d.set_item("robot0_joint_pos_cos", f(&obs.joint_pos.map(f64::cos)))?;
    d.set_item("robot0_joint_pos_sin", f(&obs.joint_pos.map(f64::sin)))?;
    Ok(d)
}

/// The 40 built-in tasks as dicts: suite, index, name (BDDL stem), language (the instruction
/// evaluations feed the policy), max_steps (the suite's policy budget), init_states.
#[pyfunction]
fn tasks(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    let mut out = Vec::new();
    for suite in vifo_scenes::suite_names() {
        let s = vifo_scenes::suite(suite).expect("built-in suite");
        for (index, task) in s.tasks.iter().enumerate() {
            let d = PyDict::new(py);
            d.set_item("suite", suite)?;
            d.set_item("index", index)?;
            d.set_item("name", &task.name)?;
            d.set_item("language", &task.instruction)?;
            d.set_item("max_steps", s.max_steps)?;
            // From the initial states alone: building the scene would fix the process's look.
            let count = vifo_scenes::init_states::fixed(task).map_err(|e| PyRuntimeError::new_err(format!("task {}: {e}", task.name)))?.len();
            d.set_item("init_states", count)?;
            out.push(d);
        }
    }
    Ok(out)
}

/// The cue instance ids of the built-in tasks in instance set `set` (`paper`, the paper's
/// 1,347, or `full`), in suite, task and catalogue order.
#[pyfunction]
#[pyo3(signature = (set = "paper"))]
fn cue_instances(set: &str) -> PyResult<Vec<String>> {
    let set: SetName = set.parse().map_err(|e: String| PyValueError::new_err(e))?;
    Ok(instances::all(set).iter().map(|c| c.id()).collect())
}

/// The same episode through the Rust API as `vifo` runs it (reset with the settle steps, then
/// `actions`), for comparison with a Python loop: `[(obs, reward, done), ...]`, the reset's
/// observation first. `upright` renders row 0 at the top instead of robosuite's order;
/// `condition` and `cue` as `NativeEnv`'s.
#[pyfunction]
#[pyo3(signature = (suite, index, init, size, actions, upright = false, condition = "original", cue = None))]
#[allow(clippy::too_many_arguments)]
fn reference_episode<'py>(
    py: Python<'py>,
    suite: &str,
    index: usize,
    init: usize,
    size: i64,
    actions: Vec<Vec<f64>>,
    upright: bool,
    condition: &str,
    cue: Option<&str>,
) -> PyResult<Vec<(Bound<'py, PyDict>, f64, bool)>> {
    let size = check_size(size)?;
    let spec = episode_spec(suite, index, condition, cue, init)?;
    let order = if upright { ImageOrder::Upright } else { ImageOrder::BottomUp };
    let mut env = look::env(py, EnvConfig { size, order, ..EnvConfig::default() })?;
    py.detach(|| env.reset(&spec).map(|_| ())).map_err(py_err)?;
    let mut out = vec![(observation(py, &env)?, 0.0, false)];
    for action in &actions {
        let done = py.detach(|| env.step(action).map(|r| r.done)).map_err(py_err)?;
        let reward = if env.scored_success() { 1.0 } else { 0.0 };
        out.push((observation(py, &env)?, reward, done));
    }
    Ok(out)
}

/// Native steps per second of `steps` steps of `action` with two `size`² cameras, the GIL
/// released (the Python-overhead baseline of `bench.py`).
#[pyfunction]
fn native_steps_per_second(py: Python<'_>, suite: &str, index: usize, size: i64, steps: usize, action: Vec<f64>) -> PyResult<f64> {
    let size = check_size(size)?;
    let task = TaskRef { suite: suite.to_string(), index };
    let spec = specs::spec(&task, Protocol::Original, None, 0, 0).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut env = look::env(py, EnvConfig { size, order: ImageOrder::BottomUp, ..EnvConfig::default() })?;
    py.detach(|| {
        env.reset_unsettled(&spec)?;
        let start = std::time::Instant::now();
        for _ in 0..steps {
            env.step(&action)?;
        }
        Ok(steps as f64 / start.elapsed().as_secs_f64())
    })
    .map_err(py_err)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeEnv>()?;
    m.add_class::<vector::NativeVectorEnv>()?;
    m.add("MAX_ENVS", vector::MAX_ENVS)?;
    m.add_class::<run::ResultsFile>()?;
    m.add_function(wrap_pyfunction!(run::episode_specs, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_specs, m)?)?;
    m.add_function(wrap_pyfunction!(run::check_policy, m)?)?;
    m.add_function(wrap_pyfunction!(run::policy_name, m)?)?;
    m.add_function(wrap_pyfunction!(run::results_file_name, m)?)?;
    m.add_function(wrap_pyfunction!(run::record_keys, m)?)?;
    m.add_function(wrap_pyfunction!(run::write_report, m)?)?;
    m.add_function(wrap_pyfunction!(tasks, m)?)?;
    m.add_function(wrap_pyfunction!(check_size, m)?)?;
    m.add_function(wrap_pyfunction!(cue_instances, m)?)?;
    m.add_function(wrap_pyfunction!(reference_episode, m)?)?;
    m.add_function(wrap_pyfunction!(native_steps_per_second, m)?)?;
    m.add_function(wrap_pyfunction!(look::use_look, m)?)?;
    m.add_function(wrap_pyfunction!(look::look_info, m)?)?;
    Ok(())
}
