//! What the project's scripted policy servers (`tests/python/*_server.py`) answer, computed
//! in-process, so a test can run the same episode over the wire and locally and compare the
//! final states bit for bit.

use std::collections::VecDeque;

use vifo_protocols::{Observation, Policy, PolicyError};

/// Row `i` of request `n` is `state8[..6] + 0.01 i` with gripper `gripper(n)`; the first
/// `replan` rows of each chunk are used, as the clients use them. Where a wire format carries
/// floats as float32, the state and the actions are rounded to float32 the same way.
pub struct SameAsServer {
    pub replan: usize,
    pub state32: bool,
    pub action32: bool,
    pub gripper: fn(usize) -> f64,
    queue: VecDeque<[f64; 7]>,
    requests: usize,
}

impl SameAsServer {
    pub fn new(replan: usize, state32: bool, action32: bool, gripper: fn(usize) -> f64) -> Self {
        SameAsServer { replan, state32, action32, gripper, queue: VecDeque::new(), requests: 0 }
    }

    /// The openpi test server: float64 throughout, gripper = requests answered so far.
    pub fn openpi(replan: usize) -> Self {
        SameAsServer::new(replan, false, false, |n| n as f64)
    }
}

impl Policy for SameAsServer {
    fn name(&self) -> String {
        "in-process".into()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.queue.clear();
        Ok(())
    }

    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError> {
        if self.queue.is_empty() {
            let f32r = |v: f64, on: bool| if on { f64::from(v as f32) } else { v };
            let state = obs.state8().map(|v| f32r(v, self.state32));
            for i in 0..self.replan {
                let mut a = [(self.gripper)(self.requests); 7];
                for j in 0..6 {
                    a[j] = f32r(state[j] + 0.01 * i as f64, self.action32);
                }
                self.queue.push_back(a);
            }
            self.requests += 1;
        }
        Ok(self.queue.pop_front().expect("filled above"))
    }
}
