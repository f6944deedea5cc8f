//! A served policy's observations are drawn only where it asks its server: between requests it
//! plays out its action chunk, and the rollout leaves the cameras alone. What the server
//! receives, and the episode's record, are the same as with every step drawn.

use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::{Arc, Mutex};

use vifo_protocols::benchmark::specs::spec;
use vifo_protocols::env::rollout::{RolloutOptions, rollout};
use vifo_protocols::env::{Env, EnvConfig};
use vifo_protocols::serving::{ModelInput, Profile, ServedPolicy, Transport};
use vifo_protocols::spec::{EpisodeRecord, Outcome, Protocol, TaskRef};
use vifo_protocols::PolicyError;
use vifo_scenes::view::CameraName;

/// What the server was sent: the step and a hash of both images, per request.
type Seen = Arc<Mutex<Vec<(usize, u64)>>>;

/// A server that answers a chunk of ten actions sweeping the arm around, so that the images
/// of consecutive requests differ (a stale image would show).
struct Sweep(Seen);

impl Transport for Sweep {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let mut h = DefaultHasher::new();
        (&input.image.data, &input.wrist.data, input.step).hash(&mut h);
        self.0.lock().unwrap().push((input.step, h.finish()));
        Ok((0..10)
            .map(|k| {
                let t = (input.step + k) as f64 * 0.15;
                [0.6 * t.sin(), 0.6 * t.cos(), 0.3 * (0.5 * t).sin(), 0.0, 0.0, 0.2 * t.cos(), if t.sin() > 0.0 { 1.0 } else { -1.0 }]
            })
            .collect())
    }
}

/// Runs libero_spatial task 0 (220 steps) at 64² with pi0.5's profile, but replanning every 3
/// steps, so that the episode ends inside a chunk; returns the record, what the server saw,
/// and the environment.
fn episode(draw_every_step: bool) -> (EpisodeRecord, Vec<(usize, u64)>, Env) {
    let seen = Seen::default();
    let profile = Profile { replan_steps: 3, ..Profile::named("pi05").unwrap().clone() };
    let mut policy = ServedPolicy::new(profile, "sweep".into(), Box::new(Sweep(seen.clone())));
    let task = TaskRef { suite: "libero_spatial".into(), index: 0 };
    let spec = spec(&task, Protocol::Original, None, 0, 0).unwrap();
    let mut env = Env::new(EnvConfig { size: 64, cameras: CameraName::ALL.to_vec(), ..EnvConfig::default() });
    let options = RolloutOptions { draw_every_step, ..RolloutOptions::default() };
    let record = rollout(&mut env, &mut policy, &spec, &options);
    let seen = seen.lock().unwrap().clone();
    (record, seen, env)
}

#[test]
fn a_chunked_policy_is_drawn_for_only_the_steps_it_sends() {
    let (every, every_seen, every_env) = episode(true);
    let (lazy, lazy_seen, mut lazy_env) = episode(false);
    assert!(matches!(every.outcome, Outcome::Completed { steps: 220, .. }), "{:?}", every.outcome);
    assert_eq!(every.outcome, lazy.outcome);
    // The server got the same images at the same steps: 74 requests, at steps 0, 3, ..., 219.
    assert_eq!(every_seen.len(), 74);
    assert_eq!(every_seen, lazy_seen);
    assert_eq!(every_seen.iter().map(|s| s.1).collect::<std::collections::HashSet<_>>().len(), 74, "the arm must move");
    // Every step drawn: the reset and 220 steps. Only what is looked at: the reset, the 73
    // later requests, and the episode's last observation (two actions of its chunk unused).
    assert_eq!(every_env.draws(), 221);
    assert_eq!(lazy_env.draws(), 75);
    assert_eq!(every_env.observation(), lazy_env.observation());
    // Asking again for a drawn state does not draw it again; a state changed from outside is
    // drawn again.
    lazy_env.render().unwrap();
    assert_eq!(lazy_env.draws(), 75);
    lazy_env.sim_mut().unwrap();
    lazy_env.render().unwrap();
    assert_eq!(lazy_env.draws(), 76);
}
