//! From goal atoms to an ordered list of skills.

use thiserror::Error;

use vifo_robots::spatial::Vec3;
use vifo_scenes::catalog::JointKind;
use vifo_scenes::sim::Sim;
use vifo_scenes::task::{Atom, Predicate};

use crate::geometry;
use crate::skills::{self, Door, Drawer, DrawerGoal, Insert, Knob, PARTLY_OPEN, PickPlace, Placement, Push, Skill, Spot, Stack, drawer_of};
use vifo_scenes::scene_class::ArmKind;

/// A goal the expert has no skill for.
#[derive(Debug, Error, PartialEq)]
pub enum PlanError {
    #[error("the expert cannot achieve {0}")]
    Unsupported(String),
    #[error("{atom}: '{name}' is not in the scene")]
    UnknownName { atom: String, name: String },
}

/// Categories too flat to grasp: LIBERO's tasks push them.
const PUSHED: [&str; 1] = ["plate"];
/// How far a knob is turned past LIBERO's "on" threshold (0.5 rad).
const KNOB_ON: f64 = 0.8;
/// A drawer to put something in is pulled out unless already past this joint position (LIBERO
/// counts it open below -0.14, but the closed drawers' handles above hang over its front, so
/// an object only fits in with the drawer nearly all the way out).
const DRAWER_OPEN_BELOW: f64 = -0.15;

fn spot_of(sim: &Sim, atom: &Atom, name: &str) -> Result<Spot, PlanError> {
    if let Some((i, _)) = sim.model().entity(name) {
        return Ok(Spot::Entity(i));
    }
    match sim.region_box(name) {
        Some(_) => Ok(Spot::Region { name: name.to_string(), offset: [0.0; 2] }),
        None => Err(PlanError::UnknownName { atom: atom.to_string(), name: name.to_string() }),
    }
}

/// The knob (entity, body, joint) of an entity, if it has one.
fn knob_of(sim: &Sim, name: &str) -> Option<(usize, usize, String)> {
    let (entity, e) = sim.model().entity(name)?;
    let (body, b) = e.model.bodies.iter().enumerate().find(|(_, b)| b.joint.is_some() && b.name == "button")?;
    Some((entity, body, b.joint.as_ref()?.name.clone()))
}

/// The door (entity, body, joint) of an entity: a hinged body other than a knob.
fn door_of(sim: &Sim, name: &str) -> Option<(usize, usize, String)> {
    let (entity, e) = sim.model().entity(name)?;
    let (body, b) = e.model.bodies.iter().enumerate().find(|(_, b)| {
        b.name != "button" && b.joint.as_ref().is_some_and(|j| j.kind == JointKind::Hinge)
    })?;
    Some((entity, body, b.joint.as_ref()?.name.clone()))
}

/// Room left between an object's edge and the open drawer's handle: the hand takes the object
/// with its 6.4 cm width toward the drawer, just past the object's middle.
const DRAWER_CLEARANCE: f64 = 0.025;

/// Queues opening `drawer`, first pushing out of its way each object the plan picks later
/// that stands where the open drawer will hang (the hand could not reach under it afterwards).
fn open_drawer(sim: &Sim, ordered: &mut Vec<(u8, Box<dyn Skill>)>, drawer: Drawer, picked: &[usize]) {
    let sweep = drawer.sweep(sim);
    let across = Vec3::new(-sweep.dir.y, sweep.dir.x, 0.0);
    for &i in picked {
        let e = &sim.model().entities[i];
        let points = geometry::corners(sim, i, 0);
        let (lo, hi) = geometry::bounds(&points);
        let (u, v) = (geometry::extent(&points, &sweep.dir), geometry::extent(&points, &across));
        let under = lo.z < sweep.bottom && hi.z > sweep.bottom - 0.15;
        let inside_closed = u.0 < sweep.along.0 + 0.02;
        let overlaps = u.0 < sweep.along.1 + DRAWER_CLEARANCE
            && v.1 > sweep.across.0 - DRAWER_CLEARANCE
            && v.0 < sweep.across.1 + DRAWER_CLEARANCE;
        if under && !inside_closed && overlaps {
            let c = sim.entity_pose(i).pos;
            let shift = sweep.along.1 + DRAWER_CLEARANCE - u.0;
            let to = c + sweep.dir * shift;
            // Behind it is the drawer's way: a vessel is pushed from inside.
            let inside = skills::inside_floor(&e.category);
            ordered.push((0, Box::new(Push::new(i, [to.x, to.y], 0.015, inside))));
        }
    }
    ordered.push((0, Box::new(drawer)));
}

