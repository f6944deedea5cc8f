//! The environment: reset builds the observation the protocol prescribes, steps reject bad
//! actions without touching the simulation, the episode ends at the suite's budget, and the
//! same spec gives the same bytes.

use vifo_protocols::benchmark::specs::spec;
use vifo_cues::{FrameInputs, Inserter, RgbImage};
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::env::{CueDrawing, CueFacing, Env, EnvConfig, EnvError, SETTLE_STEPS};
use vifo_protocols::policies::builtin;
use vifo_protocols::report;
use vifo_protocols::runner::{RunOptions, read_records};
use vifo_protocols::spec::{EpisodeSpec, Protocol, TaskRef};
use vifo_scenes::view::{CameraName, ImageOrder};

fn small(cameras: &[CameraName]) -> EnvConfig {
    EnvConfig { size: 64, cameras: cameras.to_vec(), ..EnvConfig::default() }
}

fn task(suite: &str, index: usize) -> TaskRef {
    TaskRef { suite: suite.into(), index }
}

const INSTANCE: &str = "libero_goal/0/F1/caption_bar";

fn goal0(protocol: Protocol) -> EpisodeSpec {
    let instance = protocol.uses_cue().then_some(INSTANCE);
    spec(&task("libero_goal", 0), protocol, instance, 3, 0).unwrap()
}

#[test]
fn reset_gives_the_protocols_observation() {
    let mut env = Env::new(small(&CameraName::ALL));
    let plain = env.reset(&goal0(Protocol::Original)).unwrap().agentview.clone();
    for protocol in Protocol::ALL {
        let s = goal0(protocol);
        let obs = env.reset(&s).unwrap().clone();
        // The same scene, with the cue drawn on it exactly when the protocol has one.
        assert_eq!(obs.agentview.data != plain.data, protocol.uses_cue(), "{protocol:?}");
        assert_eq!(obs.instruction, s.instruction);
        assert_eq!(obs.step, 0);
        for image in [&obs.agentview, &obs.wrist] {
            assert_eq!((image.width, image.height, image.data.len()), (64, 64, 64 * 64 * 3));
            // A rendered scene, not a blank buffer.
            assert!(image.data.iter().any(|&b| b != image.data[0]));
        }
        let state = obs.state8();
        assert!(state.iter().all(|v| v.is_finite()));
        // The hand starts above the table, fingers open (LIBERO's settle action opens them).
        assert!(state[2] > 0.8, "eef z {}", state[2]);
        assert!(state[6] > 0.01 && state[7] < -0.01, "fingers {:?}", &state[6..]);
        let drawing = env.cue_drawing();
        if protocol.uses_cue() {
            assert_ne!(drawing, CueDrawing::NoCue);
        } else {
            assert_eq!(drawing, CueDrawing::NoCue);
        }
    }
    assert_eq!(goal0(Protocol::Authorized).instruction, Protocol::AUTHORIZED_INSTRUCTION);
    assert_eq!(goal0(Protocol::NoLanguage).instruction, "");
}

#[test]
fn the_same_spec_gives_the_same_bytes_and_the_order_option_flips_rows() {
    let s = goal0(Protocol::Original);
    let mut a = Env::new(small(&[CameraName::AgentView]));
    let first = a.reset(&s).unwrap().clone();
    let after = a.step(&[0.3, -0.2, 0.1, 0.0, 0.0, 0.1, 1.0]).unwrap().observation.clone();
    let mut b = Env::new(EnvConfig { order: ImageOrder::BottomUp, ..small(&[CameraName::AgentView]) });
    // A reused environment (another episode in between) gives the same episode again.
    b.reset(&goal0(Protocol::NoLanguage)).unwrap();
    let flipped = b.reset(&s).unwrap().clone();
    let after_b = b.step(&[0.3, -0.2, 0.1, 0.0, 0.0, 0.1, 1.0]).unwrap().observation.clone();
    assert_eq!(first.state8(), flipped.state8());
    assert_eq!(after.state8(), after_b.state8());
    assert_eq!(after.joint_pos, after_b.joint_pos);
    let row = 64 * 3;
    for r in 0..64 {
        assert_eq!(first.agentview.data[r * row..(r + 1) * row], flipped.agentview.data[(63 - r) * row..(64 - r) * row]);
    }
    // Only the configured camera is rendered.
    assert_eq!(first.wrist.data.len(), 0);
    assert_ne!(first.state8(), after.state8());
}

