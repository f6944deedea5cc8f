//! Cues as scene objects (paper §4.2): the object is seen where it stands, the arm hides it
//! when it passes in front, and the arm moves it when it pushes it.

use vifo_protocols::benchmark::{instances, specs::spec};
use vifo_protocols::env::{CueDrawing, Env, EnvConfig, cue_object, scenes};
use vifo_protocols::spec::{CueForm, EpisodeSpec, Protocol};
use vifo_render::{Frame, Renderer};
use vifo_robots::spatial::{Pose, Vec3};
use vifo_scenes::cue_object::ENTITY_NAME;
use vifo_scenes::sim::Sim;
use vifo_scenes::view::{CameraName, Cameras, ImageOrder};

const SIZE: u32 = 128;

fn object_spec(id: &str, init: usize) -> EpisodeSpec {
    let cue = instances::find(id).unwrap();
    let task = instances::task_of(cue).unwrap();
    EpisodeSpec { cue_form: CueForm::Object, ..spec(&task, Protocol::Authorized, Some(id), init, 0).unwrap() }
}

fn env() -> Env {
    Env::new(EnvConfig { size: SIZE, cameras: vec![CameraName::AgentView], ..EnvConfig::default() })
}

/// World pose of the cue object's face and its half size.
fn face(sim: &Sim, id: &str) -> (Pose, [f64; 2]) {
    let kind = cue_object::kind_of(instances::find(id).unwrap()).unwrap();
    let (entity, _) = sim.model().entity(ENTITY_NAME).unwrap();
    let (local, half) = kind.face();
    (sim.entity_pose(entity).mul(&local), half)
}

fn project(sim: &Sim, p: &Vec3) -> (u32, u32) {
    let camera = Cameras::new(SIZE, SIZE).agentview(sim.model().class);
    let q = camera.project(vifo_render::glam::Vec3::new(p.x as f32, p.y as f32, p.z as f32)).unwrap();
    (q.u.round() as u32, q.v.round() as u32)
}

/// The frame (with segmentation) the env's agentview shows for the current state.
fn render(sim: &Sim, id: &str) -> (Frame, u32, Vec<String>) {
    let cue = instances::find(id).unwrap();
    let kind = cue_object::kind_of(cue).unwrap();
    let task = vifo_scenes::task(&sim.model().task.suite.clone().unwrap(), sim.model().task.index.unwrap()).unwrap();
    let mut view = scenes::assets_with(task, Some(kind)).unwrap().view.clone();
    cue_object::paint(&mut view, sim, cue).unwrap();
    view.update(sim);
    let camera = Cameras::new(SIZE, SIZE).agentview(sim.model().class);
    let frame = view.render(&mut Renderer::default(), &camera, ImageOrder::Upright).unwrap();
    let names = view.legend().iter().map(|s| s.name.clone()).collect();
    (frame, view.segment_of(ENTITY_NAME).unwrap(), names)
}

fn segment_at(frame: &Frame, (u, v): (u32, u32)) -> u32 {
    frame.segmentation[(v * SIZE + u) as usize]
}

