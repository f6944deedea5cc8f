//! The scripted expert: a privileged planner that solves LIBERO tasks through the same 7-D
//! action interface a policy uses (it reads the simulator's state, but acts only by actions —
//! no teleporting, welding or pose editing), so it can stand in for a policy.
//!
//! - `plan`: from a task's goal atoms to an ordered list of skills.
//! - `skills`: one recipe per skill (pick-place, push, drawer, door, knob, insert), each a
//!   short list of stages.
//! - `stages`: the motion vocabulary the recipes are written in (approach at cruise height,
//!   descend, grasp, lift, carry, set down, release, retreat, follow a hinge or a slide).
//! - `arm`: the arm-agnostic interface the stages drive (a grip-site pose target with the
//!   servo's gains, and a gripper command); the Panda implements it.
//! - `motion`: finger yaws the wrist reaches, and how far the gripper is from a pose target;
//!   `geometry`: the scene's shapes as the expert sees them (obstacles, grasp choice, heights
//!   to pass over).

mod approach;
mod arm;
mod geometry;
mod motion;
mod plan;
mod skills;
mod stages;

pub use plan::PlanError;

use vifo_robots::action::Action;
use vifo_scenes::sim::Sim;
use vifo_scenes::task::Atom;

use skills::Skill;
use stages::{OPEN, Step};

/// A running expert for one episode.
pub struct Expert {
    skills: Vec<Box<dyn Skill>>,
    current: usize,
    failure: Option<&'static str>,
}

impl Expert {
    /// An expert for the task's own goal.
    pub fn new(sim: &Sim) -> Result<Expert, PlanError> {
        let goals = sim.model().task.goal.clone();
        Self::for_goals(sim, &goals)
    }

    /// An expert achieving `goals` in the current scene (another task's goals, e.g. the one a
    /// cue shows).
    pub fn for_goals(sim: &Sim, goals: &[Atom]) -> Result<Expert, PlanError> {
        Ok(Expert { skills: plan::plan(sim, goals)?, current: 0, failure: None })
    }

    /// Whether every skill has finished (or one gave up).
    pub fn finished(&self) -> bool {
        self.current >= self.skills.len() || self.failure.is_some()
    }

    /// Why the expert gave up, if it did.
    pub fn failure(&self) -> Option<&'static str> {
        self.failure
    }

    /// Which skill runs now, for traces.
    pub fn describe(&self) -> String {
        self.skills.get(self.current).map_or_else(|| "done".to_string(), |s| s.describe())
    }

    /// The next action.
    pub fn act(&mut self, sim: &Sim) -> Action {
        while !self.finished() {
            match self.skills[self.current].step(sim) {
                Step::Act(a) => return a,
                Step::Done => self.current += 1,
                Step::Failed(why) => self.failure = Some(why),
            }
        }
        Action::hold(OPEN)
    }
}

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
