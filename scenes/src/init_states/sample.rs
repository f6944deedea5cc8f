//! One initial state from a seed: LIBERO's reset sampling, then settling and validation.
//!
//! Order of draws (all from one `Pcg64` seeded with the state's seed): articulation joints
//! (init order), fixture poses ([`sample_fixtures`]), movable objects (`plan.rs` order), arm
//! noise. The drawn layout is loaded, settled for [`SETTLE_STEPS`] with the arm holding still and
//! the gripper open, judged (`check.rs`), and its settled object poses and joint values are
//! recorded, rounded as the file stores them, reloaded and judged again after LIBERO's wait
//! steps. A draw that fails is replaced by the next one from the same generator.

use std::sync::Arc;

use rand::{Rng, RngExt, SeedableRng};
use thiserror::Error;
use vifo_robots::action::Action;

use super::articulation::{init_range, is_articulation};
use super::check::{check, object_poses, problems};
use super::format::rounded;
use super::place::Layout;
use super::plan::{Placement, placements};
use super::{EpisodeStart, FixturePose, apply};
use crate::scene_class::ArmKind;
use crate::init_file::{InitState, JointState, ObjectState, articulation_joints};
use crate::sim::{SceneModel, Sim, StateError, sample_fixtures};

/// Control steps a drawn layout settles for before it is recorded.
pub const SETTLE_STEPS: usize = 40;
/// Standard deviation (rad) of the Gaussian noise on each arm joint at reset: robosuite's
/// `initialization_noise` for the Panda, visible in LIBERO's files as a 0.02 spread around
/// `init_qpos`; the PiPER's six joints get the same around its ready pose.
pub const ARM_NOISE_STD: f64 = 0.02;
/// Draws of a whole state before giving up.
const ATTEMPTS: usize = 20;

/// Why no state came out.
#[derive(Debug, Error)]
pub enum SampleError {
    #[error("task {task}: {why}")]
    Unplaceable { task: String, why: String },
    #[error("task {task}, seed {seed}: no good state in {ATTEMPTS} draws; the last failed because {last}")]
    Exhausted { task: String, seed: u64, last: String },
    #[error(transparent)]
    State(#[from] StateError),
}

/// The seed of state `state` of task `task` in `suite`: FNV-1a of the suite name, then the two
/// indices mixed in with splitmix64 steps, so every (suite, task, state) has its own stream.
pub fn seed(suite: &str, task: usize, state: usize) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in suite.bytes() {
        h = (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3);
    }
    splitmix(splitmix(h ^ task as u64) ^ state as u64)
}

fn splitmix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A settled, validated initial state of `model`'s task, the same for the same seed.
pub fn sample(model: &Arc<SceneModel>, seed: u64) -> Result<EpisodeStart, SampleError> {
    let task = model.task.label();
    let plan = placements(model).map_err(|why| SampleError::Unplaceable { task: task.clone(), why })?;
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let mut last = String::new();
    for _ in 0..ATTEMPTS {
        let drawn = match draw(model, &plan, &mut rng) {
            Ok(drawn) => drawn,
            Err(why) => {
                last = why;
                continue;
            }
        };
        let settled = settle(model, &drawn)?;
        match settled {
            Ok(start) => {
                let verdict = check(model, &start, false)?;
                if verdict.ok() {
                    return Ok(start);
                }
                last = format!("after reloading: {}", verdict.problems.join("; "));
            }
            Err(why) => last = why,
        }
    }
    Err(SampleError::Exhausted { task, seed, last })
}

