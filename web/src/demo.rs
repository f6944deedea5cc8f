//! The demo's episode: one [`Env`] episode stepped by a built-in policy or by actions from the
//! page, with RGBA frames for canvases and the status the page shows. Plain Rust with string
//! errors, so `vifo web episode` runs exactly this code natively (the state hash check) and
//! the bindings in `lib.rs` only convert types.

use serde::Serialize;
use vifo_cues::{CueSpec, SetName};
use vifo_protocols::benchmark::{builtin_task, instances, language, specs};
use vifo_protocols::env::rollout::policy_step;
use vifo_protocols::env::{Env, EnvConfig, StepResult};
use vifo_protocols::{EpisodeSpec, Policy, Protocol, TaskRef, policies};
use vifo_scenes::task::Atom;
use vifo_scenes::view::{CameraName, ImageOrder};

/// The frame sizes the page offers are between these (the cameras render any square size).
pub const MIN_SIZE: u32 = 32;
pub const MAX_SIZE: u32 = 512;

/// The policy a new demo steps with.
pub const DEFAULT_POLICY: &str = "expert-cue";

/// A built-in task as the task picker lists it.
#[derive(Clone, Debug, Serialize)]
pub struct TaskInfo {
    /// `libero_goal/3`.
    pub key: String,
    pub suite: String,
    pub index: usize,
    pub instruction: String,
}

/// A cue instance as the cue picker lists it.
#[derive(Clone, Debug, Serialize)]
pub struct InstanceInfo {
    /// `libero_goal/3/F2/straight_arrow_red`.
    pub id: String,
    /// `F2`.
    pub family: String,
    /// `geometric symbol`.
    pub family_name: String,
    pub variant: String,
    /// The instruction the cue conveys.
    pub conveys: String,
    /// Whether the paper's instance set holds it (every instance is in the `full` set).
    pub paper: bool,
}

/// One goal atom of a scored task and whether it holds now.
#[derive(Clone, Debug, Serialize)]
pub struct Predicate {
    /// `language` or `cue`: whose goal the atom belongs to.
    pub task: &'static str,
    pub atom: String,
    pub holds: bool,
}

/// What the page shows about the running episode.
#[derive(Clone, Debug, Serialize)]
pub struct Status {
    pub task: String,
    /// The language condition (protocol): `original`, `authorized`, `conflict`, `no_language`.
    pub condition: &'static str,
    pub instance: Option<String>,
    pub init: usize,
    /// Decimal, because JavaScript numbers cannot hold every u64.
    pub seed: String,
    pub instruction: String,
    /// The cue as text: family, variant and what it conveys; `None` without a cue.
    pub cue: Option<String>,
    pub policy: String,
    pub steps: usize,
    pub budget: usize,
    pub done: bool,
    pub language_success: Option<bool>,
    pub cue_success: Option<bool>,
    pub predicates: Vec<Predicate>,
    /// The physics state fingerprint as 16 hex digits ([`Env::state_hash`]).
    pub state_hash: String,
}

/// The 40 built-in tasks in suite order.
pub fn tasks() -> Vec<TaskInfo> {
    vifo_scenes::all_tasks()
        .filter_map(|t| {
            let (suite, index) = (t.suite.clone()?, t.index?);
            Some(TaskInfo { key: format!("{suite}/{index}"), suite, index, instruction: t.instruction.clone() })
        })
        .collect()
}

/// The cue instances of `task` (the `full` set, each marked whether the paper set holds it).
pub fn instances(task: &str) -> Result<Vec<InstanceInfo>, String> {
    let task = parse_task(task)?;
    let key = task.to_string();
    let paper: Vec<String> = instances::all(SetName::Paper).iter().filter(|s| s.task == key).map(CueSpec::id).collect();
    Ok(instances::all(SetName::Full)
        .iter()
        .filter(|s| s.task == key)
        .map(|s| {
            let id = s.id();
            InstanceInfo {
                paper: paper.contains(&id),
                id,
                family: format!("{:?}", s.family),
                family_name: s.family.name().to_string(),
                variant: s.variant.clone(),
                conveys: s.instruction.clone(),
            }
        })
        .collect())
}

/// The protocol a language condition names.
pub fn condition(name: &str) -> Result<Protocol, String> {
    Protocol::ALL.into_iter().find(|p| p.name() == name).ok_or_else(|| {
        let known: Vec<&str> = Protocol::ALL.iter().map(|p| p.name()).collect();
        format!("unknown language condition {name:?}; expected one of {}", known.join(", "))
    })
}

fn parse_task(task: &str) -> Result<TaskRef, String> {
    let parsed: TaskRef = task.parse()?;
    builtin_task(&parsed).map_err(|e| e.to_string())?;
    Ok(parsed)
}

