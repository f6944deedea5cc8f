//! The scripted expert as a policy, following the language, the cue, or the cue only when the
//! language authorises it.

use vifo_expert::Expert;
use vifo_scenes::task::Atom;
use vifo_robots::action::Action;

use super::ground::ground;
use crate::policy::{EpisodeState, Observation, Policy, PolicyError};
use crate::spec::Protocol;
use crate::studies::piper;

/// What the expert executes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Follow {
    /// The task the instruction names (grounded with [`ground`]); nothing when it names none.
    Language,
    /// The task the cue shows (privileged: read from the episode, not from the image).
    Cue,
    /// The cue when the instruction is the authorisation sentence, else the language.
    Authorized,
}

impl Follow {
    pub fn name(self) -> &'static str {
        match self {
            Follow::Language => "expert-language",
            Follow::Cue => "expert-cue",
            Follow::Authorized => "expert-authorized",
        }
    }
}

/// The gripper command while doing nothing: open, as LIBERO's dummy action.
const OPEN: f64 = -1.0;

/// A privileged scripted policy: plans at the first step from the simulator and the chosen
/// goal, then acts through the 7-D action like any policy. Ignores the images.
pub struct ExpertPolicy {
    follow: Follow,
    /// `None` until the first step; `Some(None)` when there is nothing to do.
    plan: Option<Option<Expert>>,
}

impl ExpertPolicy {
    pub fn new(follow: Follow) -> ExpertPolicy {
        ExpertPolicy { follow, plan: None }
    }

    /// The goal this policy pursues in this episode, if any.
    fn goal(&self, obs: &Observation, state: &EpisodeState<'_>) -> Option<Vec<Atom>> {
        let scene = &state.sim.model().task;
        let cue = || state.cue_goal.map(<[Atom]>::to_vec);
        let language = || ground(&obs.instruction, scene).or_else(|| own_instruction(&obs.instruction, scene));
        match self.follow {
            Follow::Language => language(),
            Follow::Cue => cue(),
            Follow::Authorized if obs.instruction == Protocol::AUTHORIZED_INSTRUCTION || piper::authorizes(&obs.instruction) => cue(),
            Follow::Authorized => language(),
        }
    }
}

/// In a study scene, the scene task's own instruction means its goal (the grounder knows
/// LIBERO's phrasing, not "stack the cups"); LIBERO's scenes are left to the grounder alone.
fn own_instruction(instruction: &str, scene: &vifo_scenes::Task) -> Option<Vec<Atom>> {
    let study = scene.suite.as_deref() == Some(piper::SUITE);
    (study && instruction == scene.instruction).then(|| scene.goal.clone())
}

impl Policy for ExpertPolicy {
    fn name(&self) -> String {
        self.follow.name().to_string()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.plan = None;
        Ok(())
    }

    fn act(&mut self, _obs: &Observation) -> Result<[f64; 7], PolicyError> {
        Err(PolicyError::Other(format!(
            "{} is a privileged scripted policy: it needs the simulator (run it in-process through the environment)",
            self.follow.name()
        )))
    }

    fn act_with_state(&mut self, obs: &Observation, state: &EpisodeState<'_>) -> Result<[f64; 7], PolicyError> {
        if self.plan.is_none() {
            // A goal the expert cannot plan for (a skill it lacks) is the policy failing, not
            // an error of the episode: it then holds still like a policy with nothing to do.
            let expert = self.goal(obs, state).and_then(|goal| Expert::for_goals(state.sim, &goal).ok());
            self.plan = Some(expert);
        }
        Ok(match self.plan.as_mut().and_then(Option::as_mut) {
            Some(expert) => expert.act(state.sim).values(),
            None => Action::hold(OPEN).values(),
        })
    }

    fn uses_images(&self) -> bool {
        false
    }

    fn holding_still(&self) -> bool {
        match &self.plan {
            Some(Some(expert)) => expert.finished(),
            Some(None) => true,
            None => false,
        }
    }
}