/// LIBERO's reset draw: joints, fixtures, objects, arm. Objects rest just above their support.
fn draw(model: &Arc<SceneModel>, plan: &[Placement], rng: &mut impl Rng) -> Result<EpisodeStart, String> {
    let mut sim = Sim::new(model.clone());
    for atom in model.task.init.iter().filter(|a| is_articulation(a.predicate)) {
        let name = atom.args.first().map(String::as_str).unwrap_or("");
        let (entity, joints) = sim.articulation_joints(name).ok_or_else(|| format!("{atom}: nothing articulated is called {name}"))?;
        let category = &model.entities[entity].category;
        let [low, high] = init_range(category, atom.predicate).ok_or_else(|| format!("{atom}: LIBERO has no range for {category}"))?;
        for joint in joints {
            let value = low + (high - low) * rng.random::<f64>();
            sim.set_joint(entity, &joint, value);
        }
    }
    let fixtures = sample_fixtures(&sim, rng);
    sim.apply_fixtures(&fixtures);
    let mut layout = Layout::new(&sim);
    for p in plan {
        layout.place(&sim, p, rng)?;
    }
    let (mut arm, gripper) = model.robot.init_qpos();
    let joints = if model.robot.kind() == ArmKind::Piper { 6 } else { 7 };
    for q in &mut arm[..joints] {
        *q += ARM_NOISE_STD * gaussian(rng);
    }
    let objects = model.task.objects.iter().map(|o| {
        let (entity, _) = model.entity(&o.name).expect("scene objects are the task's");
        let at = layout.placed.iter().find(|(e, _)| *e == entity).map(|(_, p)| *p).expect("every object is placed");
        ObjectState { name: o.name.clone(), pos: at.pos.into(), quat_wxyz: at.quat_wxyz(), lin_vel: [0.0; 3], ang_vel: [0.0; 3] }
    });
    let state = InitState {
        time: 0.0,
        arm_qpos: arm,
        arm_qvel: [0.0; 7],
        gripper_qpos: gripper,
        gripper_qvel: [0.0; 2],
        objects: objects.collect(),
        joints: joint_states(&sim),
    };
    let fixtures = model
        .entities
        .iter()
        .enumerate()
        .filter(|(_, e)| !e.movable())
        .map(|(i, e)| {
            let p = sim.entity_pose(i);
            FixturePose { name: e.name.clone(), pos: p.pos.into(), quat_wxyz: p.quat_wxyz() }
        })
        .collect();
    Ok(EpisodeStart { state, fixtures })
}

/// Every articulation joint in state order (objects', then fixtures'), at its current value.
fn joint_states(sim: &Sim) -> Vec<JointState> {
    let task = &sim.model().task;
    let mut out = Vec::new();
    for owner in task.objects.iter().chain(&task.fixtures) {
        let Some((entity, _)) = sim.model().entity(&owner.name) else { continue };
        for joint in articulation_joints(&owner.category) {
            let qpos = sim.joint_position(entity, joint).unwrap_or(0.0);
            out.push(JointState { owner: owner.name.clone(), joint: joint.to_string(), qpos, qvel: 0.0 });
        }
    }
    out
}

/// Loads a drawn state, lets it settle and records the result (rounded as stored), or says
/// what is wrong with it.
fn settle(model: &Arc<SceneModel>, drawn: &EpisodeStart) -> Result<Result<EpisodeStart, String>, StateError> {
    let mut sim = Sim::new(model.clone());
    apply(&mut sim, drawn)?;
    let placed = object_poses(&sim);
    for _ in 0..SETTLE_STEPS {
        sim.step(&Action::hold(-1.0));
    }
    let wrong = problems(&sim, &placed);
    if !wrong.is_empty() {
        return Ok(Err(wrong.join("; ")));
    }
    let mut start = drawn.clone();
    for o in &mut start.state.objects {
        let (entity, _) = model.entity(&o.name).expect("applied above");
        let at = sim.entity_pose(entity);
        (o.pos, o.quat_wxyz) = (at.pos.into(), at.quat_wxyz());
    }
    start.state.joints = joint_states(&sim);
    Ok(Ok(rounded(&start)))
}

/// A standard normal draw (Box–Muller; libm keeps the bits the same on every platform).
fn gaussian(rng: &mut impl Rng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    libm::sqrt(-2.0 * libm::log(u1)) * libm::cos(2.0 * std::f64::consts::PI * u2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seeds_differ_per_suite_task_and_state() {
        let seeds = [seed("libero_spatial", 0, 0), seed("libero_spatial", 0, 1), seed("libero_spatial", 1, 0), seed("libero_goal", 0, 0)];
        for i in 0..seeds.len() {
            for j in i + 1..seeds.len() {
                assert_ne!(seeds[i], seeds[j]);
            }
        }
        assert_eq!(seed("libero_10", 3, 7), seed("libero_10", 3, 7));
    }

    #[test]
    fn gaussian_draws_have_unit_spread() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        let draws: Vec<f64> = (0..20000).map(|_| gaussian(&mut rng)).collect();
        let mean = draws.iter().sum::<f64>() / draws.len() as f64;
        let var = draws.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / draws.len() as f64;
        assert!(mean.abs() < 0.03 && (var - 1.0).abs() < 0.05, "{mean} {var}");
    }
}