fn make_policy(name: &str) -> Result<Box<dyn Policy>, String> {
    policies::builtin(name)
        .ok_or_else(|| format!("unknown policy {name:?}; expected one of {}", policies::NAMES.join(", ")))
}

/// The running episode and what is needed to show it.
struct Running {
    spec: EpisodeSpec,
    cue: Option<&'static CueSpec>,
    language_goal: Vec<Atom>,
    cue_goal: Vec<Atom>,
    budget: usize,
    steps: usize,
    done: bool,
    success: (Option<bool>, Option<bool>),
}

/// What a step changed, copied out of the [`StepResult`] that borrows the environment.
struct Outcome {
    steps: usize,
    done: bool,
    success: (Option<bool>, Option<bool>),
}

impl Outcome {
    fn of(step: &StepResult<'_>) -> Outcome {
        Outcome { steps: step.steps, done: step.done, success: (step.language_success, step.cue_success) }
    }
}

/// One demo: an environment, the policy that steps it and the episode it runs.
pub struct Demo {
    env: Env,
    policy: Box<dyn Policy>,
    policy_name: String,
    running: Option<Running>,
    /// RGBA copy of the last frame asked for (canvases take RGBA).
    rgba: Vec<u8>,
}

impl Demo {
    /// A demo rendering `size`² frames of agentview and, with `wrist`, the wrist camera.
    pub fn new(size: u32, wrist: bool) -> Result<Demo, String> {
        if !(MIN_SIZE..=MAX_SIZE).contains(&size) {
            return Err(format!("frame size {size} is outside {MIN_SIZE}..={MAX_SIZE}"));
        }
        let cameras = if wrist { CameraName::ALL.to_vec() } else { vec![CameraName::AgentView] };
        Ok(Demo {
            env: Env::new(EnvConfig { size, order: ImageOrder::Upright, cameras, ..EnvConfig::default() }),
            policy: make_policy(DEFAULT_POLICY)?,
            policy_name: DEFAULT_POLICY.to_string(),
            running: None,
            rgba: Vec::new(),
        })
    }

    pub fn size(&self) -> u32 {
        self.env.config().size
    }

    /// Steps with the built-in policy `name` from now on (a fresh one: an expert plans at its
    /// next step from the current state).
    pub fn set_policy(&mut self, name: &str) -> Result<(), String> {
        self.policy = make_policy(name)?;
        self.policy_name = name.to_string();
        Ok(())
    }

    /// Starts an episode of `task` (`libero_goal/3`) from shipped initial state `init` under
    /// the language condition `condition`, with cue instance `cue` (required by every condition
    /// but `original`) and `seed` (the benchmark's stable seed of the episode when `None`).
    /// Bad arguments leave the running episode as it was.
    pub fn reset(&mut self, task: &str, init: usize, cue: Option<&str>, condition_name: &str, seed: Option<u64>) -> Result<Status, String> {
        let task = parse_task(task)?;
        let protocol = condition(condition_name)?;
        if init >= specs::INIT_STATES {
            // `specs::spec` would wrap it round (episode numbers do); a page asking for state 99 means a mistake.
            return Err(format!("initial state {init} is outside 0..{}", specs::INIT_STATES));
        }
        let cue = if protocol.uses_cue() { cue } else { None };
        let mut spec = specs::spec(&task, protocol, cue, init, 0).map_err(|e| e.to_string())?;
        if let Some(seed) = seed {
            spec.seed = seed;
        }
        // From here on the old episode is gone (the environment drops it first).
        self.running = None;
        self.env.reset(&spec).map_err(|e| format!("reset: {e}"))?;
        self.policy.reset().map_err(|e| format!("policy {}: {e}", self.policy_name))?;
        let builtin = builtin_task(&task).map_err(|e| e.to_string())?;
        let language_goal =
            language::language_task(protocol, builtin).map_err(|e| e.to_string())?.map(|l| l.goal).unwrap_or_default();
        let cue_spec = spec.instance.as_deref().map(instances::find).transpose().map_err(|e| e.to_string())?;
        self.running = Some(Running {
            cue: cue_spec,
            cue_goal: if cue_spec.is_some() { builtin.goal.clone() } else { Vec::new() },
            language_goal,
            budget: vifo_scenes::suite(&task.suite).map_or(0, |s| s.max_steps as usize),
            steps: 0,
            done: false,
            success: (None, None),
            spec,
        });
        self.status()
    }

    /// One control step with the current policy.
    pub fn step(&mut self) -> Result<Status, String> {
        self.check_running()?;
        let outcome = policy_step(&mut self.env, &mut *self.policy).map(|s| Outcome::of(&s));
        self.record(outcome)
    }

