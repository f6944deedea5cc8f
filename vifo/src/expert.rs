//! `vifo expert`: the scripted expert's success rate per task.

use std::sync::Arc;

use anyhow::Result;
use serde::Serialize;
use vifo_expert::Expert;
use vifo_scenes::init_states;
use vifo_scenes::sim::{Extremes, SceneModel};

use crate::start::Starts;

/// One expert episode.
#[derive(Clone, Debug, Serialize)]
pub struct ExpertEpisode {
    pub init: usize,
    pub success: bool,
    pub steps: usize,
    pub failure: Option<String>,
    /// The first object seen below the table top or floor during the episode (checked every
    /// step), if any.
    pub below_support: Option<String>,
    /// The largest speeds and penetration seen over the episode (what the physics guard's
    /// limits are chosen against).
    pub extremes: Extremes,
    /// Every action applied from the initial state, the settling steps first (what
    /// `vifo expert --actions` writes for the original stack to replay).
    #[serde(skip)]
    pub actions: Vec<[f64; 7]>,
}

/// Runs the expert from initial state `init` (`seed` places the fixtures of LIBERO's states).
pub fn episode(model: &Arc<SceneModel>, starts: &Starts, init: usize, seed: u64, budget: usize, trace: bool) -> Result<ExpertEpisode> {
    let mut sim = starts.begin(model, init, seed)?;
    init_states::wait(&mut sim);
    let mut actions = vec![init_states::wait_action().values(); init_states::WAIT_STEPS];
    if trace {
        for (i, e) in sim.model().entities.iter().enumerate() {
            let p = sim.entity_pose(i);
            eprintln!("{} at ({:.3} {:.3} {:.3}) quat {:?}", e.name, p.pos.x, p.pos.y, p.pos.z, p.quat_wxyz().map(|v| (v * 1000.0).round() / 1000.0));
        }
    }
    let mut expert = match Expert::new(&sim) {
        Ok(e) => e,
        Err(err) => return Ok(ExpertEpisode { init, success: false, steps: 0, failure: Some(err.to_string()), below_support: None, extremes: sim.extremes(), actions }),
    };
    let mut steps = 0;
    let mut below = None;
    let mut extremes = sim.extremes();
    while steps < budget {
        if below.is_none() {
            below = init_states::below_support(&sim).into_iter().next().map(|b| format!("step {steps}: {b}"));
        }
        if sim.success()? {
            return Ok(ExpertEpisode { init, success: true, steps, failure: None, below_support: below, extremes, actions });
        }
        let action = expert.act(&sim);
        if trace && steps % 5 == 0 {
            let ee = sim.model().robot.grip_site_pose(sim.world()).pos;
            let (q, fingers) = sim.model().robot.joint_positions(sim.world());
            eprintln!(
                "step {steps:3} q {:?} ee ({:.3} {:.3} {:.3}) fingers {:.4} {:.4} action {:?} {} contacts {:?}",
                q.map(|v| (v * 100.0).round() / 100.0), ee.x, ee.y, ee.z, fingers[0], fingers[1], action.values().map(|v| (v * 100.0).round() / 100.0), expert.describe(), sim.robot_contacts()
            );
            for (i, e) in sim.model().entities.iter().enumerate().filter(|(_, e)| e.movable()) {
                let p = sim.entity_pose(i);
                eprintln!("    {} at ({:.3} {:.3} {:.3}), upright {:.3}", e.name, p.pos.x, p.pos.y, p.pos.z, (p.rot * vifo_robots::spatial::Vec3::z()).z);
            }
        }
        sim.step(&action);
        actions.push(action.values());
        extremes = extremes.max(sim.extremes());
        steps += 1;
        if expert.finished() && expert.failure().is_some() {
            break;
        }
    }
    let success = sim.success()?;
    if below.is_none() {
        below = init_states::below_support(&sim).into_iter().next().map(|b| format!("step {steps}: {b}"));
    }
    Ok(ExpertEpisode { init, success, steps, failure: expert.failure().map(str::to_string), below_support: below, extremes, actions })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::start::InitSource;

    /// libero_goal's task `index` (and its step budget), its scene and its shipped states.
    fn goal_task(index: usize) -> (usize, Arc<SceneModel>, Starts) {
        let suite = vifo_scenes::suites().iter().find(|s| s.name == "libero_goal").expect("libero_goal");
        let task = &suite.tasks[index];
        let model = SceneModel::build(task).expect("scene");
        let starts = Starts::load(task, &model, &InitSource::Shipped).expect("shipped states");
        (suite.max_steps as usize, model, starts)
    }

    /// The expert lays the wine bottle on the rack's slanted shelf (a tilted region): it
    /// succeeds within the suite's budget, and the bottle still lies in the region once the
    /// arm has let go and backed off.
    #[test]
    fn lays_the_wine_bottle_on_the_rack() {
        let (budget, model, starts) = goal_task(9);
        let mut sim = starts.begin(&model, 0, 0).expect("state 0");
        init_states::wait(&mut sim);
        let mut expert = Expert::new(&sim).expect("plan");
        let mut solved_at = None;
        for step in 0..budget {
            if solved_at.is_none() && sim.success().expect("goal") {
                solved_at = Some(step);
            }
            sim.step(&expert.act(&sim));
        }
        assert!(solved_at.is_some(), "not solved in {budget} steps: {:?}", expert.failure());
        assert!(expert.finished() && expert.failure().is_none(), "the expert did not finish: {:?}", expert.failure());
        assert!(sim.success().expect("goal"), "the bottle left the rack's region after the release");
    }

    /// The plate in libero_goal state 18 lies by the cabinet: pushed from inside, the 20 cm
    /// hand coming down at the push's start would land on the cabinet, so the closed fingers
    /// come down further along the push, and the expert succeeds.
    #[test]
    fn pushes_the_plate_from_inside_beside_the_cabinet() {
        let (budget, model, starts) = goal_task(5);
        let run = episode(&model, &starts, 18, 18, budget, false).expect("episode");
        assert!(run.success, "not solved in {budget} steps: {:?}", run.failure);
        assert_eq!(run.below_support, None);
    }
}
