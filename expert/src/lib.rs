//! The scripted expert: a privileged planner that solves LIBERO tasks through the same 7-D
//! action interface a policy uses (it reads the simulator's state, but acts only by actions —
//! no teleporting, welding or pose editing), so it can stand in for a policy.

mod door;
mod drawer;
mod geometry;
mod insert;
mod knob;
mod lean;
mod motion;
mod pick_place;
mod plan;
mod push;
mod skill;

pub use plan::PlanError;

use vifo_robots::action::Action;

use vifo_scenes::sim::Sim;
use vifo_scenes::task::Atom;
use plan::Skill;
use skill::{OPEN, Step};

/// A running expert for one episode.
pub struct Expert {
    skills: Vec<Skill>,
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
        match self.skills.get(self.current) {
            Some(Skill::PickPlace(s)) => s.describe(),
            Some(Skill::Drawer(s)) => s.describe(),
            Some(Skill::Door(s)) => s.describe(),
            Some(Skill::Knob(s)) => s.describe(),
            Some(Skill::Push(s)) => s.describe(),
            Some(Skill::Insert(s)) => s.describe(),
            None => "done".to_string(),
        }
    }

    /// The next action.
    pub fn act(&mut self, sim: &Sim) -> Action {
        while !self.finished() {
            let step = match &mut self.skills[self.current] {
                Skill::PickPlace(s) => s.step(sim),
                Skill::Drawer(s) => s.step(sim),
                Skill::Door(s) => s.step(sim),
                Skill::Knob(s) => s.step(sim),
                Skill::Push(s) => s.step(sim),
                Skill::Insert(s) => s.step(sim),
            };
            match step {
                Step::Act(a) => return a,
                Step::Done => self.current += 1,
                Step::Failed(why) => self.failure = Some(why),
            }
        }
        Action::hold(OPEN)
    }
}
