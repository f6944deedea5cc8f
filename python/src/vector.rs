//! `NativeVectorEnv`: N episodes stepped in one call on Rust threads with the GIL released
//! (the core of `libero_vifo.gym.LiberoVifoVectorEnv`). Each env owns its episode, so the
//! bytes of an env's observations do not depend on the thread count.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use vifo_protocols::env::{Env, EnvConfig, EnvError};
use vifo_protocols::spec::EpisodeSpec;
use vifo_scenes::view::ImageOrder;

use crate::{check_size, episode_spec, exclusive, py_err, shared};

/// Most sub-envs in one vector env. Each holds its own simulator, renderer and images: at 256²
/// about 3–5 MB (docs/measurements.md, `vifo bench scaling`'s memory per worker) plus 0.4 MB
/// of stacked observations per step, so 1024 is some 5 GB, and one step of them takes seconds
/// of CPU even on many cores. More than that is several vector envs (processes, Ray workers);
/// a count far beyond it is a mistake, refused before anything is allocated.
pub const MAX_ENVS: usize = 1024;

/// One sub-env's episode: (suite, task index, condition, cue instance).
type Episode = (String, usize, String, Option<String>);

#[pyclass(module = "libero_vifo._native")]
pub struct NativeVectorEnv {
    envs: Vec<Env>,
    episodes: Vec<Episode>,
    threads: usize,
}

