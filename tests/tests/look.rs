//! LIBERO's look: the built-in look is unchanged by the asset machinery, and with the asset
//! wheels installed every category and robot body is drawn from them, deterministically.

use vifo::render::{RenderRequest, episode};
use vifo::start::InitSource;
use vifo_render::Renderer;
use vifo_render::imageio::encode_png;
use vifo_scenes::look::{self, Look, Status};
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

fn png_sha1(task: &str, camera: CameraName, look: Option<&Look>) -> (String, Vec<u8>) {
    let sim = episode(&RenderRequest::still(task, InitSource::Shipped)).unwrap();
    let mut view = SceneView::with_look(sim.model(), look);
    view.update(&sim);
    let frame = view.render(&mut Renderer::default(), &Cameras::new(256, 256).get(camera, &sim), ImageOrder::Upright).unwrap();
    let png = encode_png(&frame.color).unwrap();
    (look::blob_sha1(&png), frame.color.data)
}

/// The scene view of `task`'s shipped state 0.
fn still_view(task: &str, look: Option<&Look>) -> SceneView {
    let sim = episode(&RenderRequest::still(task, InitSource::Shipped)).unwrap();
    SceneView::with_look(sim.model(), look)
}

/// `sha1sum` of the PNGs of shipped state 0 that `vifo render --task <task> --camera <camera>
/// --builtin-look` wrote before it added its look and scene as PNG text (`encode_png` still
/// writes them without). First pinned before LIBERO's look existed (commit 5215612); pinned again
/// when the shipped states were regenerated for the one-substep physics (commit b05cb9f), whose
/// code still drew the earlier states to the earlier hashes, and for the sleep delay and fixture
/// frames (libero_goal/7's wrist frame changed; the code drew the earlier states as before),
/// and for the 5 mm contact prediction distance (three frames changed; the code drew the
/// earlier states to the earlier hashes), and for the Panda's hull link colliders (libero_goal/7's
/// two frames changed; the code drew the earlier states to the earlier hashes).
const BEFORE: [(&str, CameraName, &str); 4] = [
    ("libero_spatial/0", CameraName::AgentView, "85b02d96bb045a8eeef4031a3f673d8b2e073b74"),
    ("libero_spatial/0", CameraName::EyeInHand, "7bc3672528f702dae65b9a81fd39b9eaeba83ae7"),
    ("libero_goal/7", CameraName::AgentView, "4f7708d2333e0e978da15c1a5073c5f32d2d50bf"),
    ("libero_goal/7", CameraName::EyeInHand, "5ba0fdef9503dbbf00d0d76179073dde97b5c9a1"),
];

#[test]
fn the_built_in_look_is_bit_for_bit_what_it_was() {
    for (task, camera, sha1) in BEFORE {
        let sim = episode(&RenderRequest::still(task, InitSource::Shipped)).unwrap();
        let mut view = SceneView::new(sim.model());
        view.update(&sim);
        let frame = view.render(&mut Renderer::default(), &Cameras::new(256, 256).get(camera, &sim), ImageOrder::Upright).unwrap();
        let png = encode_png(&frame.color).unwrap();
        assert_eq!(plain_sha1(&png), sha1, "{task} {camera}");
        // A look with nothing in it draws the same bytes.
        let empty = tempdir_look();
        assert_eq!(png_sha1(task, camera, Some(&empty)).1, frame.color.data, "{task} {camera}");
    }
}