/// Gap left between objects put on the same region.
const SHARE_GAP: f64 = 0.012;

/// Where each object put on a region shared with others goes (world xy offsets from the
/// region's centre, by goal index): side by side along the world axis across which the
/// objects are narrowest, centred on the region, as far as the region allows.
fn shared_offsets(sim: &Sim, goals: &[Atom]) -> Vec<[f64; 2]> {
    let mut offsets = vec![[0.0; 2]; goals.len()];
    let on_region = |a: &Atom| {
        let object = sim.model().entity(a.args.first()?)?.0;
        let region = a.args.get(1)?;
        (a.predicate == Predicate::On && sim.region_box(region).is_some()).then_some((object, region.clone()))
    };
    let placed: Vec<(usize, usize, String)> = goals.iter().enumerate().filter_map(|(g, a)| on_region(a).map(|(o, r)| (g, o, r))).collect();
    for (_, _, region) in &placed {
        let sharing: Vec<(usize, usize)> = placed.iter().filter(|(_, _, r)| r == region).map(|(g, o, _)| (*g, *o)).collect();
        if sharing.len() < 2 {
            continue;
        }
        let widths = |axis: &Vec3| -> Vec<f64> {
            sharing.iter().map(|(_, o)| { let (lo, hi) = geometry::extent(&geometry::corners(sim, *o, 0), axis); hi - lo }).collect()
        };
        let (wx, wy) = (widths(&Vec3::x()), widths(&Vec3::y()));
        let (axis, w) = if wx.iter().sum::<f64>() <= wy.iter().sum::<f64>() { (0, wx) } else { (1, wy) };
        let room = sim.region_box(region).map_or(0.0, |r| (r.pose.rot * r.half_size)[axis].abs());
        let total = w.iter().sum::<f64>() + SHARE_GAP * (w.len() - 1) as f64;
        let mut at = -0.5 * total;
        for ((g, _), width) in sharing.iter().zip(&w) {
            offsets[*g][axis] = (at + 0.5 * width).clamp(-room, room);
            at += width + SHARE_GAP;
        }
    }
    offsets
}

