//! Which LIBERO placement rule each movable object follows, in LIBERO's sampling order.
//!
//! LIBERO's `reset()` places objects in three passes: objects on workspace regions (BDDL init
//! order, one composite sampler with the fixtures), then objects on or in fixture/object sites,
//! then objects on other objects. Articulation atoms and fixtures come before all of them (see
//! `sample.rs`), so drawers are open before a bowl is put inside.

use crate::sim::{RegionPlace, SceneModel};
use crate::task::{Atom, Predicate};

/// What an object's init atom puts it on or in.
#[derive(Clone, Debug, PartialEq)]
pub enum Support {
    /// `(On obj region)` with a workspace rectangle: task region index.
    Workspace { region: usize },
    /// `(On obj site)` with a site of a fixture or object: region key.
    OnSite { key: String },
    /// `(In obj site)`: region key.
    InSite { key: String },
    /// `(On obj other)`: entity index of the object below.
    OnObject { below: usize },
}

/// One movable object's placement.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    pub entity: usize,
    pub support: Support,
    /// The init atom it comes from (checked after settling).
    pub atom: Atom,
}

/// The placements of every movable object, in sampling order, or what keeps the task from
/// being placed LIBERO's way.
pub fn placements(model: &SceneModel) -> Result<Vec<Placement>, String> {
    let mut passes: [Vec<Placement>; 3] = Default::default();
    for atom in &model.task.init {
        let Some((entity, e)) = atom.args.first().and_then(|a| model.entity(a)) else { continue };
        if !e.movable() || !matches!(atom.predicate, Predicate::On | Predicate::In) {
            continue;
        }
        let target = atom.args.get(1).map(String::as_str).unwrap_or("");
        let (pass, support) = match (atom.predicate, model.region(target), model.entity(target)) {
            (Predicate::On, Some(r), _) if matches!(r.place, RegionPlace::Workspace { .. }) => {
                let region = model.task.regions.iter().position(|t| t.key == target).ok_or_else(|| format!("{atom}: unknown region"))?;
                (0, Support::Workspace { region })
            }
            (Predicate::On, Some(_), _) => (1, Support::OnSite { key: target.to_string() }),
            (Predicate::In, Some(r), _) if matches!(r.place, RegionPlace::Site { .. }) => (1, Support::InSite { key: target.to_string() }),
            (Predicate::On, None, Some((below, b))) if b.movable() && below != entity => (2, Support::OnObject { below }),
            _ => return Err(format!("{atom}: LIBERO has no placement rule for this init atom")),
        };
        if passes.iter().flatten().any(|p| p.entity == entity) {
            return Err(format!("{atom}: {} already has a placement atom", e.name));
        }
        passes[pass].push(Placement { entity, support, atom: atom.clone() });
    }
    let [mut out, sites, stacked] = passes;
    out.extend(sites);
    out.extend(order_stacks(stacked, &out)?);
    if let Some(e) = model.entities.iter().enumerate().find(|(i, e)| e.movable() && !out.iter().any(|p| p.entity == *i)) {
        return Err(format!("{} has no (On ...) or (In ...) init atom", e.1.name));
    }
    Ok(out)
}

/// Objects on objects, each after the object it stands on.
fn order_stacks(mut pending: Vec<Placement>, placed: &[Placement]) -> Result<Vec<Placement>, String> {
    let mut out: Vec<Placement> = Vec::new();
    while !pending.is_empty() {
        let ready = pending.iter().position(|p| match p.support {
            Support::OnObject { below } => placed.iter().chain(&out).any(|q| q.entity == below),
            _ => true,
        });
        let Some(i) = ready else {
            return Err(format!("{}: the objects stand on each other in a cycle or on an unplaced object", pending[0].atom));
        };
        out.push(pending.remove(i));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::task;

    #[test]
    fn spatial_stacks_come_after_what_they_stand_on() {
        // libero_spatial[5]: bowl 1 on the ramekin, bowl 2 on the cookie box.
        let model = SceneModel::build(task("libero_spatial", 5).unwrap()).unwrap();
        let plan = placements(&model).unwrap();
        let name = |p: &Placement| model.entities[p.entity].name.clone();
        let names: Vec<String> = plan.iter().map(name).collect();
        assert_eq!(names.len(), 5);
        assert!(matches!(plan[0].support, Support::Workspace { .. }));
        let ramekin = names.iter().position(|n| n == "glazed_rim_porcelain_ramekin_1").unwrap();
        let bowl = names.iter().position(|n| n == "akita_black_bowl_1").unwrap();
        assert!(ramekin < bowl && matches!(plan[bowl].support, Support::OnObject { .. }));
    }

    #[test]
    fn drawer_and_site_atoms_are_recognised() {
        let model = SceneModel::build(task("libero_spatial", 4).unwrap()).unwrap();
        let plan = placements(&model).unwrap();
        assert!(plan.iter().any(|p| p.support == Support::InSite { key: "wooden_cabinet_1_top_region".into() }));
        assert!(plan.iter().any(|p| p.support == Support::OnSite { key: "wooden_cabinet_1_top_side".into() }));
    }

    #[test]
    fn objects_without_a_rule_are_reported() {
        let mut t = task("libero_10", 2).unwrap().clone();
        t.init.retain(|a| a.args[0] != "moka_pot_1");
        let model = SceneModel::build(&t).unwrap();
        assert_eq!(placements(&model).unwrap_err(), "moka_pot_1 has no (On ...) or (In ...) init atom");
        let mut t = task("libero_10", 2).unwrap().clone();
        t.init.push(Atom { predicate: Predicate::On, args: vec!["moka_pot_1".into(), "moka_pot_1".into()] });
        let model = SceneModel::build(&t).unwrap();
        assert!(placements(&model).unwrap_err().contains("no placement rule"));
    }
}
