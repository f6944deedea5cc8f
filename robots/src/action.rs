//! The 7-D action every policy sends: `[dx, dy, dz, dax, day, daz, gripper]`, the Panda's names,
//! which its errors use; a PiPER scene reads the first six as joint deltas
//! ([`crate::piper::Piper::command_joint_delta`]).

use thiserror::Error;

/// Why an action was refused. The simulation is untouched when this is returned.
#[derive(Debug, Error, PartialEq)]
pub enum ActionError {
    #[error("action has {0} values; expected 7 ([dx, dy, dz, dax, day, daz, gripper])")]
    WrongLength(usize),
    #[error("action value {index} ({name}) is {value}; every value must be finite")]
    NotFinite { index: usize, name: &'static str, value: f64 },
}

const NAMES: [&str; 7] = ["dx", "dy", "dz", "dax", "day", "daz", "gripper"];

/// A validated action, clipped to [-1, 1] as robosuite's controllers clip their input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Action(pub [f64; 7]);

impl Action {
    /// Validates and clips. Rejects wrong lengths and NaN/inf values with an error naming them.
    pub fn new(values: &[f64]) -> Result<Action, ActionError> {
        let values: [f64; 7] = values.try_into().map_err(|_| ActionError::WrongLength(values.len()))?;
        for (index, &value) in values.iter().enumerate() {
            if !value.is_finite() {
                return Err(ActionError::NotFinite { index, name: NAMES[index], value });
            }
        }
        Ok(Action(values.map(|v| v.clamp(-1.0, 1.0))))
    }

    /// All zeros except the gripper: hold still with the gripper opening (-1) or closing (+1).
    pub fn hold(gripper: f64) -> Action {
        Action([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, gripper.clamp(-1.0, 1.0)])
    }

    pub fn translation(&self) -> [f64; 3] {
        [self.0[0], self.0[1], self.0[2]]
    }

    pub fn rotation(&self) -> [f64; 3] {
        [self.0[3], self.0[4], self.0[5]]
    }

    pub fn gripper(&self) -> f64 {
        self.0[6]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_actions_with_a_clear_error() {
        assert_eq!(Action::new(&[0.0; 6]), Err(ActionError::WrongLength(6)));
        let err = Action::new(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("dz"), "{err}");
        assert!(Action::new(&[0.0, 0.0, 0.0, f64::INFINITY, 0.0, 0.0, 1.0]).is_err());
    }

    #[test]
    fn clips_to_the_unit_box() {
        let a = Action::new(&[2.0, -3.0, 0.5, 0.0, 0.0, 0.0, 7.0]).unwrap();
        assert_eq!(a.0, [1.0, -1.0, 0.5, 0.0, 0.0, 0.0, 1.0]);
    }
}