#[test]
fn bad_actions_are_errors_that_leave_the_episode_untouched() {
    let mut env = Env::new(small(&[]));
    env.reset(&goal0(Protocol::Original)).unwrap();
    let before = env.observation().clone();
    assert!(matches!(env.step(&[0.0; 6]), Err(EnvError::Action(_))));
    assert!(matches!(env.step(&[0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]), Err(EnvError::Action(_))));
    assert!(matches!(env.step(&[0.0, 0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0]), Err(EnvError::Action(_))));
    assert_eq!(env.observation(), &before);
    let r = env.step(&[0.0; 7]).unwrap();
    assert_eq!(r.steps, 1);
}

#[test]
fn episodes_end_at_the_suites_budget() {
    let s = spec(&task("libero_spatial", 0), Protocol::Original, None, 0, 0).unwrap();
    let mut env = Env::new(small(&[]));
    env.reset(&s).unwrap();
    let mut last = None;
    for i in 1..=220 {
        let r = env.step(&[0.0; 7]).unwrap();
        assert_eq!(r.steps, i);
        assert_eq!(r.done, i == 220, "step {i}");
        assert_eq!((r.language_success, r.cue_success), (Some(false), None));
        last = Some(r.done);
    }
    assert_eq!(last, Some(true));
    assert!(matches!(env.step(&[0.0; 7]), Err(EnvError::Finished { steps: 220 })));
    assert_eq!(SETTLE_STEPS, 10);
}

#[test]
fn specs_that_do_not_fit_the_protocol_are_errors() {
    let mut env = Env::new(small(&[]));
    let mut s = goal0(Protocol::Authorized);
    s.instruction = "put the bowl on the stove".into();
    assert!(matches!(env.reset(&s), Err(EnvError::Instruction { .. })));
    let mut s = goal0(Protocol::Authorized);
    s.instance = None;
    assert!(env.reset(&s).is_err());
    let mut s = goal0(Protocol::Original);
    s.init = 50;
    assert!(matches!(env.reset(&s), Err(EnvError::NoInitState { .. })));
    // No episode after a failed reset.
    assert!(matches!(env.step(&[0.0; 7]), Err(EnvError::NotStarted)));
}

/// Changes the first movable object's root body.
fn perturb(env: &mut Env, change: impl FnOnce(&mut vifo_physics::rapier::prelude::RigidBody)) {
    let sim = env.sim_mut().expect("episode");
    let body = sim.model().entities.iter().find(|e| e.movable()).expect("a movable object").bodies[0];
    change(&mut sim.world_mut().rapier_mut().bodies[body]);
}

#[test]
fn a_blown_up_simulation_ends_the_episode_as_an_error_naming_the_step() {
    use vifo_physics::rapier::prelude::{RigidBody, Vector};
    /// A change to the body that blows the simulation up.
    type Change = dyn Fn(&mut RigidBody);
    let nan_position = |b: &mut RigidBody| b.set_translation(Vector::new(0.0, f64::NAN, 1.0), true);
    let launched = |b: &mut RigidBody| b.set_linvel(Vector::new(0.0, 0.0, 400.0), true);
    let cases: [(&Change, &str); 2] =
        [(&nan_position, "body distance from the origin is NaN"), (&launched, "exceeds 20 m/s")];
    let mut env = Env::new(small(&[CameraName::AgentView]));
    for (change, expected) in cases {
        env.reset(&goal0(Protocol::Original)).unwrap();
        for _ in 0..3 {
            env.step(&[0.0; 7]).unwrap();
        }
        let image = env.observation().agentview.clone();
        perturb(&mut env, change);
        match env.step(&[0.0; 7]) {
            Err(e @ EnvError::Physics { .. }) => {
                // The message the rollout writes into the episode's error record.
                let message = e.to_string();
                assert!(message.starts_with("physics blew up at step 4: "), "{message}");
                assert!(message.contains(expected), "{message}");
            }
            other => panic!("expected a physics error, got {:?}", other.map(|r| r.steps)),
        }
        // Nothing was rendered or scored from the broken state, and the episode is over.
        assert_eq!(env.observation().agentview, image);
        assert!(matches!(env.step(&[0.0; 7]), Err(EnvError::Finished { .. })));
    }
}

