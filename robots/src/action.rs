//! The 7-D action every policy sends: the Panda's delta end-effector action `[dx, dy, dz, dax,
//! day, daz, gripper]`, or in a PiPER scene its joint deltas `[dq1, .., dq6, gripper]`
//! ([`crate::piper::Piper::command_joint_delta`]). Errors name the values as the arm reads them.

use thiserror::Error;

/// Why an action was refused. The simulation is untouched when this is returned.
#[derive(Debug, Error, PartialEq)]
pub enum ActionError {
    #[error("action has {got} values; expected 7 ([{}])", .names.join(", "))]
    WrongLength { got: usize, names: &'static [&'static str; 7] },
    #[error("action value {index} ({name}) is {value}; every value must be finite")]
    NotFinite { index: usize, name: &'static str, value: f64 },
}

/// The values of the Panda's delta end-effector action (OSC_POSE), as errors name them.
pub const END_EFFECTOR_DELTAS: [&str; 7] = ["dx", "dy", "dz", "dax", "day", "daz", "gripper"];
/// The values of the PiPER's joint-delta action.
pub const JOINT_DELTAS: [&str; 7] = ["dq1", "dq2", "dq3", "dq4", "dq5", "dq6", "gripper"];

/// An action of finite values in [-1, 1] (clipped, as robosuite's controllers clip their
/// input): it cannot carry a NaN or an infinity into the physics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Action([f64; 7]);

impl Action {
    /// Validates and clips. Rejects wrong lengths and NaN/inf values with an error naming them
    /// as the Panda's end-effector deltas.
    pub fn new(values: &[f64]) -> Result<Action, ActionError> {
        Action::named(values, &END_EFFECTOR_DELTAS)
    }

    /// [`Action::new`] for an arm whose action's values have other `names`.
    pub fn named(values: &[f64], names: &'static [&'static str; 7]) -> Result<Action, ActionError> {
        let values: [f64; 7] = values.try_into().map_err(|_| ActionError::WrongLength { got: values.len(), names })?;
        for (index, &value) in values.iter().enumerate() {
            if !value.is_finite() {
                return Err(ActionError::NotFinite { index, name: names[index], value });
            }
        }
        Ok(Action(values.map(|v| v.clamp(-1.0, 1.0))))
    }

    /// From values a controller computed (the scripted expert, a bench): clipped to [-1, 1],
    /// and a non-finite value becomes 0 (no motion on that axis). A policy's action goes
    /// through [`Action::new`], which refuses such values instead.
    pub fn clipped(values: [f64; 7]) -> Action {
        Action(values.map(|v| if v.is_finite() { v.clamp(-1.0, 1.0) } else { 0.0 }))
    }

    /// All zeros except the gripper: hold still with the gripper opening (-1) or closing (+1).
    pub fn hold(gripper: f64) -> Action {
        Action::clipped([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, gripper])
    }

    pub fn values(&self) -> [f64; 7] {
        self.0
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
    fn actions_built_from_computed_values_are_finite_and_clipped() {
        let a = Action::clipped([f64::NAN, 2.0, -3.0, f64::INFINITY, 0.25, -0.5, f64::NEG_INFINITY]);
        assert_eq!(a.values(), [0.0, 1.0, -1.0, 0.0, 0.25, -0.5, 0.0]);
        assert_eq!(Action::hold(f64::NAN).gripper(), 0.0);
        assert_eq!(Action::hold(-7.0).values(), [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]);
    }

    #[test]
    fn rejects_bad_actions_with_a_clear_error() {
        let short = Action::new(&[0.0; 6]).unwrap_err();
        assert_eq!(short, ActionError::WrongLength { got: 6, names: &END_EFFECTOR_DELTAS });
        assert_eq!(short.to_string(), "action has 6 values; expected 7 ([dx, dy, dz, dax, day, daz, gripper])");
        let err = Action::new(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("dz"), "{err}");
        assert!(Action::new(&[0.0, 0.0, 0.0, f64::INFINITY, 0.0, 0.0, 1.0]).is_err());
    }

    #[test]
    fn a_joint_delta_action_is_refused_in_its_own_names() {
        let err = Action::named(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 1.0], &JOINT_DELTAS).unwrap_err();
        assert_eq!(err.to_string(), "action value 2 (dq3) is NaN; every value must be finite");
        let short = Action::named(&[0.0; 8], &JOINT_DELTAS).unwrap_err();
        assert_eq!(short.to_string(), "action has 8 values; expected 7 ([dq1, dq2, dq3, dq4, dq5, dq6, gripper])");
    }

    #[test]
    fn clips_to_the_unit_box() {
        let a = Action::new(&[2.0, -3.0, 0.5, 0.0, 0.0, 0.0, 7.0]).unwrap();
        assert_eq!(a.0, [1.0, -1.0, 0.5, 0.0, 0.0, 0.0, 1.0]);
    }
}