    /// One control step with a 7-D action `[dx, dy, dz, dax, day, daz, gripper]`; a wrong length
    /// or a non-finite value is an error and changes nothing.
    pub fn step_action(&mut self, action: &[f64]) -> Result<Status, String> {
        self.check_running()?;
        let outcome = self.env.step(action).map(|s| Outcome::of(&s)).map_err(|e| e.to_string());
        self.record(outcome)
    }

    fn check_running(&self) -> Result<(), String> {
        match &self.running {
            None => Err("no episode: call reset first".into()),
            Some(r) if r.done => Err(format!("the episode is over ({} steps); call reset", r.steps)),
            Some(_) => Ok(()),
        }
    }

    fn record(&mut self, outcome: Result<Outcome, String>) -> Result<Status, String> {
        let Outcome { steps, done, success } = outcome?;
        let running = self.running.as_mut().ok_or("no episode: call reset first")?;
        running.steps = steps;
        running.done = done;
        running.success = success;
        self.status()
    }

    /// The running episode's status.
    pub fn status(&self) -> Result<Status, String> {
        let r = self.running.as_ref().ok_or("no episode: call reset first")?;
        let state = self.env.state().map_err(|e| e.to_string())?;
        let mut predicates = Vec::new();
        for (task, goal) in [("language", &r.language_goal), ("cue", &r.cue_goal)] {
            for atom in goal {
                let holds = state.sim.holds(atom).map_err(|e| format!("predicate {atom}: {e}"))?;
                predicates.push(Predicate { task, atom: atom.to_string(), holds });
            }
        }
        Ok(Status {
            task: r.spec.task.to_string(),
            condition: r.spec.protocol.name(),
            instance: r.spec.instance.clone(),
            init: r.spec.init,
            seed: r.spec.seed.to_string(),
            instruction: r.spec.instruction.clone(),
            cue: r.cue.map(|c| format!("{:?} {} · {} · conveys \"{}\"", c.family, c.family.name(), c.variant, c.instruction)),
            policy: self.policy_name.clone(),
            steps: r.steps,
            budget: r.budget,
            done: r.done,
            language_success: r.success.0,
            cue_success: r.success.1,
            predicates,
            state_hash: format!("{:016x}", self.env.state_hash().unwrap_or(0)),
        })
    }

    /// A hash of the latest frames, agentview then the wrist camera, as 16 hex digits
    /// (FNV-1a of their RGB bytes, cue included): the page's and a native run's frames are the
    /// same when these are, which checks the rasterizer and the cue drawing across the two
    /// targets as the state hash checks the physics.
    pub fn frame_hash(&self) -> Result<String, String> {
        if self.running.is_none() {
            return Err("no episode: call reset first".into());
        }
        let obs = self.env.observation();
        let mut bytes = Vec::with_capacity(obs.agentview.data.len() + obs.wrist.data.len());
        bytes.extend_from_slice(&obs.agentview.data);
        bytes.extend_from_slice(&obs.wrist.data);
        Ok(format!("{:016x}", vifo_cues::hash::fnv1a64(&bytes)))
    }

    /// The latest frame of `camera` as RGBA rows, top row first (`size()`² pixels).
    pub fn frame_rgba(&mut self, camera: CameraName) -> Result<&[u8], String> {
        if self.running.is_none() {
            return Err("no episode: call reset first".into());
        }
        let image = self.env.observation().image(camera);
        if image.data.is_empty() {
            return Err(format!("camera {camera:?} is not rendered by this demo (create it with the wrist camera on)"));
        }
        self.rgba.clear();
        self.rgba.reserve(image.data.len() / 3 * 4);
        for px in image.data.chunks_exact(3) {
            self.rgba.extend_from_slice(&[px[0], px[1], px[2], 255]);
        }
        Ok(&self.rgba)
    }
}