/// What one sub-env does in a call.
enum Job<'a> {
    Reset(&'a EpisodeSpec),
    Step(&'a [f64]),
    Keep,
}

/// A sub-env after a call.
#[derive(Default)]
struct Outcome {
    /// 1.0 once the scored task is done.
    reward: f64,
    /// Done by success.
    terminated: bool,
    /// The budget ran out, or the physics blew up (then `error` says why).
    truncated: bool,
    error: Option<String>,
    /// The language task's and the cue task's success, where the protocol has them.
    successes: (Option<bool>, Option<bool>),
}

#[pymethods]
impl NativeVectorEnv {
    /// `episodes`: one (suite, index, condition, cue) per sub-env; upright `size`² images, cues
    /// facing `cue_facing` (`upright` or `model`); `threads` worker threads (at most one per env).
    #[new]
    #[pyo3(signature = (episodes, size, threads, cue_facing = "upright"))]
    fn new(py: Python<'_>, episodes: Vec<Episode>, size: i64, threads: usize, cue_facing: &str) -> PyResult<NativeVectorEnv> {
        let size = check_size(size)?;
        let cue_facing = crate::parse_cue_facing(cue_facing)?;
        if !(1..=MAX_ENVS).contains(&episodes.len()) {
            return Err(PyValueError::new_err(format!("{} episodes: a vector env takes 1 to {MAX_ENVS}", episodes.len())));
        }
        if threads == 0 {
            return Err(PyValueError::new_err("threads: expected at least 1"));
        }
        for (suite, index, condition, cue) in &episodes {
            episode_spec(suite, *index, condition, cue.as_deref(), 0)?;
        }
        let config = EnvConfig { size, order: ImageOrder::Upright, cue_facing, ..EnvConfig::default() };
        crate::look::ensure(py)?;
        let envs = episodes.iter().map(|_| Env::new(config.clone())).collect();
        let threads = threads.min(episodes.len());
        Ok(NativeVectorEnv { envs, episodes, threads })
    }

    #[getter]
    fn num_envs(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(shared(slf)?.envs.len())
    }

    /// Each instruction (the protocol's).
    fn instructions(slf: &Bound<'_, Self>) -> PyResult<Vec<String>> {
        shared(slf)?.episodes.iter().map(|(s, i, c, q)| Ok(episode_spec(s, *i, c, q.as_deref(), 0)?.instruction)).collect()
    }

    /// Starts sub-env `k` from initial state `inits[k]` (settled, as `vifo run`) where it is
    /// not `None`; returns every sub-env's observation, stacked.
    fn reset<'py>(slf: &Bound<'py, Self>, inits: Vec<Option<usize>>) -> PyResult<Bound<'py, PyDict>> {
        let (py, mut this) = (slf.py(), exclusive(slf)?);
        let specs = this.specs(&inits)?;
        let jobs: Vec<Job> = specs.iter().map(|s| s.as_ref().map_or(Job::Keep, Job::Reset)).collect();
        this.run(py, jobs)?;
        stacked(py, &this.envs)
    }

    /// One call for all sub-envs: sub-env `k` is reset to `resets[k]` where that is given
    /// (reward 0, not done: gymnasium's next-step autoreset), else stepped with row `k` of
    /// `actions` (N×7). Every action is checked before any env moves. Returns the stacked
    /// observations and per env reward (1.0 once the scored task is done), terminated (done
    /// by success), truncated (the budget ran out, or the physics blew up) and the error of a
    /// sub-env whose physics blew up (its episode is over and keeps its last observation; the
    /// other sub-envs' steps stand), and each sub-env's (language, cue) success (`Env::successes`).
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        slf: &Bound<'py, Self>,
        actions: PyReadonlyArray2<'py, f64>,
        resets: Vec<Option<usize>>,
    ) -> PyResult<(Bound<'py, PyDict>, Vec<f64>, Vec<bool>, Vec<bool>, Vec<Option<String>>, Vec<(Option<bool>, Option<bool>)>)> {
        let (py, mut this) = (slf.py(), exclusive(slf)?);
        this.check_open()?;
        let n = this.envs.len();
        if actions.shape() != [n, 7] {
            return Err(PyValueError::new_err(format!("actions of shape {:?}: expected ({n}, 7)", actions.shape())));
        }
        // In logical (row-major) order whatever the memory layout: `as_slice` also takes a
        // Fortran-ordered array, whose memory order would hand env k another env's values.
        let actions: Vec<f64> = actions.as_array().iter().copied().collect();
        if let Some(i) = actions.iter().position(|v| !v.is_finite()) {
            return Err(PyValueError::new_err(format!("action of env {}: element {} is {}, not finite", i / 7, i % 7, actions[i])));
        }
        let specs = this.specs(&resets)?;
        let jobs: Vec<Job> =
            specs.iter().enumerate().map(|(k, s)| s.as_ref().map_or(Job::Step(&actions[k * 7..(k + 1) * 7]), Job::Reset)).collect();
        let outcomes = this.run(py, jobs)?;
        let obs = stacked(py, &this.envs)?;
        let rewards = outcomes.iter().map(|o| o.reward).collect();
        let terminated = outcomes.iter().map(|o| o.terminated).collect();
        let truncated = outcomes.iter().map(|o| o.truncated).collect();
        let successes = outcomes.iter().map(|o| o.successes).collect();
        Ok((obs, rewards, terminated, truncated, outcomes.into_iter().map(|o| o.error).collect(), successes))
    }

    /// For tests: throws the first movable object of sub-env `k` upwards at `speed` m/s, which
    /// the physics guard takes for a blow-up at the next step beyond its speed limit.
    fn _throw_object(&mut self, k: usize, speed: f64) -> PyResult<()> {
        let sim = self.envs.get_mut(k).and_then(|e| e.sim_mut()).ok_or_else(|| PyValueError::new_err(format!("env {k}: no episode")))?;
        let entity = sim.model().entities.iter().find(|e| e.movable()).ok_or_else(|| PyValueError::new_err("no movable object"))?;
        let body = entity.bodies[0];
        sim.world_mut().rapier_mut().bodies[body].set_linvel(vifo_physics::rapier::prelude::Vector::new(0.0, 0.0, speed), true);
        Ok(())
    }

    fn close(slf: &Bound<'_, Self>) -> PyResult<()> {
        exclusive(slf)?.envs.clear();
        Ok(())
    }
}

impl NativeVectorEnv {
    fn check_open(&self) -> PyResult<()> {
        if self.envs.is_empty() {
            return Err(pyo3::exceptions::PyRuntimeError::new_err("the vector env is closed"));
        }
        Ok(())
    }

    fn specs(&self, inits: &[Option<usize>]) -> PyResult<Vec<Option<EpisodeSpec>>> {
        self.check_open()?;
        if inits.len() != self.envs.len() {
            return Err(PyValueError::new_err(format!("{} initial states for {} envs", inits.len(), self.envs.len())));
        }
        inits
            .iter()
            .zip(&self.episodes)
            .map(|(init, (s, i, c, q))| init.map(|init| episode_spec(s, *i, c, q.as_deref(), init)).transpose())
            .collect()
    }