#[test]
fn the_cue_object_is_seen_where_it_stands_with_its_picture_on_the_face() {
    for id in ["libero_goal/0/F6/sign_maintenance_source", "libero_spatial/0/F1/caption_bar", "libero_object/0/F8/qr_instruction"] {
        let mut env = env();
        let obs = env.reset(&object_spec(id, 0)).unwrap().agentview.clone();
        assert_eq!(env.cue_drawing(), CueDrawing::InScene);
        let state = env.state().unwrap();
        let (frame, cue, _) = render(state.sim, id);
        // The env's picture is the scene's picture (nothing drawn over it).
        assert_eq!(frame.color.data, obs.data, "{id}");
        let (at, half) = face(state.sim, id);
        let centre = project(state.sim, &at.pos);
        assert_eq!(segment_at(&frame, centre), cue, "{id}: the face's centre projects onto the cue object");
        // Pixels of the face show the picture: several distinct colours, not one paper tone.
        let mut colours = std::collections::BTreeSet::new();
        for (a, b) in [(-0.6, -0.6), (0.6, -0.6), (0.6, 0.6), (-0.6, 0.6), (0.0, 0.0), (0.3, 0.0), (-0.3, 0.0), (0.0, 0.3)] {
            let p = at.transform_point(&Vec3::new(a * half[0], b * half[1], 0.0));
            let (u, v) = project(state.sim, &p);
            assert_eq!(segment_at(&frame, (u, v)), cue, "{id}: face point ({a}, {b})");
            let i = ((v * SIZE + u) * 3) as usize;
            colours.insert([obs.data[i] / 16, obs.data[i + 1] / 16, obs.data[i + 2] / 16]);
        }
        assert!(colours.len() >= 2, "{id}: face shows {colours:?}");
        // The overlay form of the same episode looks different (drawn over the image instead).
        let overlay = env.reset(&spec(&instances::task_of(instances::find(id).unwrap()).unwrap(), Protocol::Authorized, Some(id), 0, 0).unwrap()).unwrap();
        assert_ne!(overlay.agentview.data, obs.data);
    }
}

/// Drives the grip site towards `target` with the gripper command `grip` (P control on the
/// OSC deltas) for at most `steps` steps; returns the final distance.
fn drive(env: &mut Env, target: &Vec3, grip: f64, steps: usize) -> f64 {
    let mut distance = f64::INFINITY;
    for _ in 0..steps {
        let eef = Vec3::from(env.observation().eef_pos);
        let d = target - eef;
        distance = d.norm();
        if distance < 0.005 {
            break;
        }
        let a = |x: f64| (x / 0.05 * 1.5).clamp(-1.0, 1.0);
        if env.step(&[a(d.x), a(d.y), a(d.z), 0.0, 0.0, 0.0, grip]).unwrap().done {
            break;
        }
    }
    distance
}

/// The libero_goal instance whose cue object stands nearest the robot's base at init 0.
fn reachable(env: &mut Env) -> &'static str {
    let mut best: Option<(f64, &'static str)> = None;
    for cue in instances::all(vifo_cues::SetName::Paper) {
        if !matches!(cue.family, vifo_cues::Family::F1 | vifo_cues::Family::F6 | vifo_cues::Family::F8) || !cue.task.starts_with("libero_goal/") {
            continue;
        }
        let id: &'static str = Box::leak(cue.id().into_boxed_str());
        env.reset(&object_spec(id, 0)).unwrap();
        let sim = env.state().unwrap().sim;
        let (entity, _) = sim.model().entity(ENTITY_NAME).unwrap();
        let at = sim.entity_pose(entity).pos;
        let base = sim.model().class.robot_base.pos;
        let reach = (at.x - base[0]).hypot(at.y - base[1]);
        if best.is_none_or(|(r, _)| reach < r) {
            best = Some((reach, id));
        }
    }
    best.expect("libero_goal has F1, F6 and F8 instances").1
}

