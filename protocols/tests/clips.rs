//! Clips of filmed episodes (`env::film`): filming changes no record, writes one frame per due
//! step, draws lazily exactly what step-by-step drawing shows, and a clip that cannot be
//! written costs the episode nothing.

use std::path::{Path, PathBuf};

use vifo_protocols::benchmark::specs::spec;
use vifo_protocols::env::EnvConfig;
use vifo_protocols::env::film::Filming;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::policies::builtin;
use vifo_protocols::report;
use vifo_protocols::runner::{RunOptions, read_records};
use vifo_protocols::spec::{EpisodeRecord, EpisodeSpec, Outcome, Protocol, TaskRef};
use vifo_protocols::{EpisodeState, Observation, Policy, PolicyError};

const SIZE: u32 = 32;

/// The authorized episode of a libero_goal cue instance and the task's original episode.
fn specs() -> Vec<EpisodeSpec> {
    let task = TaskRef { suite: "libero_goal".into(), index: 0 };
    vec![
        spec(&task, Protocol::Authorized, Some("libero_goal/0/F1/caption_bar"), 0, 0).unwrap(),
        spec(&task, Protocol::Original, None, 0, 0).unwrap(),
    ]
}

/// `random`, claiming to look at the images: the environment then draws every step.
struct Looking(Box<dyn Policy>);

impl Policy for Looking {
    fn name(&self) -> String {
        self.0.name()
    }
    fn reset(&mut self) -> Result<(), PolicyError> {
        self.0.reset()
    }
    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError> {
        self.0.act(obs)
    }
    fn act_with_state(&mut self, obs: &Observation, state: &EpisodeState<'_>) -> Result<[f64; 7], PolicyError> {
        self.0.act_with_state(obs, state)
    }
}

/// Runs `specs` with `random` (wrapped in [`Looking`] when `looking`) without cameras, filming
/// the first spec into `clip` when given; returns the records without their wall times.
fn run(specs: &[EpisodeSpec], dir: &Path, clip: Option<&Path>, looking: bool) -> Vec<EpisodeRecord> {
    let path = dir.join(format!("results-{}.jsonl", clip.is_some() as u8 + 2 * looking as u8));
    let config = EnvConfig { size: SIZE, cameras: Vec::new(), ..EnvConfig::default() };
    let options = RunOptions { threads: 1, quiet: true, policy: "random".into(), ..RunOptions::new(&path) };
    let make = || {
        let p = builtin("random").ok_or("no random policy")?;
        Ok::<Box<dyn Policy>, String>(if looking { Box::new(Looking(p)) } else { p })
    };
    let mut film = Filming { size: SIZE, ..Filming::none() };
    film.clips.extend(clip.map(|c| (specs[0].key(), c.to_path_buf())));
    run_episodes(specs, make, config, &RolloutOptions { film, ..RolloutOptions::default() }, &options).unwrap();
    let mut records = read_records(&path).unwrap().records;
    records.sort_by_key(|r| r.spec.key());
    records.iter_mut().for_each(|r| r.wall_ms = 0.0);
    records
}

/// Frames of a GIF file and their size.
fn frames(path: &Path) -> (usize, u16, u16) {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options.read_info(std::fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (decoder.width(), decoder.height());
    let mut n = 0;
    while decoder.read_next_frame().unwrap().is_some() {
        n += 1;
    }
    (n, w, h)
}

fn part(clip: &Path) -> PathBuf {
    PathBuf::from(format!("{}.part", clip.display()))
}

#[test]
fn filming_changes_no_record_and_keeps_every_second_step() {
    let dir = tempfile::tempdir().unwrap();
    let specs = specs();
    let plain = run(&specs, dir.path(), None, false);
    let clip = dir.path().join("clips/random/F1.gif");
    let filmed = run(&specs, dir.path(), Some(&clip), false);
    assert_eq!(plain, filmed, "filming must not change what the episode does");
    assert!(filmed.iter().all(|r| r.look == report::NO_IMAGES), "the policy was sent no images; the clip's frames do not count");
    assert!(!part(&clip).exists(), "the unfinished name is gone");
    let record = filmed.iter().find(|r| r.spec.key() == specs[0].key()).unwrap();
    let Outcome::Completed { steps, .. } = record.outcome else { panic!("{:?}", record.outcome) };
    // Steps 0, 2, 4, ... and the last one.
    let (n, w, h) = frames(&clip);
    assert_eq!(n, steps / 2 + 1 + steps % 2, "{steps} steps");
    assert_eq!((w, h), (2 * SIZE as u16 + 4, SIZE as u16));
    assert_eq!(std::fs::read_dir(dir.path().join("clips/random")).unwrap().count(), 1, "one clip: the filmed episode's");
    // It names the look that drew it (this process draws the built-in one) and the episode.
    let comment = format!("look: built-in; episode: {}", specs[0].key());
    let bytes = std::fs::read(&clip).unwrap();
    assert!(bytes.windows(comment.len()).any(|w| w == comment.as_bytes()), "the clip carries the comment {comment:?}");
}

#[test]
fn lazy_drawing_draws_what_every_step_drawing_shows() {
    let dir = tempfile::tempdir().unwrap();
    let specs = &specs()[..1];
    let (lazy, eager) = (dir.path().join("lazy.gif"), dir.path().join("eager.gif"));
    let a = run(specs, dir.path(), Some(&lazy), false);
    let b = run(specs, dir.path(), Some(&eager), true);
    assert_eq!(a, b);
    assert_eq!(std::fs::read(&lazy).unwrap(), std::fs::read(&eager).unwrap(), "same frames, byte for byte");
}

#[test]
fn a_clip_that_cannot_be_written_costs_the_episode_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let specs = &specs()[..1];
    let plain = run(specs, dir.path(), None, false);
    // The clip's folder would have to be where a file is.
    let blocker = dir.path().join("clips");
    std::fs::write(&blocker, b"not a folder").unwrap();
    let clip = blocker.join("F1.gif");
    assert_eq!(run(specs, dir.path(), Some(&clip), false), plain);
    assert!(!clip.exists() && !part(&clip).exists());
}