/// The skills achieving `goals`, in order: opening drawers first, then switches, then moving
/// objects, and closing last (so things can be put into a drawer before it is shut).
pub fn plan(sim: &Sim, goals: &[Atom]) -> Result<Vec<Box<dyn Skill>>, PlanError> {
    if sim.model().robot.kind() == ArmKind::Piper {
        return stacking_plan(sim, goals);
    }
    let mut ordered: Vec<(u8, Box<dyn Skill>)> = Vec::new();
    let picked: Vec<usize> = goals
        .iter()
        .filter(|a| matches!(a.predicate, Predicate::On | Predicate::In))
        .filter_map(|a| sim.model().entity(a.args.first()?))
        .filter(|(_, e)| e.movable() && !PUSHED.contains(&e.category.as_str()))
        .map(|(i, _)| i)
        .collect();
    let offsets = shared_offsets(sim, goals);
    for (g, atom) in goals.iter().enumerate() {
        let unsupported = || PlanError::Unsupported(atom.to_string());
        let unknown = |name: &str| PlanError::UnknownName { atom: atom.to_string(), name: name.to_string() };
        let arg = |i: usize| atom.args.get(i).map(String::as_str).unwrap_or("");
        match atom.predicate {
            Predicate::On | Predicate::In => {
                let (object, e) = sim.model().entity(arg(0)).ok_or_else(|| unknown(arg(0)))?;
                if !e.movable() {
                    return Err(unsupported());
                }
                let spot = match spot_of(sim, atom, arg(1))? {
                    Spot::Region { name, .. } => Spot::Region { name, offset: offsets[g] },
                    entity => entity,
                };
                if PUSHED.contains(&e.category.as_str()) && atom.predicate == Predicate::On {
                    for push in skills::pushes(sim, object, spot.xy(sim), 0.015) {
                        ordered.push((2, Box::new(push)));
                    }
                    continue;
                }
                if atom.predicate == Predicate::In
                    && let Some((entity, body, joint)) = drawer_of(sim, arg(1))
                    && let Some(q) = sim.joint_position(entity, &joint).filter(|&q| q > DRAWER_OPEN_BELOW)
                {
                    let goal = if q < PARTLY_OPEN { DrawerGoal::Widen } else { DrawerGoal::Open };
                    open_drawer(sim, &mut ordered, Drawer::new(entity, body, joint, goal), &picked);
                }
                if let Spot::Region { name, .. } = &spot
                    && atom.predicate == Predicate::In
                    && skills::insert_needed(sim, object, name)
                {
                    ordered.push((2, Box::new(Insert::new(object, name.clone()))));
                    continue;
                }
                let placement = if atom.predicate == Predicate::In { Placement::Into(spot) } else { Placement::On(spot) };
                ordered.push((2, Box::new(PickPlace::new(object, placement))));
            }
            Predicate::Open | Predicate::Close => {
                if let (Predicate::Close, Some((entity, body, joint))) = (&atom.predicate, door_of(sim, arg(0))) {
                    ordered.push((3, Box::new(Door::new(entity, body, joint))));
                    continue;
                }
                let (entity, body, joint) = drawer_of(sim, arg(0)).ok_or_else(unsupported)?;
                if atom.predicate == Predicate::Open {
                    open_drawer(sim, &mut ordered, Drawer::new(entity, body, joint, DrawerGoal::Open), &picked);
                } else {
                    ordered.push((3, Box::new(Drawer::new(entity, body, joint, DrawerGoal::Close))));
                }
            }
            // A knob already on is left alone.
            Predicate::TurnOn if sim.holds(atom) == Ok(true) => {}
            Predicate::TurnOn => {
                let (entity, body, joint) = knob_of(sim, arg(0)).ok_or_else(unsupported)?;
                ordered.push((1, Box::new(Knob::new(entity, body, joint, KNOB_ON))));
            }
            _ => return Err(unsupported()),
        }
    }
    ordered.sort_by_key(|(rank, _)| *rank);
    Ok(ordered.into_iter().map(|(_, s)| s).collect())
}

/// The PiPER's plan (§4.4 study): its one skill is stacking a cup into another, so every goal
/// must be `(On cup other_cup)` between movable objects; they run in goal order (the cup that
/// goes in first is the one the next goes into).
fn stacking_plan(sim: &Sim, goals: &[Atom]) -> Result<Vec<Box<dyn Skill>>, PlanError> {
    let mut out: Vec<Box<dyn Skill>> = Vec::new();
    for atom in goals {
        let unknown = |name: &str| PlanError::UnknownName { atom: atom.to_string(), name: name.to_string() };
        let arg = |i: usize| atom.args.get(i).map(String::as_str).unwrap_or("");
        if atom.predicate != Predicate::On {
            return Err(PlanError::Unsupported(atom.to_string()));
        }
        let (object, a) = sim.model().entity(arg(0)).ok_or_else(|| unknown(arg(0)))?;
        let (target, b) = sim.model().entity(arg(1)).ok_or_else(|| unknown(arg(1)))?;
        if !a.movable() || !b.movable() {
            return Err(PlanError::Unsupported(atom.to_string()));
        }
        out.push(Box::new(Stack::new(object, target)));
    }
    Ok(out)
}
