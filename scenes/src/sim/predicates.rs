//! LIBERO's success predicates with its exact thresholds and contact conditions
//! (`envs/predicates/base_predicates.py`, `envs/object_states/base_object_states.py`).

use thiserror::Error;
use vifo_robots::spatial::Vec3;

use super::episode::Sim;
use crate::task::{Atom, Predicate};

/// An atom that cannot be evaluated in this scene.
#[derive(Debug, Error, PartialEq)]
pub enum PredicateError {
    #[error("{atom}: '{name}' is neither an object, a fixture nor a region of the scene")]
    UnknownName { atom: String, name: String },
    #[error("{atom}: {why}")]
    Unsupported { atom: String, why: String },
}

/// An articulated class's `(open, close)` tests on one joint position.
type OpenClose = (fn(f64) -> bool, fn(f64) -> bool);

/// Joint thresholds of LIBERO's articulated object classes: `(open, close)` as predicates on
/// one joint position.
fn articulation(category: &str) -> Option<OpenClose> {
    match category {
        "wooden_cabinet" | "white_cabinet" => Some((|q| q < -0.14, |q| q > 0.0)),
        "microwave" => Some((|q| q < -1.3, |q| q > -0.005)),
        // The stove's knob: TurnOn is "open", TurnOff is "close".
        "flat_stove" => Some((|q| q >= 0.5, |q| q < 0.0)),
        _ => None,
    }
}

/// Horizontal distance below which `On(a, b)` with an object `b` holds (body origins).
pub const ON_OBJECT_XY: f64 = 0.03;

impl Sim {
    fn position_of(&self, name: &str) -> Option<Vec3> {
        self.model().entity(name).map(|(i, _)| self.entity_pose(i).pos)
    }

    /// Evaluates one atom at the current state.
    pub fn holds(&self, atom: &Atom) -> Result<bool, PredicateError> {
        let text = atom.to_string();
        let unknown = |name: &str| PredicateError::UnknownName { atom: text.clone(), name: name.to_string() };
        let arg = |i: usize| atom.args.get(i).map(String::as_str).unwrap_or("");
        match atom.predicate {
            Predicate::True => Ok(true),
            Predicate::False => Ok(false),
            Predicate::Up => Ok(self.position_of(arg(0)).ok_or_else(|| unknown(arg(0)))?.z >= 1.0),
            Predicate::On => {
                let a = self.position_of(arg(0)).ok_or_else(|| unknown(arg(0)))?;
                if let Some(b) = self.position_of(arg(1)) {
                    let xy = ((a.x - b.x).powi(2) + (a.y - b.y).powi(2)).sqrt();
                    return Ok(b.z <= a.z && self.touching(arg(1), arg(0)) && xy < ON_OBJECT_XY);
                }
                let region = self.region_box(arg(1)).ok_or_else(|| unknown(arg(1)))?;
                // LIBERO rotates the offset by R, not Rᵀ (matters only for yawed sites).
                let d = region.pose.rot * (a - region.pose.pos);
                let s = region.half_size;
                let inside = s.z - 0.005 < d.z && d.z < s.z + 0.10 && d.x.abs() < s.x && d.y.abs() < s.y;
                let owner_touch = match region.owner {
                    Some(owner) => self.touching(&self.model().entities[owner].name, arg(0)),
                    None => true,
                };
                Ok(inside && owner_touch)
            }
            Predicate::In => {
                let a = self.position_of(arg(0)).ok_or_else(|| unknown(arg(0)))?;
                let region = self.region_box(arg(1)).ok_or_else(|| PredicateError::Unsupported {
                    atom: text.clone(),
                    why: format!("In needs a region as second argument, '{}' is not one", arg(1)),
                })?;
                // in_box: element-wise |R·s| as an axis-aligned box, 1 cm extra below.
                let h = (region.pose.rot * region.half_size).abs();
                let (mut lb, ub) = (region.pose.pos - h, region.pose.pos + h);
                lb.z -= 0.01;
                Ok((0..3).all(|k| lb[k] < a[k] && a[k] < ub[k]))
            }
            Predicate::Open | Predicate::Close | Predicate::TurnOn | Predicate::TurnOff => {
                let open = matches!(atom.predicate, Predicate::Open | Predicate::TurnOn);
                let (entity, joints) = self.articulation_joints(arg(0)).ok_or_else(|| unknown(arg(0)))?;
                let category = &self.model().entities[entity].category;
                let (is_open, is_close) = articulation(category).ok_or_else(|| PredicateError::Unsupported {
                    atom: text.clone(),
                    why: format!("category {category} has no articulation thresholds"),
                })?;
                let q: Vec<f64> = joints.iter().filter_map(|j| self.joint_position(entity, j)).collect();
                Ok(if open { q.iter().any(|&v| is_open(v)) } else { !q.is_empty() && q.iter().all(|&v| is_close(v)) })
            }
            Predicate::PrintJointState => Ok(true),
        }
    }

    /// The entity and joint names an articulation predicate reads: a region on a moving part
    /// (a drawer's `top_region`) means that part's joint; a whole object means all its joints.
    pub(crate) fn articulation_joints(&self, name: &str) -> Option<(usize, Vec<String>)> {
        let joint_names = |entity: usize, body: Option<usize>| -> Vec<String> {
            let model = self.model().entities[entity].model;
            model
                .bodies
                .iter()
                .enumerate()
                .filter(|(i, _)| body.is_none_or(|b| b == *i))
                .filter_map(|(_, b)| b.joint.as_ref().map(|j| j.name.clone()))
                .collect()
        };
        if let Some((i, _)) = self.model().entity(name) {
            return Some((i, joint_names(i, None)));
        }
        let region = self.model().region(name)?;
        match &region.place {
            super::model::RegionPlace::Site { entity, site } => {
                let body = self.model().entities[*entity].model.sites[*site].body;
                Some((*entity, joint_names(*entity, Some(body))))
            }
            super::model::RegionPlace::Workspace { .. } => None,
        }
    }

    /// Whether every goal atom holds (LIBERO's `_check_success`).
    pub fn success(&self) -> Result<bool, PredicateError> {
        for atom in &self.model().task.goal {
            if !self.holds(atom)? {
                return Ok(false);
            }
        }
        Ok(true)
    }
}
