//! From goal atoms to an ordered list of skills.

use thiserror::Error;

use super::skills::{PickPlace, Placement};
use crate::sim::{RegionPlace, Sim};
use crate::task::{Atom, Predicate};

/// A goal the expert has no skill for.
#[derive(Debug, Error, PartialEq)]
pub enum PlanError {
    #[error("the expert cannot achieve {0}")]
    Unsupported(String),
    #[error("{atom}: '{name}' is not in the scene")]
    UnknownName { atom: String, name: String },
}

/// One thing to do.
pub enum Skill {
    PickPlace(PickPlace),
}

fn xy_of(sim: &Sim, atom: &Atom, name: &str) -> Result<[f64; 2], PlanError> {
    if let Some((i, _)) = sim.model().entity(name) {
        let p = sim.entity_pose(i).pos;
        return Ok([p.x, p.y]);
    }
    let region = sim
        .region_box(name)
        .ok_or_else(|| PlanError::UnknownName { atom: atom.to_string(), name: name.to_string() })?;
    Ok([region.pose.pos.x, region.pose.pos.y])
}

/// The skills achieving `goals`, in order.
pub fn plan(sim: &Sim, goals: &[Atom]) -> Result<Vec<Skill>, PlanError> {
    let mut skills = Vec::new();
    for atom in goals {
        let unknown = |name: &str| PlanError::UnknownName { atom: atom.to_string(), name: name.to_string() };
        match atom.predicate {
            Predicate::On | Predicate::In => {
                let (object, _) = sim.model().entity(&atom.args[0]).ok_or_else(|| unknown(&atom.args[0]))?;
                if !sim.model().entities[object].movable() {
                    return Err(PlanError::Unsupported(atom.to_string()));
                }
                let xy = xy_of(sim, atom, &atom.args[1])?;
                let into = atom.predicate == Predicate::In
                    || matches!(sim.model().region(&atom.args[1]).map(|r| &r.place), Some(RegionPlace::Site { .. }) if atom.predicate == Predicate::In);
                let placement = if into { Placement::Into { xy } } else { Placement::On { xy } };
                skills.push(Skill::PickPlace(PickPlace::new(object, placement)));
            }
            _ => return Err(PlanError::Unsupported(atom.to_string())),
        }
    }
    Ok(skills)
}
