//! What makes a state good: after settling, every object rests where its init atom says, none
//! sank below the table top or floor, none still moves, and under a zero action none drifts.

use std::sync::Arc;

use vifo_robots::action::Action;
use vifo_robots::spatial::{Pose, angle_between};

use super::drop::lowest_point;
use super::{EpisodeStart, apply};
use crate::sim::{RegionPlace, SceneModel, Sim, StateError, fixture_ranges};
use crate::task::Predicate;

/// LIBERO's no-op steps (gripper opening) before the policy acts.
pub const WAIT_STEPS: usize = 10;

/// LIBERO's wait after loading a state (`num_steps_wait`): [`WAIT_STEPS`] control steps of its
/// dummy action, holding still with the gripper open. Every episode start runs this.
pub fn wait(sim: &mut Sim) {
    for _ in 0..WAIT_STEPS {
        sim.step(&wait_action());
    }
}

/// The action of [`wait`]'s steps.
pub fn wait_action() -> Action {
    Action::hold(-1.0)
}
/// Zero-action steps over which drift is measured.
pub const DRIFT_STEPS: usize = 200;
/// The stability gate: no object moves further than this (m) over [`DRIFT_STEPS`].
pub const MAX_DRIFT: f64 = 0.001;
/// How far an object may sink into its support (soft contacts rest slightly inside).
const SINK: f64 = 0.003;
/// How far settling may move an object from where the state put it (m, rad).
const SETTLE_SHIFT: f64 = 0.005;
const SETTLE_TURN: f64 = 0.05;
/// Settled objects move slower than this (m/s, rad/s).
const STILL_SPEED: f64 = 0.005;
const STILL_SPIN: f64 = 0.05;

/// The verdict on one state.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// Everything wrong, in words; empty for a good state.
    pub problems: Vec<String>,
    /// Largest distance an object moved during the wait steps (m).
    pub settle_shift: f64,
    /// Largest distance an object moved over [`DRIFT_STEPS`] zero-action steps after the wait,
    /// and which object, when measured.
    pub drift: Option<(f64, String)>,
}

impl Check {
    pub fn ok(&self) -> bool {
        self.problems.is_empty()
    }
}

/// Loads `start`, runs LIBERO's wait steps and judges the result; with `drift`, then also runs
/// [`DRIFT_STEPS`] zero-action steps and measures how far objects creep.
pub fn check(model: &Arc<SceneModel>, start: &EpisodeStart, drift: bool) -> Result<Check, StateError> {
    let mut sim = Sim::new(model.clone());
    apply(&mut sim, start)?;
    let placed = object_poses(&sim);
    wait(&mut sim);
    let mut problems = fixture_problems(model, start);
    problems.extend(self::problems(&sim, &placed));
    let settle_shift = largest_shift(&sim, &placed).0;
    let drift = drift.then(|| {
        let settled = object_poses(&sim);
        for _ in 0..DRIFT_STEPS {
            sim.step(&Action::hold(0.0));
        }
        let (d, entity) = largest_shift(&sim, &settled);
        if d > MAX_DRIFT {
            problems.push(format!("{} drifts {:.2} mm under a zero action", sim.model().entities[entity].name, d * 1e3));
        }
        problems.extend(below_support(&sim));
        (d, sim.model().entities[entity].name.clone())
    });
    Ok(Check { problems, settle_shift, drift })
}

/// Fixtures missing from `start`, or where their placement could not have put them (a stored
/// state is otherwise free to put a stove in the robot or under the floor).
fn fixture_problems(model: &SceneModel, start: &EpisodeStart) -> Vec<String> {
    // The files round poses to 1e-6 (metres, quaternion components); a yaw read back from a
    // rounded quaternion is off by a few times that.
    const TOLERANCE: f64 = 1e-5;
    fixture_ranges(model)
        .into_iter()
        .filter_map(|range| {
            let name = &model.entities[range.entity].name;
            match start.fixtures.iter().find(|f| &f.name == name) {
                None => Some(format!("fixture {name} has no pose")),
                Some(f) if !range.admits(&Pose::from_wxyz(f.pos, f.quat_wxyz), TOLERANCE) => {
                    Some(format!("fixture {name} at {:?} (quat {:?}) lies outside its placement region", f.pos, f.quat_wxyz))
                }
                Some(_) => None,
            }
        })
        .collect()
}

/// Poses of the movable objects (entity, pose).
pub(super) fn object_poses(sim: &Sim) -> Vec<(usize, Pose)> {
    (0..sim.model().entities.len()).filter(|&i| sim.model().entities[i].movable()).map(|i| (i, sim.entity_pose(i))).collect()
}

/// The farthest any object moved since `before`, and which.
fn largest_shift(sim: &Sim, before: &[(usize, Pose)]) -> (f64, usize) {
    before.iter().map(|(i, p)| ((sim.entity_pose(*i).pos - p.pos).norm(), *i)).fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

/// What is wrong with a settled scene whose objects were put at `placed`.
pub(super) fn problems(sim: &Sim, placed: &[(usize, Pose)]) -> Vec<String> {
    let model = sim.model();
    let mut out = Vec::new();
    for atom in &model.task.init {
        let subject = atom.args.first().and_then(|a| model.entity(a));
        let checkable = match atom.predicate {
            Predicate::On | Predicate::In => subject.is_some_and(|(_, e)| e.movable()),
            Predicate::Open | Predicate::Close | Predicate::TurnOn | Predicate::TurnOff => true,
            _ => false,
        };
        if !checkable {
            continue;
        }
        // LIBERO's own draws on tiny workspace regions land outside the region's box (the
        // widened interval), so for those the test is that the object stands on the workspace.
        let on_workspace = atom.predicate == Predicate::On
            && model.region(&atom.args[1]).is_some_and(|r| matches!(r.place, RegionPlace::Workspace { .. }));
        if on_workspace {
            let workspace = &model.task.region(&atom.args[1]).map(|r| r.target.clone()).unwrap_or_default();
            if !sim.touching(&atom.args[0], workspace) {
                out.push(format!("{atom}: {} does not rest on {workspace}", atom.args[0]));
            }
        } else {
            match sim.holds(atom) {
                Ok(true) => {}
                Ok(false) => out.push(format!("{atom} does not hold")),
                Err(e) => out.push(e.to_string()),
            }
        }
    }
    out.extend(below_support(sim));
    let r = sim.world().rapier();
    for (i, at) in placed {
        let e = &model.entities[*i];
        let now = sim.entity_pose(*i);
        let shift = (now.pos - at.pos).norm();
        let turn = angle_between(&now.rot, &at.rot);
        if shift > SETTLE_SHIFT || turn > SETTLE_TURN {
            out.push(format!("{} moved {:.1} mm / {:.3} rad while settling", e.name, shift * 1e3, turn));
        }
        let body = &r.bodies[e.bodies[0]];
        let (v, w) = (body.linvel().length(), body.angvel().length());
        if v > STILL_SPEED || w > STILL_SPIN {
            out.push(format!("{} still moves ({:.1} mm/s, {:.3} rad/s)", e.name, v * 1e3, w));
        }
    }
    out
}

/// Objects whose lowest point is below the table top (or floor), one line each.
pub fn below_support(sim: &Sim) -> Vec<String> {
    let floor = sim.model().class.support_z() - SINK;
    object_poses(sim)
        .into_iter()
        .filter_map(|(i, at)| {
            let low = lowest_point(sim, i, &at);
            (low < floor).then(|| format!("{} reaches {:.1} mm below the support", sim.model().entities[i].name, (floor + SINK - low) * 1e3))
        })
        .collect()
}
