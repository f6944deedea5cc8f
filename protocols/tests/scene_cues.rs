//! Cue instances on real scenes (shipped initial states after the settle steps): anchors land
//! on the right things and follow them, ghosts and goal pictures come from the expert's
//! demonstration, the same instance and state give the same bytes, bad input is explained.

use std::sync::Arc;

use vifo_cues::{AnchorUse, CueSpec, Family, FrameInputs, InsertMode, Inserter, SetName, parse, variants};
use vifo_protocols::scene_cues::{
    CameraProjector, CueFacing, EpisodeCue, SceneCueError, ScenePoint, anchors, builtin_instances, builtin_set, instance,
    start::settled_start,
    task_of,
};
use vifo_render::{Camera, Frame, RgbImage, Renderer};
use vifo_scenes::sim::{SceneModel, Sim};
use vifo_scenes::view::{Cameras, ImageOrder, SceneView};

const SIZE: u32 = 128;

struct Episode {
    sim: Sim,
    view: SceneView,
    agent: Camera,
    wrist: Camera,
}

fn episode(task: &str) -> Episode {
    let (suite, index) = task.split_once('/').unwrap();
    let model: Arc<SceneModel> = SceneModel::build(vifo_scenes::task(suite, index.parse().unwrap()).unwrap()).unwrap();
    let sim = settled_start(&model, 0).unwrap();
    let mut view = SceneView::new(&model);
    view.update(&sim);
    let cameras = Cameras::new(SIZE, SIZE);
    Episode { agent: cameras.agentview(model.class), wrist: cameras.eye_in_hand(&sim), sim, view }
}

impl Episode {
    fn frame(&self, renderer: &mut Renderer, camera: &Camera) -> Frame {
        self.view.render(renderer, camera, ImageOrder::Upright).unwrap()
    }

    fn prepare(&self, renderer: &mut Renderer, spec: &CueSpec) -> Result<EpisodeCue, SceneCueError> {
        EpisodeCue::prepare(&self.sim, &self.view, renderer, spec, &task_of(spec).unwrap().goal, (SIZE, SIZE))
    }

    /// The frame of `camera` with the cue drawn.
    fn with_cue(&self, renderer: &mut Renderer, cue: &mut EpisodeCue, camera: &Camera) -> RgbImage {
        let mut image = self.frame(renderer, camera).color;
        cue.apply(&self.sim, renderer, camera, &mut image).unwrap();
        image
    }
}

/// Segment ids within `r` pixels of (u, v).
fn segments_near(frame: &Frame, u: f64, v: f64, r: i64) -> Vec<u32> {
    let mut out = Vec::new();
    for dy in -r..=r {
        for dx in -r..=r {
            let (x, y) = (u.round() as i64 + dx, v.round() as i64 + dy);
            if x >= 0 && y >= 0 && x < frame.width() as i64 && y < frame.height() as i64 {
                out.push(frame.segment_at(x as u32, y as u32));
            }
        }
    }
    out
}

/// The entity a scene point belongs to (a region's owner).
fn owner(sim: &Sim, point: &ScenePoint) -> Option<String> {
    let entity = match point {
        ScenePoint::Entity { entity } | ScenePoint::Part { entity, .. } => Some(*entity),
        ScenePoint::Region { key } => sim.region_box(key).and_then(|b| b.owner),
    }?;
    Some(sim.model().entities[entity].name.clone())
}

#[test]
fn anchors_land_on_the_source_and_target_in_the_image() {
    let mut renderer = Renderer::default();
    for (task, variant) in [
        ("libero_goal/1", "straight_arrow_red"),
        ("libero_spatial/0", "numbered_waypoints"),
        ("libero_object/0", "dashed_path_cyan"),
        ("libero_10/6", "dual_spotlights"),
        ("libero_goal/0", "glow_halo"),
        ("libero_goal/7", "rim_light"),
    ] {
        let e = episode(task);
        let spec = instance(&format!("{task}/{}/{variant}", variants::find(variant).unwrap().family)).unwrap();
        let mut cue = e.prepare(&mut renderer, spec).unwrap();
        let frame = e.frame(&mut renderer, &e.agent);
        let anchors = cue.anchors(&e.sim, &e.agent);
        let points = cue.points().clone();
        for (role, anchor, point) in [("source", anchors.source, Some(points.source)), ("target", anchors.target, points.target)] {
            let (Some(a), Some(point)) = (anchor, point) else { continue };
            assert!(a.inside(SIZE, SIZE), "{task} {role} at {a:?}");
            let Some(name) = owner(&e.sim, &point) else { continue };
            let id = e.view.segment_of(&name).unwrap();
            assert!(segments_near(&frame, a.u, a.v, 2).contains(&id), "{task}: the {role} anchor is not on {name}");
        }
        let mut image = frame.color.clone();
        let report = cue.apply(&e.sim, &mut renderer, &e.agent, &mut image).unwrap();
        assert!(report.drawn && report.source == AnchorUse::InView, "{task}: {report:?}");
        assert_ne!(image, frame.color);
    }
}

