//! The future a ghost or a goal picture shows: the scripted expert achieving the cue's goals on
//! a fork of the episode, recording the manipulated object's pose at every step and handing
//! out the states worth a picture.
//!
//! A demonstration depends only on the start state, the goals and what is tracked, and every
//! cue protocol of every ghost and picture variant of a task starts from the same shipped state:
//! [`recorded`] keeps finished recordings for the life of the process, so a benchmark run
//! simulates each demonstration once instead of once per episode (a quarter of the expert-cue
//! run's physics). Recordings are pure functions of their key, so sharing them between threads
//! changes no result.

use std::collections::{BTreeMap, VecDeque};
use std::sync::{Arc, Mutex};

use serde::Serialize;
use vifo_cues::RgbaImage;
use vifo_robots::spatial::Pose;
use vifo_expert::Expert;
use vifo_render::Renderer;
use vifo_scenes::sim::Sim;
use vifo_scenes::view::SceneView;
use vifo_scenes::task::Atom;

use super::SceneCueError;

/// Steps the expert may take when the task belongs to no suite (the longest suite budget).
pub const DEFAULT_STEP_CAP: usize = 520;
/// Steps to wait after the expert is done before the demonstration is called finished (things
/// settle into their goal relations).
const SETTLE_AFTER_DONE: usize = 20;
/// Height (m) the manipulated object must rise above its start to count as lifted.
const LIFTED: f64 = 0.05;

/// How the demonstration ended, for the caller to log: a failed one still gives ghosts and
/// pictures, of the states it reached.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DemoOutcome {
    /// Every goal atom held at the end.
    pub success: bool,
    /// Control steps run.
    pub steps: usize,
    /// Why the expert gave up or could not finish (`None` on success).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// A finished demonstration.
pub struct Demo {
    pub outcome: DemoOutcome,
    /// Root pose of the tracked entity at the start and after every step.
    pub track: Vec<Pose>,
}

/// A demonstration with the pictures taken along it (empty when none were asked for).
pub struct Recording {
    pub demo: Demo,
    pub pictures: Vec<RgbaImage>,
}

/// Recordings kept; beyond this the oldest is dropped (a run over every task and initial state
/// needs 2 per task and state, each about 1 MB with pictures).
const KEPT: usize = 256;

/// Everything a recording depends on: the task, the exact start (state bits and step count),
/// the goals, the tracked entity, the step cap and what the pictures are drawn with (`None`:
/// no pictures).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct RecordingKey {
    task: String,
    start: (u64, usize),
    goals: String,
    tracked: Option<usize>,
    cap: usize,
    pictures: Option<PictureKey>,
}

/// What a recording's pictures are drawn with: their size, the view's look and instance count
/// (a cue object's face is an attached instance) and the renderer's options, so that a caller
/// drawing with another look or renderer in the same process never gets these pictures.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct PictureKey {
    size: (u32, u32),
    look: String,
    instances: usize,
    options: String,
}

impl PictureKey {
    pub fn new(size: (u32, u32), view: &SceneView, renderer: &Renderer) -> PictureKey {
        PictureKey { size, look: view.look().to_string(), instances: view.scene().instances.len(), options: format!("{:?}", renderer.options()) }
    }
}

impl RecordingKey {
    pub fn new(sim: &Sim, goals: &[Atom], tracked: Option<usize>, cap: usize, pictures: Option<PictureKey>) -> RecordingKey {
        RecordingKey {
            task: sim.model().task.label(),
            start: (sim.world().fingerprint().0, sim.steps()),
            goals: format!("{goals:?}"),
            tracked,
            cap,
            pictures,
        }
    }
}

/// The recordings kept, and their keys oldest first.
type Kept = (BTreeMap<RecordingKey, Arc<Recording>>, VecDeque<RecordingKey>);

/// The recording of `key`, made with `record` the first time it is asked for (errors are not
/// kept). Two threads asking at once may both record; they get equal recordings.
pub fn recorded(key: RecordingKey, record: impl FnOnce() -> Result<Recording, SceneCueError>) -> Result<Arc<Recording>, SceneCueError> {
    static KEEP: Mutex<Kept> = Mutex::new((BTreeMap::new(), VecDeque::new()));
    let lock = || KEEP.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(r) = lock().0.get(&key) {
        return Ok(r.clone());
    }
    let made = Arc::new(record()?);
    let mut keep = lock();
    let (map, order) = &mut *keep;
    if map.insert(key.clone(), made.clone()).is_none() {
        order.push_back(key);
        while order.len() > KEPT {
            if let Some(old) = order.pop_front() {
                map.remove(&old);
            }
        }
    }
    Ok(made)
}