/// A seed written as decimal digits, 0 to 2^64-1 (what `vifo web episode` prints).
pub fn parse_seed(text: &str) -> Result<u64, String> {
    let digits = !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit());
    digits.then(|| text.parse().ok()).flatten().ok_or_else(|| format!("seed must be decimal digits of a number from 0 to 2^64-1, got {text:?}"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn seeds_are_read_as_decimal_digits_of_64_bits() {
        assert_eq!(parse_seed("3309794020868337508"), Ok(3309794020868337508));
        assert_eq!(parse_seed("18446744073709551615"), Ok(u64::MAX));
        for bad in ["", "1e3", "0x10", "-1", " 7", "18446744073709551616"] {
            assert!(parse_seed(bad).unwrap_err().contains("decimal digits"), "{bad}");
        }
    }

    use super::*;

    const CUE: &str = "libero_goal/0/F1/caption_bar";

    #[test]
    fn lists_forty_tasks_and_their_instances() {
        let tasks = tasks();
        assert_eq!(tasks.len(), 40);
        let goal0 = instances("libero_goal/0").unwrap();
        assert!(goal0.iter().any(|i| i.id == CUE && i.paper));
        assert!(goal0.iter().all(|i| i.id.starts_with("libero_goal/0/")));
        assert!(instances("libero_goal/10").unwrap_err().contains("unknown task"));
        assert!(instances("nonsense").unwrap_err().contains("expected <suite>/<index>"));
    }

    #[test]
    fn bad_input_is_explained_and_keeps_the_episode() {
        let mut demo = Demo::new(64, true).unwrap();
        assert!(Demo::new(8, true).err().unwrap().contains("frame size 8"));
        assert!(demo.step().unwrap_err().contains("call reset first"));
        assert!(demo.reset("libero_goal/0", 0, Some("libero_goal/0/F9/nothing"), "authorized", None).unwrap_err().contains("unknown cue instance"));
        assert!(demo.reset("libero_goal/0", 0, None, "authorized", None).unwrap_err().contains("needs a cue instance"));
        assert!(demo.reset("libero_goal/0", 0, Some(CUE), "shouting", None).unwrap_err().contains("unknown language condition"));
        assert!(demo.reset("libero_goal/1", 0, Some(CUE), "authorized", None).unwrap_err().contains("belongs to task"));
        assert!(demo.reset("libero_goal/0", 99, Some(CUE), "authorized", None).unwrap_err().contains("initial state 99 is outside"));
        assert!(demo.set_policy("clever").unwrap_err().contains("unknown policy"));
        demo.reset("libero_goal/0", 0, None, "original", None).unwrap();
        demo.step_action(&[0.0, 0.0, 0.1, 0.0, 0.0, 0.0, -1.0]).unwrap();
        assert!(demo.reset("libero_goal/0", 0, Some("libero_goal/0/F9/nothing"), "authorized", None).is_err());
        assert_eq!(demo.status().unwrap().steps, 1, "a rejected reset dropped the running episode");
        let start = demo.reset("libero_goal/0", 0, Some(CUE), "authorized", Some(7)).unwrap();
        assert_eq!(start.seed, "7");
        assert!(start.cue.as_deref().unwrap().contains("caption_bar"));
        assert!(demo.step_action(&[0.0; 6]).unwrap_err().contains("invalid action"));
        assert!(demo.step_action(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0]).unwrap_err().contains("invalid action"));
        let after = demo.status().unwrap();
        assert_eq!((after.steps, &after.state_hash), (0, &start.state_hash), "a bad action changed the episode");
        let moved = demo.step_action(&[0.5, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap();
        assert_eq!(moved.steps, 1);
        assert_ne!(moved.state_hash, start.state_hash);
        assert_eq!(demo.frame_rgba(CameraName::EyeInHand).unwrap().len(), 64 * 64 * 4);
        let mut agent_only = Demo::new(64, false).unwrap();
        agent_only.reset("libero_goal/0", 0, None, "original", None).unwrap();
        assert!(agent_only.frame_rgba(CameraName::EyeInHand).unwrap_err().contains("not rendered"));
    }

    #[test]
    fn same_episode_same_hash() {
        let run = || {
            let mut demo = Demo::new(32, false).unwrap();
            demo.set_policy("random").unwrap();
            demo.reset("libero_goal/0", 1, Some(CUE), "no_language", None).unwrap();
            (0..5).map(|_| demo.step().unwrap().state_hash).last().unwrap()
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn frame_hash_follows_the_frames() {
        let mut demo = Demo::new(32, true).unwrap();
        assert!(demo.frame_hash().unwrap_err().contains("call reset first"));
        demo.reset("libero_goal/0", 0, None, "original", None).unwrap();
        let plain = demo.frame_hash().unwrap();
        assert_eq!(plain.len(), 16);
        demo.reset("libero_goal/0", 0, Some(CUE), "authorized", None).unwrap();
        let cued = demo.frame_hash().unwrap();
        assert_ne!(cued, plain, "the cue is part of the frames");
        demo.step_action(&[0.0, 0.0, 0.5, 0.0, 0.0, 0.0, -1.0]).unwrap();
        assert_ne!(demo.frame_hash().unwrap(), cued, "the arm moved");
        demo.reset("libero_goal/0", 0, Some(CUE), "authorized", None).unwrap();
        assert_eq!(demo.frame_hash().unwrap(), cued);
    }
}