    /// Runs the jobs on the worker threads, the GIL released; the first error names its env.
    fn run(&mut self, py: Python<'_>, jobs: Vec<Job>) -> PyResult<Vec<Outcome>> {
        let threads = self.threads;
        let envs = &mut self.envs;
        let results: Vec<Result<Outcome, EnvError>> = py.detach(|| {
            let mut work: Vec<(&mut Env, Job)> = envs.iter_mut().zip(jobs).collect();
            let per_thread = work.len().div_ceil(threads);
            if threads == 1 {
                return work.iter_mut().map(|(env, job)| apply(env, job)).collect();
            }
            std::thread::scope(|scope| {
                let handles: Vec<_> = work
                    .chunks_mut(per_thread)
                    .map(|chunk| scope.spawn(move || chunk.iter_mut().map(|(env, job)| apply(env, job)).collect::<Vec<_>>()))
                    .collect();
                handles.into_iter().flat_map(|h| h.join().expect("a vector env worker panicked")).collect()
            })
        });
        results.into_iter().enumerate().map(|(k, r)| r.map_err(|e| with_env(k, py_err(e), py))).collect()
    }
}

fn apply(env: &mut Env, job: &Job) -> Result<Outcome, EnvError> {
    match job {
        Job::Reset(spec) => env.reset(spec).map(|_| Outcome::default()),
        Job::Step(action) => match env.step(action) {
            Ok(step) => {
                let done = step.done;
                let success = env.scored_success();
                let successes = env.successes();
                Ok(Outcome { reward: if success { 1.0 } else { 0.0 }, terminated: success, truncated: done && !success, error: None, successes })
            }
            // This sub-env's episode is over (nothing was scored or rendered from the broken
            // state); the others' steps stand, and autoreset restarts this one.
            Err(e @ EnvError::Physics { .. }) => Ok(Outcome { truncated: true, error: Some(e.to_string()), ..Outcome::default() }),
            Err(e) => Err(e),
        },
        Job::Keep => Ok(Outcome::default()),
    }
}

/// The error of sub-env `k`, its message prefixed with `env k: `.
fn with_env(k: usize, err: PyErr, py: Python<'_>) -> PyErr {
    let message = format!("env {k}: {}", err.value(py));
    if err.is_instance_of::<PyValueError>(py) {
        PyValueError::new_err(message)
    } else {
        pyo3::exceptions::PyRuntimeError::new_err(message)
    }
}

/// The observations of every env stacked along a first axis of length N.
fn stacked<'py>(py: Python<'py>, envs: &[Env]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = envs.len();
    let images = |f: fn(&vifo_protocols::Observation) -> &vifo_cues::RgbImage| -> PyResult<Bound<'py, PyAny>> {
        let first = f(envs[0].observation());
        let shape = [n, first.height as usize, first.width as usize, 3];
        let data: Vec<u8> = envs.iter().flat_map(|e| f(e.observation()).data.iter().copied()).collect();
        if data.len() != shape.iter().product::<usize>() {
            return Err(pyo3::exceptions::PyRuntimeError::new_err("an env has not been reset"));
        }
        Ok(PyArray1::from_vec(py, data).reshape(shape)?.into_any())
    };
    d.set_item("agentview_image", images(|o| &o.agentview)?)?;
    d.set_item("robot0_eye_in_hand_image", images(|o| &o.wrist)?)?;
    let vectors = |len: usize, f: &dyn Fn(&vifo_protocols::Observation) -> Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        let data: Vec<f64> = envs.iter().flat_map(|e| f(e.observation())).collect();
        Ok(PyArray1::from_vec(py, data).reshape([n, len])?.into_any())
    };
    d.set_item("robot0_eef_pos", vectors(3, &|o| o.eef_pos.to_vec())?)?;
    d.set_item("robot0_eef_quat", vectors(4, &|o| o.eef_quat_xyzw.to_vec())?)?;
    d.set_item("robot0_gripper_qpos", vectors(2, &|o| o.gripper_qpos.to_vec())?)?;
    d.set_item("robot0_joint_pos", vectors(7, &|o| o.joint_pos.to_vec())?)?;
    d.set_item("robot0_joint_pos_cos", vectors(7, &|o| o.joint_pos.map(f64::cos).to_vec())?)?;
    d.set_item("robot0_joint_pos_sin", vectors(7, &|o| o.joint_pos.map(f64::sin).to_vec())?)?;
    Ok(d)
}