/// Runs the expert on a fork of `sim` until `goals` hold, it gives up, or `cap` steps.
/// `keyframe` sees the states worth a picture, in time order: the moment the tracked object is
/// first lifted, every moment a goal atom becomes true (the end of a step), and the final state.
pub fn run(
    sim: &Sim,
    cue: &str,
    goals: &[Atom],
    tracked: Option<usize>,
    cap: usize,
    mut keyframe: impl FnMut(&Sim) -> Result<(), SceneCueError>,
) -> Result<Demo, SceneCueError> {
    let predicate = |source| SceneCueError::Predicate { cue: cue.to_string(), source };
    let mut fork = sim.fork();
    let mut expert = Expert::for_goals(&fork, goals).map_err(|source| SceneCueError::Plan { cue: cue.to_string(), source })?;
    let pose = |s: &Sim| tracked.map_or(Pose::IDENTITY, |e| s.entity_pose(e));
    let mut track = vec![pose(&fork)];
    let start_z = track[0].pos.z;
    let mut lifted = tracked.is_none();
    let mut held: Vec<bool> = goals.iter().map(|a| fork.holds(a)).collect::<Result<_, _>>().map_err(predicate)?;
    let mut idle = 0;
    let mut success = held.iter().all(|h| *h);
    while !success && track.len() <= cap && idle < SETTLE_AFTER_DONE && expert.failure().is_none() {
        let action = expert.act(&fork);
        fork.step(&action);
        track.push(pose(&fork));
        if expert.finished() {
            idle += 1;
        }
        let mut picture = false;
        if !lifted && track[track.len() - 1].pos.z > start_z + LIFTED {
            lifted = true;
            picture = true;
        }
        for (atom, was) in goals.iter().zip(held.iter_mut()) {
            let now = fork.holds(atom).map_err(predicate)?;
            picture |= now && !*was;
            *was = now;
        }
        success = held.iter().all(|h| *h);
        if picture && !success {
            keyframe(&fork)?;
        }
    }
    keyframe(&fork)?;
    let failure = match (success, expert.failure()) {
        (true, _) => None,
        (false, Some(why)) => Some(why.to_string()),
        (false, None) if track.len() > cap => Some(format!("goals not reached within {cap} steps")),
        (false, None) => Some("the expert finished but the goals do not hold".to_string()),
    };
    Ok(Demo { outcome: DemoOutcome { success, steps: track.len() - 1, failure }, track })
}

/// `k` poses along the track, evenly spaced by the distance the object travelled (so pauses
/// while the gripper approaches take no ghosts), the final pose included and the start left
/// out (the object itself is there). A track that never moved gives `k` copies of its end.
pub fn spaced_poses(track: &[Pose], k: usize) -> Vec<Pose> {
    let Some(last) = track.last() else { return Vec::new() };
    let mut travelled = Vec::with_capacity(track.len());
    let mut total = 0.0;
    travelled.push(0.0);
    for w in track.windows(2) {
        total += (w[1].pos - w[0].pos).norm();
        travelled.push(total);
    }
    (1..=k)
        .map(|i| {
            if total <= 0.0 {
                return *last;
            }
            let goal = total * i as f64 / k as f64;
            let at = travelled.iter().position(|&d| d >= goal - 1e-12).unwrap_or(track.len() - 1);
            track[at]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use vifo_robots::spatial::Vec3;

    fn at(x: f64) -> Pose {
        Pose { pos: Vec3::new(x, 0.0, 0.0), ..Pose::IDENTITY }
    }

    #[test]
    fn poses_are_spaced_by_distance_and_end_at_the_last() {
        // Idle for three steps, then 0.1 m per step to x = 0.4.
        let track: Vec<Pose> = [0.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4].map(at).to_vec();
        let xs: Vec<f64> = spaced_poses(&track, 4).iter().map(|p| p.pos.x).collect();
        assert_eq!(xs, [0.1, 0.2, 0.3, 0.4]);
        let xs: Vec<f64> = spaced_poses(&track, 2).iter().map(|p| p.pos.x).collect();
        assert_eq!(xs, [0.2, 0.4]);
    }

    #[test]
    fn a_recording_is_made_once_per_key() {
        let task = vifo_scenes::task("libero_object", 0).unwrap();
        let sim = Sim::new(vifo_scenes::sim::SceneModel::build(task).unwrap());
        let made = std::cell::Cell::new(0);
        let record = || {
            made.set(made.get() + 1);
            let outcome = DemoOutcome { success: false, steps: 0, failure: None };
            Ok(Recording { demo: Demo { outcome, track: vec![at(made.get() as f64)] }, pictures: Vec::new() })
        };
        let first = recorded(RecordingKey::new(&sim, &task.goal, None, 7, None), record).unwrap();
        let again = recorded(RecordingKey::new(&sim, &task.goal, None, 7, None), record).unwrap();
        assert!(Arc::ptr_eq(&first, &again));
        assert_eq!(made.get(), 1);
        // Another cap (or start, goals, tracked object, picture size) is another recording.
        let other = recorded(RecordingKey::new(&sim, &task.goal, None, 8, None), record).unwrap();
        assert_eq!((made.get(), other.demo.track[0]), (2, at(2.0)));
        // So are pictures drawn by another renderer.
        let view = SceneView::new(sim.model());
        let plain = Renderer::new(vifo_render::RenderOptions::default());
        let fine = Renderer::new(vifo_render::RenderOptions { supersample: 2, ..Default::default() });
        for renderer in [&plain, &fine, &plain] {
            recorded(RecordingKey::new(&sim, &task.goal, None, 8, Some(PictureKey::new((8, 8), &view, renderer))), record).unwrap();
        }
        assert_eq!(made.get(), 4);
    }

    #[test]
    fn a_still_track_gives_copies_of_its_end_and_an_empty_one_nothing() {
        assert_eq!(spaced_poses(&[at(0.3), at(0.3)], 3), vec![at(0.3); 3]);
        assert!(spaced_poses(&[], 3).is_empty());
    }
}