#[test]
fn a_drawer_anchor_follows_the_drawer() {
    let mut renderer = Renderer::default();
    let mut e = episode("libero_goal/0");
    let spec = instance("libero_goal/0/F2/target_crosshair_magenta").unwrap();
    let cue = e.prepare(&mut renderer, spec).unwrap();
    let ScenePoint::Part { entity, .. } = cue.points().source else { panic!("{:?}", cue.points()) };
    let closed = cue.points().source.world(&e.sim).center;
    let before = cue.anchors(&e.sim, &e.agent).source.unwrap();
    // The anchor fits the handle (about 9 cm wide), not the whole drawer seen edge-on.
    let radius = before.radius.unwrap();
    assert!((2.0..10.0).contains(&radius), "radius {radius} px at {SIZE}²");
    e.sim.set_joint(entity, "middle_level", -0.15);
    let open = cue.points().source.world(&e.sim).center;
    let after = cue.anchors(&e.sim, &e.agent).source.unwrap();
    let moved = (0..3).map(|k| (open[k] - closed[k]).powi(2)).sum::<f64>().sqrt();
    assert!((moved - 0.15).abs() < 0.01, "the anchor moved {moved} m");
    assert!((after.u - before.u).abs() + (after.v - before.v).abs() > 3.0, "{before:?} {after:?}");
}

#[test]
fn ghosts_follow_the_demonstration_to_the_target() {
    let mut renderer = Renderer::default();
    let e = episode("libero_goal/1");
    let spec = instance("libero_goal/1/F3/ghost_fade").unwrap();
    let mut cue = e.prepare(&mut renderer, spec).unwrap();
    let demo = cue.demo().unwrap().clone();
    assert_eq!(cue.ghost_count(), 4);
    let target = cue.anchors(&e.sim, &e.agent).target;
    let layers = cue.ghost_layers(&mut renderer, &e.agent).unwrap().to_vec();
    assert_eq!(layers.len(), 4);
    let centroid = |l: &vifo_cues::RgbaImage| {
        let (mut x, mut y, mut n) = (0.0, 0.0, 0.0);
        for (i, p) in l.data.chunks_exact(4).enumerate() {
            if p[3] > 0 {
                x += (i % SIZE as usize) as f64;
                y += (i / SIZE as usize) as f64;
                n += 1.0;
            }
        }
        assert!(n > 0.0, "an empty ghost layer");
        (x / n, y / n)
    };
    let source = cue.anchors(&e.sim, &e.agent).source.unwrap();
    let first = centroid(&layers[0]);
    let last = centroid(&layers[3]);
    assert!((first.0 - source.u).hypot(first.1 - source.v) > 3.0, "the first ghost sits on the object");
    if demo.success {
        // The bowl ends on the stove: the last ghost is drawn where the cook region is.
        let t = target.unwrap();
        assert!((last.0 - t.u).hypot(last.1 - t.v) < 12.0, "last ghost at {last:?}, target at {t:?}");
    } else {
        assert!(demo.failure.is_some());
    }
    // Ghosts change both cameras' frames, and the wrist camera's layers are its own.
    let clean = e.frame(&mut renderer, &e.agent).color;
    assert_ne!(e.with_cue(&mut renderer, &mut cue, &e.agent), clean);
    let wrist_layers = cue.ghost_layers(&mut renderer, &e.wrist).unwrap().to_vec();
    assert_ne!(wrist_layers, layers);
}

#[test]
fn goal_pictures_run_from_the_start_to_the_goal() {
    let mut renderer = Renderer::default();
    let e = episode("libero_goal/1");
    let spec = instance("libero_goal/1/F4/keyframe_storyboard").unwrap();
    let cue = e.prepare(&mut renderer, spec).unwrap();
    let pictures = cue.pictures();
    assert!(pictures.len() >= 2, "{} pictures", pictures.len());
    let start = e.frame(&mut renderer, &e.agent).color;
    let first: Vec<u8> = pictures[0].data.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    assert_eq!(first, start.data, "the first picture is the episode's start");
    assert_ne!(pictures.last().unwrap(), &pictures[0]);
    // Pictogram cards need no demonstration.
    let cards = e.prepare(&mut renderer, instance("libero_goal/1/F4/step_cards").unwrap()).unwrap();
    assert!(cards.pictures().is_empty() && cards.demo().is_none());
}