#[test]
fn the_arm_hides_the_cue_object_when_it_passes_in_front() {
    let mut env = env();
    let id = reachable(&mut env);
    env.reset(&object_spec(id, 0)).unwrap();
    let (at, _) = face(env.state().unwrap().sim, id);
    let centre = project(env.state().unwrap().sim, &at.pos);
    // A point on the ray from the face's centre to the camera, 8 cm in front of the face.
    let camera = Cameras::new(SIZE, SIZE).agentview(env.state().unwrap().sim.model().class);
    let cam = Vec3::new(camera.position.x as f64, camera.position.y as f64, camera.position.z as f64);
    let front = at.pos + (cam - at.pos).normalize() * 0.08;
    let before = env.observation().agentview.clone();
    let left = drive(&mut env, &front, 1.0, 200);
    assert!(left < 0.03, "{id}: the hand stopped {left} m from the point in front of the face");
    let sim = env.state().unwrap().sim;
    let (frame, cue, names) = render(sim, id);
    let seen = segment_at(&frame, centre);
    assert_ne!(seen, cue, "{id}: the face's centre is still visible");
    assert!(names[(seen - 1) as usize].starts_with("robot0_"), "{id}: hidden by {}", names[(seen - 1) as usize]);
    let i = ((centre.1 * SIZE + centre.0) * 3) as usize;
    assert_ne!(&before.data[i..i + 3], &env.observation().agentview.data[i..i + 3], "{id}: the observation shows the arm there");
    // The cue itself stayed where it was.
    let (still, _) = face(sim, id);
    assert!((still.pos - at.pos).norm() < 0.005, "{id}: the cue moved {}", (still.pos - at.pos).norm());
}

#[test]
fn the_arm_moves_the_cue_object_when_it_pushes_it() {
    let mut env = env();
    let id = reachable(&mut env);
    env.reset(&object_spec(id, 0)).unwrap();
    let sim = env.state().unwrap().sim;
    let (entity, _) = sim.model().entity(ENTITY_NAME).unwrap();
    let start = sim.entity_pose(entity).pos;
    let base = sim.model().class.robot_base.pos;
    // From the robot's side of the cue (its back), at the height of its lower part, push
    // horizontally through where it stands.
    let away = Vec3::new(start.x - base[0], start.y - base[1], 0.0).normalize();
    let behind = start - away * 0.14 + Vec3::new(0.0, 0.0, 0.035);
    assert!(drive(&mut env, &(behind + Vec3::new(0.0, 0.0, 0.15)), 1.0, 150) < 0.03, "{id}: over the start");
    assert!(drive(&mut env, &behind, 1.0, 100) < 0.03, "{id}: down behind the cue");
    drive(&mut env, &(start + away * 0.08 + Vec3::new(0.0, 0.0, 0.035)), 1.0, 120);
    let sim = env.state().unwrap().sim;
    let moved = (sim.entity_pose(entity).pos - start).norm();
    assert!(moved > 0.03, "{id}: the cue moved only {moved} m");
}

#[test]
fn only_text_signs_and_codes_become_objects_and_other_families_are_errors() {
    let mut env = env();
    let arrow = instances::all(vifo_cues::SetName::Paper).iter().find(|c| c.family == vifo_cues::Family::F2).unwrap().id();
    let arrow = arrow.as_str();
    let err = env.reset(&object_spec(arrow, 0)).unwrap_err().to_string();
    assert!(err.contains("F2") && err.contains("scene-object"), "{err}");
    let original = EpisodeSpec { cue_form: CueForm::Object, ..spec(&instances::task_of(instances::find(arrow).unwrap()).unwrap(), Protocol::Original, None, 0, 0).unwrap() };
    assert!(env.reset(&original).unwrap_err().to_string().contains("no cue"));
}

#[test]
fn the_object_form_is_deterministic_and_records_stay_compatible() {
    let id = "libero_goal/3/F8/fiducial_tag";
    let s = object_spec(id, 2);
    let a = env().reset(&s).unwrap().agentview.clone();
    let b = env().reset(&s).unwrap().agentview.clone();
    assert_eq!(a.data, b.data);
    // The object form has its own key; the overlay form's spec serialises as before.
    let overlay = EpisodeSpec { cue_form: CueForm::Overlay, ..s.clone() };
    assert_eq!(s.key(), format!("{}|object", overlay.key()));
    let json = serde_json::to_string(&overlay).unwrap();
    assert!(!json.contains("cue_form"));
    let back: EpisodeSpec = serde_json::from_str(&json).unwrap();
    assert_eq!(back.cue_form, CueForm::Overlay);
    let object: EpisodeSpec = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
    assert_eq!(object, s);
}
