//! robosuite's `PandaGripper` command path: a hidden per-substep ramp driving two position
//! servos with clipped force.

use serde::{Deserialize, Serialize};

/// Servo gain of each finger's position actuator (N/m); robosuite has no velocity term.
pub const FINGER_KP: f64 = 1000.0;
/// Force limit of each finger actuator (N).
pub const FINGER_FORCE_LIMIT: f64 = 20.0;
/// Ramp increment per physics substep (robosuite `PandaGripper.speed`).
pub const RAMP_PER_SUBSTEP: f64 = 0.01;
/// Control ranges of the two finger actuators (m).
pub const CTRL_RANGE: [[f64; 2]; 2] = [[0.0, 0.04], [-0.04, 0.0]];

/// The gripper's hidden command state (`gripper.current_action`): not part of the physics state,
/// so it travels with every snapshot. `[1, -1]` is fully open, `[-1, 1]` fully closed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GripperRamp {
    pub current: [f64; 2],
}

impl GripperRamp {
    /// One substep of `format_action`: moves the ramp by ±0.01 toward `sign(command)`
    /// (−1 opens, +1 closes) and returns the two actuators' position targets.
    pub fn step(&mut self, command: f64) -> [f64; 2] {
        let s = if command > 0.0 {
            1.0
        } else if command < 0.0 {
            -1.0
        } else {
            0.0
        };
        let delta = [-RAMP_PER_SUBSTEP * s, RAMP_PER_SUBSTEP * s];
        for (c, d) in self.current.iter_mut().zip(delta) {
            *c = (*c + d).clamp(-1.0, 1.0);
        }
        self.targets()
    }

    /// Position targets for the current ramp value: `mid + half_range · current`.
    pub fn targets(&self) -> [f64; 2] {
        [0, 1].map(|k| {
            let [lo, hi] = CTRL_RANGE[k];
            0.5 * (lo + hi) + 0.5 * (hi - lo) * self.current[k]
        })
    }
}

/// The finger actuator forces for targets `ctrl` at finger positions `q`.
pub fn finger_forces(ctrl: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [0, 1].map(|k| (FINGER_KP * (ctrl[k] - q[k])).clamp(-FINGER_FORCE_LIMIT, FINGER_FORCE_LIMIT))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_swing_takes_eight_control_steps() {
        let mut ramp = GripperRamp::default();
        assert_eq!(ramp.targets(), [0.02, -0.02]);
        for _ in 0..25 * 4 {
            ramp.step(-1.0);
        }
        assert!((ramp.current[0] - 1.0).abs() < 1e-12 && (ramp.current[1] + 1.0).abs() < 1e-12);
        let mut steps = 0;
        while ramp.current != [-1.0, 1.0] {
            for _ in 0..25 {
                ramp.step(1.0);
            }
            steps += 1;
        }
        assert_eq!(steps, 8);
        assert_eq!(ramp.targets(), [0.0, 0.0]);
        ramp.step(0.0);
        assert_eq!(ramp.targets(), [0.0, 0.0]);
    }

    #[test]
    fn forces_are_clipped() {
        assert_eq!(finger_forces([0.04, -0.04], [0.0, 0.0]), [20.0, -20.0]);
        let f = finger_forces([0.02, -0.02], [0.019, -0.019]);
        assert!((f[0] - 1.0).abs() < 1e-9 && (f[1] + 1.0).abs() < 1e-9);
    }
}