fn plain_sha1(bytes: &[u8]) -> String {
    use sha1::{Digest, Sha1};
    Sha1::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

fn tempdir_look() -> Look {
    Look::load(look::Roots::default())
}

#[test]
fn installed_assets_draw_every_category_and_robot_body() {
    let roots = look::discover(None, None).unwrap();
    if roots.libero.is_empty() || roots.robot.is_none() {
        vifo_tests::skip_notice("installed_assets_draw_every_category_and_robot_body", format_args!("no LIBERO asset wheels or robosuite installed ({})", roots.notes.join("; ")));
        return;
    }
    let look = Look::load(roots);
    for r in look.report() {
        assert_eq!(r.status, Status::Assets, "{}: {:?}", r.category, r.problem);
    }
    let (a, frame) = png_sha1("libero_spatial/0", CameraName::AgentView, Some(&look));
    let (b, again) = png_sha1("libero_spatial/0", CameraName::AgentView, Some(&look));
    assert_eq!((a, frame.clone()), (b, again));
    let (_, builtin) = png_sha1("libero_spatial/0", CameraName::AgentView, None);
    assert_ne!(frame, builtin);
}

/// With LIBERO's textures found, the floor, the walls and the box table's faces are drawn with
/// them (the table's legs keep their mean colour); the built-in look draws all in mean colours.
#[test]
fn the_asset_look_textures_the_floor_the_walls_and_the_box_table() {
    let roots = look::discover(None, None).unwrap();
    if roots.libero.is_empty() {
        vifo_tests::skip_notice("the_asset_look_textures_the_floor_the_walls_and_the_box_table", format_args!("no LIBERO asset wheels installed ({})", roots.notes.join("; ")));
        return;
    }
    let look = Look::load(roots);
    // Per instance of `segment`: whether it is textured.
    let textured = |task: &str, segment: &str, look: Option<&Look>| -> Vec<bool> {
        let view = still_view(task, look);
        let id = view.segment_of(segment).unwrap_or_else(|| panic!("{task}: no segment {segment}"));
        view.scene().instances.iter().filter(|i| i.segment == id).map(|i| i.material.texture.is_some()).collect()
    };
    // The plain table scene and the kitchen.
    for (task, table) in [("libero_spatial/0", "main_table"), ("libero_10/3", "kitchen_table")] {
        for segment in ["floor", "walls"] {
            assert!(textured(task, segment, Some(&look)).iter().all(|&t| t), "{task} {segment}");
            assert!(textured(task, segment, None).iter().all(|&t| !t), "{task} {segment}");
        }
        let with = textured(task, table, Some(&look));
        assert_eq!((with.iter().filter(|&&t| t).count(), with.iter().filter(|&&t| !t).count()), (1, 4), "{task}: the top, then four legs");
        assert!(textured(task, table, None).iter().all(|&t| !t));
    }
}

/// robosuite's Panda meshes dress the Panda only: the PiPER's links (named `link1`… like the
/// Panda's) keep their own shapes when LIBERO's look is loaded.
#[test]
fn the_look_dresses_only_the_panda() {
    use vifo_scenes::view::SegmentKind;
    let roots = look::discover(None, None).unwrap();
    if roots.robot.is_none() {
        vifo_tests::skip_notice("the_look_dresses_only_the_panda", format_args!("robosuite's robot meshes are not installed ({})", roots.notes.join("; ")));
        return;
    }
    let look = Look::load(roots);
    // (instances, triangles) of the robot's segments in a scene's view.
    let robot = |task: &str, look: Option<&Look>| {
        let view = still_view(task, look);
        let links: Vec<u32> = view.legend().iter().filter(|s| s.kind == SegmentKind::RobotLink).map(|s| s.id).collect();
        let parts: Vec<_> = view.scene().instances.iter().filter(|i| links.contains(&i.segment)).collect();
        (parts.len(), parts.iter().map(|i| i.mesh.triangles().len()).sum::<usize>())
    };
    assert_eq!(robot("vifo_piper/0", Some(&look)), robot("vifo_piper/0", None));
    assert_ne!(robot("libero_spatial/0", Some(&look)), robot("libero_spatial/0", None));
    // robosuite's Panda has no visual geom on `right_hand` (a frame inside the gripper's hand):
    // with the look it draws nothing there, where the built-in look has a flange.
    let hand_instances = |look: Option<&Look>| {
        let view = still_view("libero_spatial/0", look);
        let hand = view.segment_of("robot0_right_hand").unwrap();
        view.scene().instances.iter().filter(|i| i.segment == hand).count()
    };
    assert_eq!(hand_instances(Some(&look)), 0);
    assert!(hand_instances(None) > 0);
}

/// The renderer's static layer (each camera keeps what did not move) draws every frame of an
/// expert episode as a whole frame would: a scene with a drawer the expert opens, both cameras,
/// the built-in look and, where installed, LIBERO's.
#[test]
fn the_static_layer_draws_an_expert_episode_as_whole_frames() {
    use vifo_render::RenderOptions;
    let roots = look::discover(None, None).unwrap();
    let assets = (!roots.libero.is_empty() && roots.robot.is_some()).then(|| Look::load(roots));
    if assets.is_none() {
        vifo_tests::skip_notice("the_static_layer_draws_an_expert_episode_as_whole_frames (LIBERO's look; the built-in look runs)", "no asset wheels or robosuite installed");
    }
    for look in std::iter::once(None).chain(assets.as_ref().map(Some)) {
        // libero_goal/0: open the middle drawer of the cabinet.
        let mut sim = episode(&RenderRequest::still("libero_goal/0", InitSource::Shipped)).unwrap();
        let mut view = SceneView::with_look(sim.model(), look);
        let cameras = Cameras::new(128, 128);
        let mut expert = vifo_expert::Expert::new(&sim).unwrap();
        let (mut layered, mut whole) = (Renderer::default(), Renderer::new(RenderOptions { static_layer: false, ..RenderOptions::default() }));
        let mut reused = 0;
        for step in 0..45 {
            view.update(&sim);
            for camera in CameraName::ALL {
                let c = cameras.get(camera, &sim);
                let want = view.render(&mut whole, &c, ImageOrder::Upright).unwrap();
                let got = view.render(&mut layered, &c, ImageOrder::Upright).unwrap();
                assert!(got == want, "step {step}, {camera}, look {}: the static layer changed the frame", look.is_some());
                if camera == CameraName::AgentView {
                    reused += layered.stats().instances_reused;
                }
            }
            sim.step(&expert.act(&sim));
        }
        // From the second frame on, at least 20 instances (table, floor, walls, cabinet, objects).
        assert!(reused >= 44 * 20, "look {}: only {reused} instances came from the layer in 45 frames", look.is_some());
    }
}

/// What the look's disk cache gives back is what LIBERO's files give: every part of every
/// category, robot body and scene's decor (meshes, coarser copies, textures), the arena
/// textures, the report, the hash and the frames drawn with them. Loaded here without the cache
/// and through a new one, so both ways run whatever the user's cache holds.
#[test]
fn the_look_read_from_its_cache_is_the_look_made_from_the_files() {
    use vifo_scenes::look::PartKind;
    use vifo_scenes::task::ProblemClass;
    let roots = look::discover(None, None).unwrap();
    if roots.libero.is_empty() || roots.robot.is_none() {
        vifo_tests::skip_notice("the_look_read_from_its_cache_is_the_look_made_from_the_files", format_args!("no LIBERO asset wheels or robosuite installed ({})", roots.notes.join("; ")));
        return;
    }
    let cache = tempfile::tempdir().unwrap();
    let fresh = Look::load_with_cache(roots.clone(), None);
    let first = Look::load_with_cache(roots.clone(), Some(cache.path()));
    let cached = Look::load_with_cache(roots, Some(cache.path()));
    assert_eq!(fresh.cache().dir, None);
    assert!(first.cache().made > 100 && first.cache().problem.is_none(), "{:?}", first.cache());
    assert_eq!((cached.cache().read, cached.cache().made), (first.cache().read + first.cache().made, 0));
    assert_eq!(cached.hash(), fresh.hash());
    assert_eq!(serde_json::to_string(cached.report()).unwrap(), serde_json::to_string(fresh.report()).unwrap());
    let mut coarser = 0;
    for line in fresh.report() {
        let name = line.category.as_str();
        match line.kind {
            PartKind::Object | PartKind::Fixture => {
                assert_eq!(cached.parts(name), fresh.parts(name), "{name}");
                coarser += fresh.parts(name).map_or(0, |p| p.iter().map(|p| p.lods.len()).sum::<usize>());
            }
            PartKind::Robot => {
                let body = name.trim_start_matches("robot0_");
                assert_eq!(cached.robot_parts("panda", body, false), fresh.robot_parts("panda", body, false), "{name}");
            }
            PartKind::Arena => {
                if let Some((_, file)) = name.split_once(' ').filter(|(piece, _)| ["floor", "table", "walls"].contains(piece)) {
                    assert_eq!(cached.arena_texture(file), fresh.arena_texture(file), "{name}");
                }
            }
        }
    }
    assert!(coarser > 50, "coarser copies compared: {coarser}");
    for problem in ProblemClass::ALL {
        assert_eq!(cached.decor(problem), fresh.decor(problem), "{problem:?}");
    }
    for camera in [CameraName::AgentView, CameraName::EyeInHand] {
        assert_eq!(png_sha1("libero_10/3", camera, Some(&cached)), png_sha1("libero_10/3", camera, Some(&fresh)), "{camera}");
    }
}
