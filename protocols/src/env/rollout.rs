//! One episode of a policy in the environment, as the record the runner writes.

use std::path::Path;
use std::sync::Mutex;

use vifo_cues::SetName;
use vifo_render::imageio::ImageIoError;

use super::film::{Clip, Filming};
use super::{Env, EnvConfig, StepResult};
use crate::policy::Policy;
use crate::runner::{self, RunError, RunOptions, RunSummary};
use crate::spec::{EpisodeRecord, EpisodeSpec, Outcome, RESULTS_VERSION};

/// How episodes are run.
#[derive(Clone, Debug, PartialEq)]
pub struct RolloutOptions {
    /// End an episode early when the policy holds still in a world at rest (see [`rollout`]).
    pub fast_forward: bool,
    /// The episodes [`run_episodes`] films (none by default).
    pub film: Filming,
    /// Draw the configured cameras after every step, as LIBERO does (for timing against it).
    /// Off, only the observations the policy looks at ([`Policy::sees_images_next`]), the
    /// clip's frames and the episode's last observation are drawn; what the policy sees is the
    /// same either way.
    pub draw_every_step: bool,
}

impl Default for RolloutOptions {
    fn default() -> RolloutOptions {
        RolloutOptions { fast_forward: true, film: Filming::none(), draw_every_step: false }
    }
}

/// Consecutive at-rest steps (with the policy holding still) before fast-forwarding.
pub const REST_STEPS: usize = 5;

/// Runs `spec` with `policy` and returns its record (`wall_ms` is left to the runner).
///
/// Failures to set up or continue the episode — an unknown instance, a policy error (dropped
/// connection, malformed reply), an invalid action — make an error record, which a resumed run
/// retries; a policy that does not finish the task makes a completed record with its success
/// flags.
///
/// With `fast_forward`, an episode whose policy holds still ([`Policy::holding_still`]) while
/// every body has been at rest for [`REST_STEPS`] steps ends there and is recorded as run to
/// the budget: the same action on a world at rest changes nothing, so no scored goal can
/// become true later. Remote policies never hold still, so their episodes always run out.
pub fn rollout(env: &mut Env, policy: &mut dyn Policy, spec: &EpisodeSpec, options: &RolloutOptions) -> EpisodeRecord {
    let outcome = run(env, policy, spec, options, &mut None).unwrap_or_else(|message| Outcome::Error { message });
    record(spec, policy, outcome, env.config())
}

/// Runs `spec` as [`rollout`] does, in an environment of its own that draws both cameras
/// ([`Filming::env_config`] of the run's `config`), and films it into the clip `path`. The
/// record is the one [`rollout`] makes; a clip that cannot be written is reported on stderr
/// and removed, and changes nothing else.
pub fn rollout_filmed(
    config: &EnvConfig,
    policy: &mut dyn Policy,
    spec: &EpisodeSpec,
    options: &RolloutOptions,
    path: &Path,
) -> EpisodeRecord {
    let mut env = Env::new(options.film.env_config(config));
    let not_written = |e: ImageIoError| eprintln!("note: clip {} not written: {e}", path.display());
    // The clip says which look drew it, as `vifo render`'s files do.
    let look = super::scenes::recorded_look(config.cue_facing);
    let comment = format!("look: {}; episode: {}", super::scenes::look_name(&look), spec.key());
    let mut clip = Clip::create(path, &options.film, &comment).map_err(not_written).ok();
    let outcome = run(&mut env, policy, spec, options, &mut clip).unwrap_or_else(|message| Outcome::Error { message });
    if let Some(Err(e)) = clip.map(Clip::finish) {
        not_written(e);
    }
    record(spec, policy, outcome, config)
}

/// The record of an episode run with `config`: its look is the process's where the policy's
/// cameras drew, [`NO_IMAGES`](super::scenes::NO_IMAGES) where they drew nothing (a clip does
/// not count).
fn record(spec: &EpisodeSpec, policy: &dyn Policy, outcome: Outcome, config: &EnvConfig) -> EpisodeRecord {
    // The set is not the episode's business; the runner writes the run's into every record.
    EpisodeRecord {
        version: RESULTS_VERSION,
        spec: spec.clone(),
        policy: policy.name(),
        outcome,
        wall_ms: 0.0,
        set: SetName::Paper,
        look: if config.cameras.is_empty() { super::scenes::NO_IMAGES.to_string() } else { super::scenes::recorded_look(config.cue_facing) },
    }
}