#[test]
fn the_same_instance_and_state_give_the_same_bytes() {
    let e = episode("libero_goal/1");
    let ids: Vec<String> = Family::ALL
        .iter()
        .map(|f| variants::of_family(*f).next().unwrap().name)
        .chain(["ghost_trail_path", "dim_surround", "hand_point_then_place", "before_after"])
        .map(|v| format!("libero_goal/1/{}/{v}", variants::find(v).unwrap().family))
        .collect();
    for id in ids {
        let spec = instance(&id).unwrap();
        let frames = |renderer: &mut Renderer| {
            let mut cue = e.prepare(renderer, spec).unwrap();
            let a = e.with_cue(renderer, &mut cue, &e.agent);
            let w = e.with_cue(renderer, &mut cue, &e.wrist);
            // Cached assets and layers give the same bytes as the first frame.
            assert_eq!(e.with_cue(renderer, &mut cue, &e.agent), a, "{id}");
            (a, w)
        };
        let first = frames(&mut Renderer::default());
        let second = frames(&mut Renderer::default());
        assert!(first == second, "{id}: two runs differ");
    }
}

#[test]
fn every_instance_finds_its_things_in_its_scene() {
    let set = builtin_instances().unwrap();
    let mut tasks: Vec<&str> = set.instances.iter().map(|s| s.task.as_str()).collect();
    tasks.dedup();
    assert_eq!(tasks.len(), 40);
    let mut renderer = Renderer::default();
    for task in tasks {
        let e = episode(task);
        for spec in set.instances.iter().filter(|s| s.task == task) {
            let points = anchors::resolve(&e.sim, spec).unwrap_or_else(|err| panic!("{err}"));
            assert_eq!(points.target.is_some(), spec.target.is_some(), "{}", spec.id());
            if spec.family == Family::F3 {
                let movable = matches!(points.source, ScenePoint::Entity { entity } if e.sim.model().entities[entity].movable());
                assert!(movable, "{}: ghost of {:?}", spec.id(), points.source);
            }
            if spec.insert_mode == InsertMode::SceneAnchored {
                let mut cue = e.prepare(&mut renderer, spec).unwrap();
                let anchors = cue.anchors(&e.sim, &e.agent);
                let source = anchors.source.unwrap();
                assert!(source.usable() && source.radius.is_some(), "{}: {source:?}", spec.id());
                let mut image = e.frame(&mut renderer, &e.agent).color;
                let report = cue.apply(&e.sim, &mut renderer, &e.agent, &mut image).unwrap();
                assert!(report.drawn, "{}: {report:?}", spec.id());
            }
        }
    }
}

#[test]
fn both_instance_sets_cover_the_tasks_and_every_instance_is_found_by_id() {
    let full = builtin_instances().unwrap();
    let paper = builtin_set(SetName::Paper).unwrap();
    assert_eq!(builtin_set(SetName::Full).unwrap(), full);
    assert_eq!(paper.instances.len(), 1347);
    assert!(full.instances.len() > paper.instances.len());
    for set in [full, paper] {
        for (family, count) in set.composition() {
            assert!(variants::of_family(family).count() >= 3, "{family}");
            assert_eq!(count.tasks, if family == Family::F3 { 38 } else { 40 }, "{family}");
        }
    }
    for spec in &full.instances {
        assert_eq!(instance(&spec.id()).unwrap(), spec);
    }
}

