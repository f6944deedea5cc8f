//! A Python callable as a [`Policy`], and runs from Python that a Ctrl-C stops.
//!
//! A user's own model (a PyTorch checkpoint, a scripted baseline) is a function of the
//! observation; [`run_specs`](crate::run::run_specs) runs it through the same runner, records
//! and report as `vifo run`, without a policy server.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use vifo_protocols::policy::PolicyError;
use vifo_protocols::{Observation, Policy};
use vifo_scenes::view::CameraName;

/// `callable(obs, instruction)` → 7 numbers, where `obs` is the gym env's observation (upright
/// `agentview_image` and `robot0_eye_in_hand_image`, the robot's vectors) and `instruction`
/// the protocol's; its `reset()`, where it has one, starts each episode. The first exception
/// or malformed action stops the run: it is kept in `raised` and the run's `stop` is set (the
/// episode is recorded as an error, which a resumed run retries).
pub struct PyPolicy {
    callable: Py<PyAny>,
    name: String,
    raised: Arc<Mutex<Option<PyErr>>>,
    stop: Arc<AtomicBool>,
}

impl PyPolicy {
    pub fn new(callable: Py<PyAny>, name: String, raised: Arc<Mutex<Option<PyErr>>>, stop: Arc<AtomicBool>) -> PyPolicy {
        PyPolicy { callable, name, raised, stop }
    }

    /// Keeps the first error of the run, stops it, and gives the episode its message.
    fn failed(&self, py: Python<'_>, e: PyErr, what: &str) -> PolicyError {
        let message = format!("Python policy {what}: {}", e.value(py));
        self.stop.store(true, Ordering::Relaxed);
        self.raised.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
        PolicyError::Other(message)
    }
}

impl Policy for PyPolicy {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        Python::attach(|py| {
            let c = self.callable.bind(py);
            let result = c.hasattr("reset").and_then(|has| if has { c.call_method0("reset").map(drop) } else { Ok(()) });
            result.map_err(|e| self.failed(py, e, "reset()"))
        })
    }

    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError> {
        // Stopped (a Ctrl-C, or another episode's error): the running episode ends now.
        if self.stop.load(Ordering::Relaxed) {
            return Err(PolicyError::Other("the run was stopped".to_string()));
        }
        Python::attach(|py| {
            let action = (|| -> PyResult<[f64; 7]> {
                let d = crate::robot_observation(py, obs, &CameraName::ALL)?;
                let out = self.callable.bind(py).call1((d, obs.instruction.as_str()))?;
                let v: Vec<f64> = out.extract().map_err(|e| PyValueError::new_err(format!("returned no sequence of numbers ({e})")))?;
                let action: [f64; 7] =
                    v.as_slice().try_into().map_err(|_| PyValueError::new_err(format!("returned {} numbers, expected 7", v.len())))?;
                if let Some(i) = action.iter().position(|x| !x.is_finite()) {
                    return Err(PyValueError::new_err(format!("returned {} at element {i}, not a finite number", action[i])));
                }
                Ok(action)
            })();
            action.map_err(|e| self.failed(py, e, &format!("at step {}", obs.step)))
        })
    }
}

/// Runs `work` on a thread of its own with the GIL released, looking for a Ctrl-C every 50 ms:
/// Python runs signal handlers only on its main thread, which would otherwise wait in Rust
/// until the whole run ended. On one, `stop` is set, the episodes running finish and are
/// written, and the `KeyboardInterrupt` is raised.
pub fn interruptible<T: Send>(py: Python<'_>, stop: &AtomicBool, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    std::thread::scope(|scope| {
        let handle = scope.spawn(work);
        let mut interrupted = None;
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(Duration::from_millis(50)));
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::Relaxed);
                interrupted = Some(e);
            }
        }
        let out = py.detach(|| handle.join()).map_err(|_| PyRuntimeError::new_err("the run's thread panicked"))?;
        interrupted.map_or(Ok(out), Err)
    })
}