#[test]
fn an_unsettled_start_plus_libero_dummy_steps_is_the_settled_start() {
    // The original protocol, and a cue anchored to the state (a halo on the drawer)
    // under the conflict protocol: the cue is prepared from the settled scene either way.
    let halo = spec(&task("libero_goal", 0), Protocol::Conflict, Some("libero_goal/0/F7/glow_halo"), 3, 0).unwrap();
    for s in [goal0(Protocol::Original), halo] {
        let mut settled = Env::new(small(&CameraName::ALL));
        let reference = settled.reset(&s).unwrap().clone();
        let mut env = Env::new(small(&CameraName::ALL));
        let first = env.reset_unsettled(&s).unwrap().clone();
        // Not settled yet: the fingers have not opened.
        assert_ne!(first.gripper_qpos, reference.gripper_qpos);
        assert_eq!(first.instruction, reference.instruction);
        for _ in 0..SETTLE_STEPS {
            assert!(!env.step(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap().done);
        }
        let obs = env.observation();
        assert_eq!((&obs.agentview, &obs.wrist), (&reference.agentview, &reference.wrist), "{}", s.key());
        assert_eq!((obs.eef_pos, obs.eef_quat_xyzw, obs.joint_pos), (reference.eef_pos, reference.eef_quat_xyzw, reference.joint_pos));
        assert_eq!(obs.gripper_qpos, reference.gripper_qpos);
        // The same action from here gives the same state, and the success check agrees.
        let a = [0.3, -0.2, 0.1, 0.0, 0.05, 0.0, 1.0];
        let (x, y) = (env.step(&a).unwrap().observation.clone(), settled.step(&a).unwrap().observation.clone());
        assert_eq!((x.agentview, x.wrist, x.eef_pos, x.gripper_qpos), (y.agentview, y.wrist, y.eef_pos, y.gripper_qpos));
        assert_eq!(env.scored_success(), settled.scored_success());
        assert_eq!(env.cue_drawing(), settled.cue_drawing());
    }
}

#[test]
fn cues_facing_the_model_read_the_right_way_in_the_image_the_model_receives() {
    let config = EnvConfig { cue_facing: CueFacing::Model, ..small(&[CameraName::AgentView]) };
    let mut env = Env::new(config.clone());
    let plain = env.reset(&goal0(Protocol::Original)).unwrap().agentview.clone();
    let drawn = env.reset(&goal0(Protocol::Authorized)).unwrap().agentview.clone();
    let upright = Env::new(small(&[CameraName::AgentView])).reset(&goal0(Protocol::Authorized)).unwrap().agentview.clone();
    let mirrored = |image: &RgbImage| {
        let mut m = image.clone();
        m.mirror_left_right();
        m
    };
    // The model receives the frame mirrored: there the caption is drawn as on any upright frame.
    let mut want = mirrored(&plain);
    let spec = vifo_protocols::scene_cues::instance(INSTANCE).unwrap();
    Inserter::new().insert(&mut want, spec, &FrameInputs::default()).unwrap();
    assert_eq!(mirrored(&drawn), want);
    assert_ne!(drawn, upright);
    // Prepared from an unsettled start, the cue faces the same way.
    let mut unsettled = Env::new(config);
    unsettled.reset_unsettled(&goal0(Protocol::Authorized)).unwrap();
    for _ in 0..SETTLE_STEPS {
        unsettled.step(&[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap();
    }
    assert_eq!(unsettled.observation().agentview, drawn);
}

#[test]
fn records_say_when_cues_faced_the_model() {
    let dir = tempfile::tempdir().unwrap();
    let record = |facing: CueFacing, cameras: &[CameraName]| {
        let path = dir.path().join(format!("results-{facing:?}-{}.jsonl", cameras.len()));
        let config = EnvConfig { cue_facing: facing, ..small(cameras) };
        let options = RunOptions { threads: 1, quiet: true, policy: "zero".into(), ..RunOptions::new(&path) };
        let make = || builtin("zero").ok_or_else(|| "no zero policy".to_string());
        run_episodes(&[goal0(Protocol::Authorized)], make, config, &RolloutOptions::default(), &options).unwrap();
        read_records(&path).unwrap().records.remove(0)
    };
    // Upright cues keep the built-in look's empty label (records as before the option).
    let (upright, faced) = (record(CueFacing::Upright, &[CameraName::AgentView]), record(CueFacing::Model, &[CameraName::AgentView]));
    assert_eq!(upright.look, "");
    assert_eq!(faced.look, "built-in with cues facing the model");
    // A policy sent no images has no look, whichever way cues would have faced.
    assert_eq!(record(CueFacing::Model, &[]).look, report::NO_IMAGES);
    // A report does not put the two in one table unless told to.
    let looks = report::looks_with_vqa(&[upright, faced], []);
    assert!(report::check_looks(&looks, false, "--mix-looks").unwrap_err().contains("built-in with cues facing the model (1 episode)"));
    assert!(report::check_looks(&looks, true, "--mix-looks").is_ok());
}

/// A camera size no renderer takes is an error at the first reset, not an allocation of
/// 10¹⁰ pixels that aborts the process in `Env::new`.
#[test]
fn an_impossible_camera_size_is_an_error() {
    let mut env = Env::new(EnvConfig { size: 100_000, ..EnvConfig::default() });
    let err = env.reset(&goal0(Protocol::Original)).unwrap_err();
    assert!(matches!(err, EnvError::Render(_)) && err.to_string().contains("100000"), "{err}");
}