#[test]
fn bad_input_is_explained() {
    let err = |r: Result<&CueSpec, SceneCueError>| r.unwrap_err().to_string();
    assert!(err(instance("libero_goal/1/F2/no_such_arrow")).contains("no variant 'no_such_arrow'"));
    assert!(err(instance("libero_goal/0/F3/ghost_fade")).contains("cannot carry ghost_fade"));
    assert!(err(instance("libero_goal/42/F2/straight_arrow_red")).contains("no built-in task libero_goal/42"));
    assert!(err(instance("straight_arrow_red")).contains("expected <suite>/<index>/<family>/<variant>"));

    let mut renderer = Renderer::default();
    let e = episode("libero_goal/1");
    // A spec naming an object the scene does not have.
    let mut spec = instance("libero_goal/1/F2/straight_arrow_red").unwrap().clone();
    spec.steps[0].source_id = Some("unicorn_1".into());
    let msg = e.prepare(&mut renderer, &spec).err().unwrap().to_string();
    assert!(msg.contains("source 'unicorn_1' is not in the scene") && msg.contains("akita_black_bowl_1"), "{msg}");
    // A phrase nothing in the scene matches.
    let parsed = parse("put the teapot on the plate").unwrap();
    let spec = CueSpec::new("libero_goal/1", &parsed, 0, variants::find("glow_halo").unwrap()).unwrap();
    let msg = e.prepare(&mut renderer, &spec).err().unwrap().to_string();
    assert!(msg.contains("'teapot'"), "{msg}");
    // A ghost of something that does not move.
    let parsed = parse("open the middle drawer of the cabinet").unwrap();
    let spec = CueSpec::new("libero_goal/1", &parsed, 0, variants::find("ghost_fade").unwrap()).unwrap();
    let msg = e.prepare(&mut renderer, &spec).err().unwrap().to_string();
    assert!(msg.contains("needs a movable source"), "{msg}");
    // A frame that is not the camera's size is refused and left alone.
    let mut cue = e.prepare(&mut renderer, instance("libero_goal/1/F2/straight_arrow_red").unwrap()).unwrap();
    let mut small = RgbImage::new(64, 64);
    let msg = cue.apply(&e.sim, &mut renderer, &e.agent, &mut small).unwrap_err().to_string();
    assert!(msg.contains("the camera is 128x128, the frame 64x64"), "{msg}");
    assert_eq!(small, RgbImage::new(64, 64));
}

#[test]
fn the_camera_projector_matches_the_renderer() {
    let e = episode("libero_goal/1");
    use vifo_cues::Projector;
    let p = e.sim.entity_pose(0).pos;
    let [u, v, d] = CameraProjector(&e.agent).project([p.x, p.y, p.z]).unwrap();
    let q = e.agent.project(vifo_render::glam::Vec3::new(p.x as f32, p.y as f32, p.z as f32)).unwrap();
    assert_eq!((u as f32, v as f32, d as f32), (q.u, q.v, q.depth));
}

/// `image` mirrored left–right: what a model served with LIBERO's 180° rotation receives.
fn mirrored(image: &RgbImage) -> vifo_cues::RgbImage {
    let mut m = vifo_cues::RgbImage::from_raw(image.width, image.height, image.data.clone()).unwrap();
    m.mirror_left_right();
    m
}

#[test]
fn a_cue_facing_the_model_is_the_upright_cue_on_the_models_image() {
    let mut renderer = Renderer::default();
    let e = episode("libero_goal/1");
    let clean = e.frame(&mut renderer, &e.agent).color;
    // Text in a fixed region, and a storyboard of goal pictures: what the model receives is the
    // cue drawn as usual on the image it receives (its pictures mirrored with the scene), also
    // after the same cue drew an upright frame.
    for id in ["libero_goal/1/F1/caption_bar", "libero_goal/1/F4/keyframe_storyboard"] {
        let spec = instance(id).unwrap();
        let mut cue = e.prepare(&mut renderer, spec).unwrap();
        let upright = e.with_cue(&mut renderer, &mut cue, &e.agent);
        cue.set_facing(CueFacing::Model);
        let seen = mirrored(&e.with_cue(&mut renderer, &mut cue, &e.agent));
        let mut pictures = cue.pictures().to_vec();
        pictures.iter_mut().for_each(vifo_cues::RgbaImage::mirror_left_right);
        let mut want = mirrored(&clean);
        let inputs = FrameInputs { pictures: &pictures, ..FrameInputs::default() };
        Inserter::new().insert(&mut want, spec, &inputs).unwrap();
        assert!(seen == want, "{id}: the model's image is not the upright cue on it");
        assert!(mirrored(&upright) != want, "{id}: facing changed nothing");
    }
    // Marks anchored in the scene and symmetric left–right (a halo, a ghost's images) come out
    // byte for byte where the upright cue puts them, on both cameras: their anchors and ghost
    // images are mirrored with the frame. Turning back to upright gives the upright bytes.
    for id in ["libero_goal/1/F7/glow_halo", "libero_goal/1/F3/ghost_fade"] {
        let spec = instance(id).unwrap();
        for camera in [&e.agent, &e.wrist] {
            let mut cue = e.prepare(&mut renderer, spec).unwrap();
            let upright = e.with_cue(&mut renderer, &mut cue, camera);
            assert_ne!(upright, e.frame(&mut renderer, camera).color, "{id}: nothing drawn");
            cue.set_facing(CueFacing::Model);
            assert!(e.with_cue(&mut renderer, &mut cue, camera) == upright, "{id}: a symmetric mark moved");
            cue.set_facing(CueFacing::Upright);
            assert!(e.with_cue(&mut renderer, &mut cue, camera) == upright, "{id}");
        }
    }
}