fn run(
    env: &mut Env,
    policy: &mut dyn Policy,
    spec: &EpisodeSpec,
    options: &RolloutOptions,
    clip: &mut Option<Clip>,
) -> Result<Outcome, String> {
    env.reset(spec).map_err(|e| format!("reset: {e}"))?;
    film(clip, env, false);
    policy.reset().map_err(|e| e.to_string())?;
    let mut resting = 0;
    loop {
        let action = policy_action(env, policy)?;
        // The next observation's images are drawn only if the policy will look at them (or
        // the clip takes them): between its requests a chunked policy plays out its queue.
        env.set_rendering(options.draw_every_step || policy.sees_images_next());
        let step = env.step(&action).map_err(|e| e.to_string())?;
        let (language_success, cue_success, mut steps, done) =
            (step.language_success, step.cue_success, step.steps, step.done);
        film(clip, env, done);
        if !done && options.fast_forward && policy.holding_still() && env.at_rest() {
            resting += 1;
        } else {
            resting = 0;
        }
        if resting >= REST_STEPS {
            steps = env.fast_forward().map_err(|e| e.to_string())?.steps;
            film(clip, env, true);
        } else if !done {
            continue;
        }
        // The episode's last observation is drawn whoever looks at it next.
        env.render().map_err(|e| e.to_string())?;
        return Ok(Outcome::Completed { language_success, cue_success, steps });
    }
}

/// Adds the current observation to the clip when it is due, drawing it first where the step
/// did not; a clip that fails is dropped (see [`rollout_filmed`]).
fn film(clip: &mut Option<Clip>, env: &mut Env, last: bool) {
    let Some(c) = clip.as_mut() else { return };
    if !c.due(env.observation().step, last) {
        return;
    }
    let order = env.config().order;
    let drawn = env.render().map_err(|e| e.to_string());
    let added = drawn.and_then(|obs| c.add(obs, order).map_err(|e| e.to_string()));
    if let Err(e) = added {
        eprintln!("note: clip {} not written: {e}", c.path().display());
        if let Some(failed) = clip.take() {
            failed.abandon();
        }
    }
}

/// One control step of `policy` in `env`'s running episode: the policy sees the latest
/// observation (privileged policies also the episode state) and its action is applied. Errors
/// of the policy name the step.
pub fn policy_step<'e>(env: &'e mut Env, policy: &mut dyn Policy) -> Result<StepResult<'e>, String> {
    let action = policy_action(env, policy)?;
    env.step(&action).map_err(|e| e.to_string())
}

/// The policy's action for `env`'s latest observation (see [`policy_step`]).
fn policy_action(env: &Env, policy: &mut dyn Policy) -> Result<[f64; 7], String> {
    let state = env.state().map_err(|e| e.to_string())?;
    policy.act_with_state(env.observation(), &state).map_err(|e| format!("step {}: {e}", env.observation().step))
}

/// Runs every spec with policies made by `make` (one per worker thread, kept across its
/// episodes) in environments configured by `config`, writing records as [`runner::run`] does.
/// A policy that cannot be made (a server that refuses the connection) makes error records,
/// which a resumed run retries.
pub fn run_episodes<M>(
    specs: &[EpisodeSpec],
    make: M,
    config: EnvConfig,
    rollout_options: &RolloutOptions,
    options: &RunOptions,
) -> Result<RunSummary, RunError>
where
    M: Fn() -> Result<Box<dyn Policy>, String> + Sync,
{
    let look = super::scenes::recorded_look(config.cue_facing);
    let workers: Workers<Box<dyn Policy>> = Workers::new(config);
    runner::run(
        specs,
        |spec| {
            let clip = rollout_options.film.clips.get(&spec.key());
            let episode = |env: &mut Env, p: &mut Box<dyn Policy>| match clip {
                Some(path) => rollout_filmed(env.config(), &mut **p, spec, rollout_options, path),
                None => rollout(env, &mut **p, spec, rollout_options),
            };
            workers.with(&make, episode).unwrap_or_else(|message| EpisodeRecord {
                version: RESULTS_VERSION,
                spec: spec.clone(),
                policy: options.policy.clone(),
                outcome: Outcome::Error { message: format!("policy {}: {message}", options.policy) },
                wall_ms: 0.0,
                set: options.set,
                look: look.clone(),
            })
        },
        options,
    )
}

/// Environments and policies kept between the episodes a worker thread runs (renderer
/// buffers, policy connections), handed out one per running episode.
pub struct Workers<P> {
    config: EnvConfig,
    idle: Mutex<Vec<(Env, P)>>,
}

impl<P> Workers<P> {
    pub fn new(config: EnvConfig) -> Workers<P> {
        Workers { config, idle: Mutex::new(Vec::new()) }
    }

    /// Runs `f` with an idle environment and policy, or new ones made with `make`.
    pub fn with<T, E>(&self, make: impl FnOnce() -> Result<P, E>, f: impl FnOnce(&mut Env, &mut P) -> T) -> Result<T, E> {
        let taken = self.idle.lock().unwrap_or_else(|p| p.into_inner()).pop();
        let (mut env, mut policy) = match taken {
            Some(pair) => pair,
            None => (Env::new(self.config.clone()), make()?),
        };
        let out = f(&mut env, &mut policy);
        self.idle.lock().unwrap_or_else(|p| p.into_inner()).push((env, policy));
        Ok(out)
    }
}
