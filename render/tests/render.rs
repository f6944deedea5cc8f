//! Behaviour of the full renderer: camera agreement, clipping, depth, segmentation, lighting,
//! textures, transparency, determinism, and bad input.

use std::sync::Arc;

use vifo_render::glam::{Vec2, Vec3};
use vifo_render::{
    Background, Camera, Filter, Frame, Headlight, Instance, Light, Material, Mesh, Mirror, RenderError,
    RenderOptions, Renderer, Scene, Texture, Transform,
};

/// LIBERO's Tabletop agentview (model_facts.json).
fn agentview(w: u32, h: u32) -> Camera {
    Camera::new(
        Vec3::new(0.658_613_2, 0.0, 1.610_35),
        [0.638_017_7, 0.304_849_7, 0.304_849_8, 0.638_017_7],
        45.0,
        w,
        h,
    )
}

fn unlit_scene(instances: Vec<Instance>) -> Scene {
    Scene { instances, ..Scene::default() }
}

fn render(scene: &Scene, cam: &Camera) -> Frame {
    Renderer::default().render(scene, cam).unwrap()
}

/// A square of half-size `half` (m) centred at `p`, facing the camera.
fn facing_square(cam: &Camera, p: Vec3, half: f32, material: Material, segment: u32) -> Instance {
    let rot = vifo_render::glam::Mat3::from_cols(cam.right() * half, cam.up() * half, -cam.forward());
    Instance::new(Arc::new(Mesh::plane(1.0, 1.0)), Transform::from_pos_mat3(p, rot), segment).with_material(material)
}

fn covered(frame: &Frame, segment: u32) -> Vec<(u32, u32)> {
    let w = frame.width();
    frame.segmentation.iter().enumerate().filter(|&(_, &s)| s == segment).map(|(i, _)| (i as u32 % w, i as u32 / w)).collect()
}

#[test]
fn marker_lights_the_pixel_project_returns() {
    let cam = agentview(96, 72);
    let k = cam.intrinsics();
    let points = [Vec3::new(0.013, 0.021, 0.9), Vec3::new(-0.31, 0.17, 0.91), Vec3::new(0.12, -0.4, 0.95), Vec3::new(-0.6, 0.05, 1.2)];
    for p in points {
        let q = cam.project(p).unwrap();
        // A square 0.9 px wide around the projected point covers exactly one pixel centre:
        // the nearest one.
        let half = 0.45 * q.depth / k.fy;
        let scene = unlit_scene(vec![facing_square(&cam, p, half, Material::unlit([1.0, 0.0, 0.0, 1.0]), 7)]);
        let frame = render(&scene, &cam);
        let expect = (q.u.round() as u32, q.v.round() as u32);
        assert_eq!(covered(&frame, 7), vec![expect], "point {p} projects to ({}, {})", q.u, q.v);
        assert_eq!(frame.color.pixel(expect.0, expect.1), [255, 0, 0]);
        let d = frame.depth_at(expect.0, expect.1);
        assert!((d - q.depth).abs() < 1e-4, "depth {d} vs {}", q.depth);
    }
}

#[test]
fn pixel_centres_and_image_orientation() {
    // A camera looking down at the xy-plane with +y appearing up in the image.
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 90.0, 4, 4);
    // Half-plane x > 0 (right half of the image), top edge y > 0 only.
    let quad = Instance::new(Arc::new(Mesh::plane(5.0, 5.0)), Transform::from_translation(Vec3::new(5.0, 5.0, 0.0)), 3)
        .with_material(Material::unlit([0.0, 1.0, 0.0, 1.0]));
    let frame = render(&unlit_scene(vec![quad]), &cam);
    // Pixel centres are at u = 0..3 with c_x = 1.5, so columns 2 and 3 are right of the axis;
    // rows 0 and 1 are above it.
    let mut got = covered(&frame, 3);
    got.sort();
    assert_eq!(got, vec![(2, 0), (2, 1), (3, 0), (3, 1)]);
}

#[test]
fn near_plane_clipping_matches_ray_casting() {
    // A wrist-like camera 2 cm above a large floor, looking forward and down at 30°: the floor
    // crosses the near plane right below the camera.
    let eye = Vec3::new(0.0, 0.0, 0.02);
    let dir = Vec3::new(1.0, 0.0, -30f32.to_radians().tan());
    let near = 0.03;
    let cam = Camera::look_at(eye, eye + dir, Vec3::Z, 75.0, 64, 48).with_clip(near, 50.0);
    let floor = Instance::new(Arc::new(Mesh::plane(5.0, 5.0)), Transform::IDENTITY, 1).with_material(Material::rgba([0.6, 0.6, 0.6, 1.0]));
    let scene = Scene { instances: vec![floor], ..Scene::default() };
    let frame = render(&scene, &cam);
    let mut mismatches = 0;
    for v in 0..48 {
        for u in 0..64 {
            let (o, d) = cam.ray(u as f32, v as f32);
            // Ray hits z = 0 at t; its depth along the view axis must exceed near.
            let t = -o.z / d.z;
            let hit = o + d * t;
            let expect = d.z < 0.0 && hit.x.abs() < 5.0 && hit.y.abs() < 5.0 && cam.world_to_camera(hit).z >= near;
            let got = frame.segment_at(u, v) == 1;
            if got != expect {
                mismatches += 1;
            }
            if got {
                let depth = frame.depth_at(u, v);
                let z = cam.world_to_camera(hit).z;
                // Inverse depth is what is interpolated; vertex snapping (1/256 px) shifts it by
                // its screen gradient times ~1/512 px, which is largest at the horizon.
                let err = (1.0 / depth - 1.0 / z).abs();
                assert!(err <= 3e-3 + 1e-4 / z, "({u},{v}) depth {depth} vs {z}");
                let c = frame.color.pixel(u, v);
                assert!(c[0] > 0 && c[0] == c[1] && c[1] == c[2], "({u},{v}) colour {c:?}");
            }
        }
    }
    // Only pixels within a hair of the horizon or the near cut may disagree.
    assert!(mismatches <= 2, "{mismatches} pixels disagree with ray casting");
    // The bottom rows are cut by the near plane (closer than 3 cm along the axis): empty.
    assert!((0..64).all(|u| frame.segment_at(u, 47) == 0));
    assert!((0..64).all(|u| frame.segment_at(u, 20) == 1));
}

#[test]
fn depth_and_segmentation_follow_occlusion() {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 64, 64);
    let cube = Arc::new(Mesh::cuboid(Vec3::splat(0.1)));
    let near_box = Instance::new(cube.clone(), Transform::from_translation(Vec3::new(0.0, 0.0, 0.5)), 2);
    let far_box = Instance::new(Arc::new(Mesh::cuboid(Vec3::new(0.5, 0.5, 0.1))), Transform::IDENTITY, 1);
    // Draw order must not matter.
    for instances in [vec![near_box.clone(), far_box.clone()], vec![far_box, near_box]] {
        let frame = render(&Scene { instances, ..Scene::default() }, &cam);
        // Centre: the near box's top at z = 0.6 → 1.4 m from the camera.
        let (cx, cy) = (32, 32);
        assert_eq!(frame.segment_at(cx, cy), 2);
        assert!((frame.depth_at(cx, cy) - 1.4).abs() < 1e-4);
        // Off-centre: the big box's top at z = 0.1 → 1.9 m.
        assert_eq!(frame.segment_at(cx + 12, cy), 1);
        assert!((frame.depth_at(cx + 12, cy) - 1.9).abs() < 1e-4);
        // Corner: background.
        assert_eq!(frame.segment_at(0, 0), 0);
        assert_eq!(frame.depth_at(0, 0), f32::INFINITY);
    }
}

#[test]
fn what_is_hidden_behind_what_is_drawn_is_skipped_and_not_lit() {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 48, 48);
    let wall = facing_square(&cam, Vec3::new(0.0, 0.0, 0.5), 2.0, Material::default(), 1);
    let hidden = Instance::new(Arc::new(Mesh::sphere(0.2, 16)), Transform::IDENTITY, 2);
    let lights = |instances| Scene { instances, headlight: Headlight::default(), ..Scene::default() };
    let mut r = Renderer::default();
    let alone = r.render(&lights(vec![wall.clone()]), &cam).unwrap();
    let (lit_alone, rasterized_alone) = (r.stats().vertices_lit, r.stats().triangles_rasterized);
    // The sphere is drawn after the wall, which covers all of it: it is skipped whole.
    let both = r.render(&lights(vec![hidden.clone(), wall.clone()]), &cam).unwrap();
    assert_eq!(r.stats().hidden, 1);
    assert_eq!((r.stats().triangles_rasterized, r.stats().vertices_lit), (rasterized_alone, lit_alone));
    assert_eq!(both, alone);
    // Half in front of the wall: drawn, and only what shows is lit.
    let poking = Instance::new(Arc::new(Mesh::sphere(0.2, 16)), Transform::from_translation(Vec3::new(0.0, 0.0, 0.5)), 2);
    let through = r.render(&lights(vec![poking, wall]), &cam).unwrap();
    assert_eq!(r.stats().hidden, 0);
    assert!(through.segmentation.contains(&2));
}

#[test]
fn large_triangles_behind_what_is_drawn_are_skipped_without_changing_a_pixel() {
    // A wall over the left half of the view, and behind it a tessellated floor-like plane over
    // all of it: the plane's triangles wholly behind the wall are skipped before their pixels
    // are tested. Every pixel must still be the nearer of the two drawn alone.
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 96, 96);
    let wall = Instance::new(Arc::new(Mesh::plane(0.6, 1.5)), Transform::from_translation(Vec3::new(-0.6, 0.0, 0.8)), 1)
        .with_material(Material::rgba([0.8, 0.3, 0.2, 1.0]));
    let back = Instance::new(Arc::new(Mesh::grid(3.0, 3.0, 12, 12)), Transform::IDENTITY, 2).with_material(Material::rgba([0.2, 0.5, 0.7, 1.0]));
    let lit = |instances| Scene { instances, headlight: Headlight::default(), ..Scene::default() };
    // Without the static layer, which would draw the unmoved plane first.
    let mut r = Renderer::new(RenderOptions { static_layer: false, ..RenderOptions::default() });
    let wall_alone = r.render(&lit(vec![wall.clone()]), &cam).unwrap();
    let back_alone = r.render(&lit(vec![back.clone()]), &cam).unwrap();
    assert_eq!(r.stats().triangles_hidden, 0, "nothing hides the plane drawn alone");
    let both = r.render(&lit(vec![back, wall]), &cam).unwrap();
    assert!(r.stats().triangles_hidden >= 8, "only {} triangles skipped", r.stats().triangles_hidden);
    for p in 0..both.depth.len() {
        let near = if wall_alone.depth[p] <= back_alone.depth[p] { &wall_alone } else { &back_alone };
        assert_eq!(both.color.data[3 * p..3 * p + 3], near.color.data[3 * p..3 * p + 3], "pixel {p}");
        assert_eq!((both.segmentation[p], both.depth[p]), (near.segmentation[p], near.depth[p]), "pixel {p}");
    }
}

#[test]
fn clustered_meshes_draw_the_same_pixels_and_skip_clusters_facing_away() {
    let dense = Mesh::sphere(0.3, 48);
    let clustered = dense.clone().clustered();
    let scene = |mesh: Mesh| Scene { instances: vec![Instance::new(Arc::new(mesh), Transform::IDENTITY, 1)], headlight: Headlight::default(), ..Scene::default() };
    let mut r = Renderer::default();
    for eye in [Vec3::new(0.0, 0.0, 2.0), Vec3::new(1.2, -0.7, 0.4), Vec3::new(0.0, 0.45, 0.1)] {
        let cam = Camera::look_at(eye, Vec3::ZERO, Vec3::Z, 45.0, 64, 64);
        let plain = r.render(&scene(dense.clone()), &cam).unwrap();
        assert_eq!(r.stats().clusters_culled, 0);
        let grouped = r.render(&scene(clustered.clone()), &cam).unwrap();
        assert!(r.stats().clusters_culled > 0, "from {eye}: no cluster was skipped");
        assert_eq!(grouped, plain, "from {eye}");
    }
}

#[test]
fn back_faces_are_culled_unless_double_sided() {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, -1.0), Vec3::ZERO, Vec3::Y, 45.0, 16, 16);
    // The plane faces +z; the camera is below it.
    let plane = Arc::new(Mesh::plane(1.0, 1.0));
    let one = Instance::new(plane.clone(), Transform::IDENTITY, 5);
    assert!(covered(&render(&unlit_scene(vec![one.clone()]), &cam), 5).is_empty());
    let two = one.with_material(Material { double_sided: true, ..Material::default() });
    let frame = render(&unlit_scene(vec![two]), &cam);
    assert_eq!(covered(&frame, 5).len(), 256);
    // Seen from the back, it is lit with the reversed normal (headlight: not dark).
    assert!(frame.color.pixel(8, 8)[0] > 100);
}

#[test]
fn headlight_on_a_facing_plane_matches_the_opengl_equation() {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 45.0, 33, 33);
    let plane = Instance::new(Arc::new(Mesh::grid(1.0, 1.0, 8, 8)), Transform::IDENTITY, 1)
        .with_material(Material::rgba([0.5, 0.5, 0.5, 1.0]));
    let frame = render(&unlit_scene(vec![plane]), &cam);
    // Centre pixel (a grid vertex sits on the axis): ambient 0.1·0.5 + diffuse 0.4·0.5 +
    // specular 0.5·0.5·1 = 0.5 → 128.
    assert_eq!(frame.color.pixel(16, 16), [128, 128, 128]);
    // Off-axis the specular term falls off.
    assert!(frame.color.pixel(0, 16)[0] < 128);
}

#[test]
fn lighting_sanity() {
    let cam = Camera::look_at(Vec3::new(0.0, -2.0, 0.0), Vec3::ZERO, Vec3::Z, 45.0, 64, 64);
    let sphere = Instance::new(Arc::new(Mesh::sphere(0.4, 48)), Transform::IDENTITY, 1)
        .with_material(Material { rgba: [0.8, 0.8, 0.8, 1.0], specular: 0.0, ..Material::default() });
    // A directional light coming from the image's left (−x), no headlight.
    let mut light = Light::mujoco_directional(Vec3::new(1.0, 0.0, 0.0));
    light.cast_shadow = false;
    let scene = Scene {
        instances: vec![sphere],
        lights: vec![light],
        headlight: Headlight { active: false, ..Headlight::default() },
        background: Background::Solid([0.0, 0.0, 1.0]),
        mirror: None,
    };
    let frame = render(&scene, &cam);
    let left = frame.color.pixel(20, 32)[0];
    let right = frame.color.pixel(44, 32)[0];
    assert!(left > 60 && right == 0, "left {left}, right {right}");
    assert_eq!(frame.color.pixel(0, 0), [0, 0, 255]);
    // Same light with a specular surface gets a highlight where n bisects light and view.
    let mut shiny = scene.clone();
    shiny.instances[0].material.specular = 1.0;
    let f2 = render(&shiny, &cam);
    let max_diff = f2.color.data.iter().zip(&frame.color.data).map(|(a, b)| a.saturating_sub(*b)).max().unwrap();
    assert!(max_diff > 40, "no specular highlight ({max_diff})");
}

#[test]
fn textures_are_perspective_correct() {
    // A 2×1 texture: left half red, right half blue, on a plane tilted away from the camera.
    let tex = Arc::new(Texture::from_rgb8(2, 1, &[255, 0, 0, 0, 0, 255]).unwrap().with_filter(Filter::Nearest));
    let mat = Material { texture: Some(tex), unlit: true, ..Material::default() };
    let cam = Camera::look_at(Vec3::new(0.0, -1.0, 0.6), Vec3::new(0.0, 1.0, 0.0), Vec3::Z, 60.0, 80, 60);
    // Plane in xy, rotated 90° about z so the texture's u runs along +y (away from the camera).
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let plane = Instance::new(Arc::new(Mesh::plane(1.0, 1.0)), Transform::from_pos_quat(Vec3::Y, [h, 0.0, 0.0, h]), 1).with_material(mat);
    let frame = render(&unlit_scene(vec![plane]), &cam);
    // The plane spans y ∈ [0, 2]. The red/blue boundary is the line y = 1; its image is where
    // that line projects, which is not the middle of the plane's image (where affine
    // interpolation would put it).
    let boundary = cam.project(Vec3::new(0.0, 1.0, 0.0)).unwrap().v;
    let top_of_plane = cam.project(Vec3::new(0.0, 2.0, 0.0)).unwrap().v;
    let bottom = cam.project(Vec3::new(0.0, 0.0, 0.0)).unwrap().v;
    assert!((boundary - 0.5 * (top_of_plane + bottom)).abs() > 3.0, "test geometry too symmetric");
    for v in 0..60u32 {
        let c = frame.color.pixel(40, v);
        if frame.segment_at(40, v) != 1 || (v as f32 - boundary).abs() < 1.0 {
            continue;
        }
        // Rows above the boundary (smaller v) are farther along +y: blue.
        let expect = if (v as f32) < boundary { [0, 0, 255] } else { [255, 0, 0] };
        assert_eq!(c, expect, "row {v} (boundary at {boundary})");
    }
}

#[test]
fn distant_textures_are_filtered_not_aliased() {
    // A 64×64 one-texel checkerboard tiled 40× over a 2 m plane seen from 3 m: many texels
    // per pixel, so each pixel should come out near the average grey.
    let data: Vec<u8> = (0..64 * 64).flat_map(|i| if (i % 64 + i / 64) % 2 == 0 { [255u8; 3] } else { [0u8; 3] }).collect();
    let tex = Arc::new(Texture::from_rgb8(64, 64, &data).unwrap());
    let mat = Material { texture: Some(tex), unlit: true, uv_scale: Vec2::splat(40.0), ..Material::default() };
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 40.0, 64, 64);
    let plane = Instance::new(Arc::new(Mesh::plane(1.0, 1.0)), Transform::IDENTITY, 1).with_material(mat);
    let frame = render(&unlit_scene(vec![plane]), &cam);
    let px = covered(&frame, 1);
    assert!(px.len() > 1000);
    let worst = px.iter().map(|&(x, y)| (frame.color.pixel(x, y)[0] as i32 - 128).abs()).max().unwrap();
    assert!(worst < 40, "a pixel is {worst} levels off grey: aliasing");
}

#[test]
fn transparent_instances_blend_and_keep_depth() {
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO, Vec3::Y, 45.0, 16, 16);
    let back = Instance::new(Arc::new(Mesh::plane(1.0, 1.0)), Transform::IDENTITY, 1).with_material(Material::unlit([0.0, 0.0, 1.0, 1.0]));
    let front = Instance::new(Arc::new(Mesh::plane(1.0, 1.0)), Transform::from_translation(Vec3::new(0.0, 0.0, 0.5)), 2)
        .with_material(Material::unlit([1.0, 0.0, 0.0, 0.5]));
    let frame = render(&unlit_scene(vec![front, back]), &cam);
    assert_eq!(frame.color.pixel(8, 8), [128, 0, 128]);
    assert_eq!(frame.segment_at(8, 8), 2);
    assert!((frame.depth_at(8, 8) - 2.0).abs() < 1e-5);
}

#[test]
fn rendering_is_deterministic_across_renderers_and_threads() {
    let scene = busy_scene();
    let cam = agentview(128, 128);
    let a = render(&scene, &cam);
    let mut r = Renderer::new(RenderOptions::default());
    let _ = r.render(&scene, &agentview(40, 30)).unwrap(); // Reused buffers must not leak.
    let b = r.render(&scene, &cam).unwrap();
    let c = std::thread::spawn(move || render(&scene, &cam)).join().unwrap();
    assert_eq!(a, b);
    assert_eq!(a, c);
    assert!(covered(&a, 1).len() > 1000, "the table should be visible");
}

#[test]
fn supersampling_smooths_edges_and_keeps_segmentation() {
    let scene = busy_scene();
    let cam = agentview(64, 64);
    let plain = render(&scene, &cam);
    let ss = Renderer::new(RenderOptions { supersample: 3, ..RenderOptions::default() }).render(&scene, &cam).unwrap();
    let same_seg = plain.segmentation.iter().zip(&ss.segmentation).filter(|(a, b)| a == b).count();
    assert!(same_seg as f32 > 0.98 * plain.segmentation.len() as f32);
    assert_ne!(plain.color, ss.color);
    let psnr = vifo_render::metrics::psnr(&plain.color, &ss.color).unwrap();
    assert!(psnr > 20.0, "supersampled image differs too much ({psnr} dB)");
}

#[test]
fn shadows_darken_what_the_light_cannot_see() {
    let cam = Camera::look_at(Vec3::new(0.0, -1.5, 1.5), Vec3::ZERO, Vec3::Z, 45.0, 64, 64);
    let floor = Instance::new(Arc::new(Mesh::grid(1.0, 1.0, 16, 16)), Transform::IDENTITY, 1);
    let blocker = Instance::new(Arc::new(Mesh::cuboid(Vec3::splat(0.1))), Transform::from_translation(Vec3::new(0.0, 0.0, 0.5)), 2);
    let light = Light::mujoco_spot(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -1.0));
    let scene = Scene {
        instances: vec![floor, blocker],
        lights: vec![light],
        headlight: Headlight { active: false, ..Headlight::default() },
        ..Scene::default()
    };
    let lit = render(&scene, &cam);
    let shadowed = Renderer::new(RenderOptions { shadows: true, shadow_map_size: 512, ..RenderOptions::default() })
        .render(&scene, &cam)
        .unwrap();
    let under = cam.project(Vec3::ZERO).unwrap();
    let aside = cam.project(Vec3::new(0.5, 0.3, 0.0)).unwrap();
    let px = |f: &Frame, p: vifo_render::Projection| f.color.pixel(p.u.round() as u32, p.v.round() as u32)[0];
    assert!(px(&lit, under) > 100);
    assert_eq!(px(&shadowed, under), 0, "the floor below the box is in shadow");
    assert_eq!(px(&shadowed, aside), px(&lit, aside), "lit floor is unchanged");
}

#[test]
fn bad_input_is_an_error_or_skipped_never_a_panic() {
    let mut r = Renderer::default();
    let scene = busy_scene();
    for cam in [
        agentview(0, 10),
        Camera { fovy_deg: 180.0, ..agentview(8, 8) },
        Camera { fovy_deg: f32::NAN, ..agentview(8, 8) },
        Camera { position: Vec3::new(f32::NAN, 0.0, 0.0), ..agentview(8, 8) },
        agentview(8, 8).with_clip(0.0, 1.0),
        agentview(100_000, 8),
    ] {
        assert!(matches!(r.render(&scene, &cam), Err(RenderError::InvalidCamera(_))), "{cam:?}");
    }
    let mut broken = scene.clone();
    broken.instances[0].transform.translation.x = f32::NAN;
    broken.instances[1].transform.linear.x_axis.y = f32::INFINITY;
    let frame = r.render(&broken, &agentview(32, 32)).unwrap();
    assert_eq!(r.stats().instances_culled, 2);
    assert!(frame.segmentation.iter().all(|&s| s != 1 && s != 2));
    // Absurd but finite placements (overflow checks are on in tests).
    let mut wild = scene.clone();
    wild.instances[0].transform = Transform::from_pos_quat_scale(Vec3::new(0.0, 0.0, 1.0), [1.0, 0.0, 0.0, 0.0], Vec3::splat(1e30));
    wild.instances[1].transform = Transform::from_pos_quat_scale(Vec3::new(1e25, -1e25, 0.9), [0.3, 0.1, 0.9, 0.2], Vec3::new(1e-30, 1e20, 1.0));
    wild.instances[2].transform.translation = Vec3::new(0.66, 0.0, 1.6105); // Inside the camera.
    for cam in [agentview(32, 32), agentview(64, 48).with_clip(1e-6, 1e30)] {
        r.render(&wild, &cam).unwrap();
    }
}

/// A grey box whose top (z = 0.9) is a mirror of reflectance 0.5, as MuJoCo draws one: a red
/// square above the top shows, at half strength and added to the grey, where its mirror image
/// projects; what stands below the plane, nearer the mirrored eye, is clipped away; pixels off
/// the top are untouched.
#[test]
fn mirrors_add_the_scene_above_them_to_their_face_only() {
    let cam = agentview(128, 128);
    let unlit_double = |rgba: [f32; 4]| Material { double_sided: true, ..Material::unlit(rgba) };
    let top = Vec3::new(0.0, 0.0, 0.9);
    let face = Instance::new(Arc::new(Mesh::cuboid(Vec3::new(0.2, 0.2, 0.02))), Transform::from_translation(top - Vec3::new(0.0, 0.0, 0.02)), 1)
        .with_material(Material::unlit([0.2, 0.2, 0.2, 1.0]));
    let q = Vec3::new(-0.05, 0.02, 0.9);
    let to_q = (q - cam.position).normalize();
    let reflected = Vec3::new(to_q.x, to_q.y, -to_q.z);
    let red = facing_square(&cam, q + 0.3 * reflected, 0.03, unlit_double([1.0, 0.0, 0.0, 1.0]), 2);
    // A blue wall beside the box, from 0.4 m below the plane to 0.1 m above it: its lower part
    // stands between the mirrored eye and `q`, its upper part is out of every ray that matters.
    let wall_rot = vifo_render::glam::Mat3::from_cols(Vec3::Y, Vec3::Z, Vec3::X);
    let blue = Instance::new(Arc::new(Mesh::plane(0.3, 0.25)), Transform::from_pos_mat3(Vec3::new(0.25, 0.0, 0.75), wall_rot), 3)
        .with_material(unlit_double([0.0, 0.0, 1.0, 1.0]));
    let plain = unlit_scene(vec![face, red, blue]);
    let mirror = Scene { mirror: Some(Mirror { instance: 0, face_z: 0.02, reflectance: 0.5 }), ..plain.clone() };
    let (without, with) = (render(&plain, &cam), render(&mirror, &cam));
    let p = cam.project(q).unwrap();
    let (u, v) = (p.u.round() as u32, p.v.round() as u32);
    assert_eq!(with.segment_at(u, v), 1);
    assert_eq!(without.color.pixel(u, v), [51, 51, 51]);
    let [r, g, b] = with.color.pixel(u, v);
    assert!((177..=179).contains(&r) && g == 51 && b == 51, "{:?}", [r, g, b]);
    let mut changed = 0;
    for (k, (a, b)) in with.color.data.chunks(3).zip(without.color.data.chunks(3)).enumerate() {
        if a != b {
            assert_eq!(with.segmentation[k], 1, "pixel {k} off the mirror changed");
            changed += 1;
        }
    }
    assert!(changed > 4, "{changed}");
    assert_eq!(with.segmentation, without.segmentation);
    assert_eq!(with.depth, without.depth);
}

/// The face's pixels are looked for only where the mirror can project: a mirror cut by the
/// image's border, and one so near that its bounds reach behind the eye, still reflect on every
/// pixel that shows them. A red sheet above covers every reflected ray, so each face pixel gains
/// red and no other pixel changes.
#[test]
fn every_visible_pixel_of_a_mirror_reflects_at_the_border_and_up_close() {
    let face = Instance::new(Arc::new(Mesh::plane(0.3, 0.3)), Transform::from_translation(Vec3::new(0.0, 0.0, 0.9)), 1)
        .with_material(Material::unlit([0.2, 0.2, 0.2, 1.0]));
    let sheet = Instance::new(Arc::new(Mesh::plane(20.0, 20.0)), Transform::from_translation(Vec3::new(0.0, 0.0, 3.0)), 2)
        .with_material(Material { double_sided: true, ..Material::unlit([1.0, 0.0, 0.0, 1.0]) });
    let plain = unlit_scene(vec![face, sheet]);
    let mirror = Scene { mirror: Some(Mirror { instance: 0, face_z: 0.0, reflectance: 0.5 }), ..plain.clone() };
    let border = Camera::look_at(Vec3::new(0.9, -0.5, 1.5), Vec3::new(0.55, 0.0, 0.9), Vec3::Z, 45.0, 64, 48);
    let close = Camera::look_at(Vec3::new(0.05, -0.1, 1.05), Vec3::new(0.0, 0.0, 0.9), Vec3::Z, 75.0, 64, 48);
    for (name, cam) in [("border", border), ("close", close)] {
        let (without, with) = (render(&plain, &cam), render(&mirror, &cam));
        let face_px = covered(&with, 1);
        let w = cam.width;
        match name {
            "border" => assert!(face_px.iter().any(|&(x, _)| x == 0) && face_px.len() < (w * cam.height) as usize / 2, "the mirror is not cut by the border"),
            _ => assert!(cam.position.distance(Vec3::new(0.0, 0.0, 0.9)) < 0.3 * 2f32.sqrt() && face_px.len() > 100, "the mirror's bounds do not reach behind the eye"),
        }
        for k in 0..(w * cam.height) as usize {
            let (a, b) = (with.color.data[3 * k], without.color.data[3 * k]);
            if with.segmentation[k] == 1 {
                assert!(a > b, "{name}: face pixel ({}, {}) did not reflect", k as u32 % w, k as u32 / w);
            } else {
                assert_eq!(with.color.data[3 * k..3 * k + 3], without.color.data[3 * k..3 * k + 3], "{name}: pixel {k} off the mirror changed");
            }
        }
    }
}

#[test]
fn frustum_culling_skips_instances_behind_the_camera() {
    let cam = agentview(32, 32);
    let mut scene = busy_scene();
    let n = scene.instances.len();
    scene.instances.push(Instance::new(Arc::new(Mesh::sphere(0.1, 16)), Transform::from_translation(Vec3::new(3.0, 0.0, 2.0)), 99));
    let mut r = Renderer::default();
    r.render(&scene, &cam).unwrap();
    assert_eq!(r.stats().instances_culled, 1);
    assert_eq!(r.stats().instances_drawn, n);
}

/// A table with a few objects under LIBERO's lights.
fn busy_scene() -> Scene {
    let table = Instance::new(Arc::new(Mesh::cuboid_tessellated(Vec3::new(0.5, 0.6, 0.025), 4)), Transform::from_translation(Vec3::new(0.0, 0.0, 0.875)), 1)
        .with_material(Material { rgba: [0.7, 0.55, 0.4, 1.0], specular: 0.2, shininess: 0.0, ..Material::default() });
    let floor = Instance::new(Arc::new(Mesh::grid(3.0, 3.0, 24, 24)), Transform::IDENTITY, 2)
        .with_material(Material { rgba: [0.5, 0.5, 0.5, 1.0], specular: 0.0, shininess: 0.0, uv_scale: Vec2::splat(3.0), ..Material::default() });
    let bowl = Arc::new(Mesh::lathe(&[(0.0, 0.0), (0.04, 0.0), (0.055, 0.05), (0.05, 0.05), (0.035, 0.006), (0.0, 0.006)], 24));
    let mut instances = vec![table, floor];
    for k in 0..5 {
        let p = Vec3::new(-0.2 + 0.1 * k as f32, -0.25 + 0.12 * k as f32, 0.9);
        instances.push(
            Instance::new(bowl.clone(), Transform::from_translation(p), 10 + k)
                .with_material(Material::rgba([0.1 + 0.2 * k as f32, 0.2, 0.3, 1.0])),
        );
    }
    let mut l1 = Light::mujoco_spot(Vec3::new(1.0, 1.0, 4.0), Vec3::new(0.0, -0.15, -1.0));
    l1.diffuse = [0.8; 3];
    l1.cast_shadow = false;
    let mut l2 = l1;
    l2.kind = match l1.kind {
        vifo_render::LightKind::Spot { direction, cutoff_deg, exponent, attenuation, .. } => {
            vifo_render::LightKind::Spot { position: Vec3::new(-3.0, -3.0, 4.0), direction, cutoff_deg, exponent, attenuation }
        }
        k => k,
    };
    Scene {
        instances,
        lights: vec![l1, l2],
        headlight: Headlight::default(),
        background: Background::Gradient { up: [0.9, 0.9, 1.0], down: [0.2, 0.3, 0.4] },
        mirror: None,
    }
}

/// A fixed camera keeps a layer of what did not move (`RenderOptions::static_layer`): every
/// frame must be the frame a renderer without layers draws, bit for bit, while objects move,
/// stop and move again, a moved copy ties exactly in depth with a static one, a transparent
/// instance and a mirror are in view, and a second, moving camera shares the renderer.
#[test]
fn a_fixed_camera_reuses_what_did_not_move_and_draws_the_same_pixels() {
    // With a mirror, whose pass redraws the whole visibility buffer, and without, where a frame
    // restores only what the camera's last frame changed.
    for mirror in [true, false] {
        fixed_camera_frames_match_whole_frames(mirror);
    }
}

fn fixed_camera_frames_match_whole_frames(mirror: bool) {
    let mut base = busy_scene();
    let bowl = base.instances[3].clone();
    // The copy comes first in the scene, so that a whole frame draws it before the original
    // where they coincide: there it takes every pixel on a tie.
    let copy = Instance { segment: 40, material: Material::rgba([0.9, 0.9, 0.1, 1.0]), ..bowl.clone() };
    base.instances.insert(0, copy);
    base.mirror = mirror.then_some(Mirror { instance: 1, face_z: 0.025, reflectance: 0.3 });
    base.instances.push(Instance::new(Arc::new(Mesh::sphere(0.05, 16)), Transform::IDENTITY, 41).with_material(Material::rgba([0.2, 0.8, 0.3, 1.0])));
    base.instances.push(
        Instance::new(Arc::new(Mesh::cuboid(Vec3::new(0.05, 0.05, 0.05))), Transform::from_translation(Vec3::new(0.1, 0.1, 0.96)), 42)
            .with_material(Material::rgba([0.9, 0.2, 0.2, 0.5])),
    );
    let (copy, ball) = (0, base.instances.len() - 2);
    let cam = agentview(96, 96);
    let mut layered = Renderer::default();
    let mut plain = Renderer::new(RenderOptions { static_layer: false, ..RenderOptions::default() });
    let (mut reused, mut tied) = (vec![0; 22], 0);
    // `k` is the frame number, used well beyond indexing `reused`.
    #[allow(clippy::needless_range_loop)]
    for k in 0..22 {
        let mut scene = base.clone();
        // The ball rolls across the table, rests for frames 6-16, then rolls on.
        let t = if (6..=16).contains(&k) { 6.0 } else { k as f32 - 10.0 };
        scene.instances[ball].transform = Transform::from_translation(Vec3::new(-0.3 + 0.05 * t, 0.2 - 0.04 * t, 0.95));
        // The copy jumps between a place of its own and the original's pose.
        if k % 2 == 0 {
            scene.instances[copy].transform = Transform::from_translation(Vec3::new(0.25, 0.3, 0.9 + 0.001 * k as f32));
        }
        let wrist = Camera::look_at(Vec3::new(0.1 + 0.02 * k as f32, 0.0, 1.3), Vec3::new(0.0, 0.0, 0.9), Vec3::Z, 75.0, 64, 64);
        for c in [cam, wrist] {
            let want = plain.render(&scene, &c).unwrap();
            assert_eq!(plain.stats().instances_reused, 0);
            let got = layered.render(&scene, &c).unwrap();
            assert!(got == want, "frame {k}, {}×{} camera, mirror {mirror}: the layer changed pixels", c.width, c.height);
            if c == cam {
                reused[k] = layered.stats().instances_reused;
                tied += (k % 2 == 1 && covered(&got, 40).len() > 50) as usize;
            } else {
                assert_eq!(layered.stats().instances_reused, 0, "frame {k}: the moving camera reused a layer");
            }
        }
    }
    // From frame 1 the table, floor and five bowls come from the layer (the transparent box is
    // blended anew in every frame); the resting ball joins them once it has not moved for a
    // few frames, and leaves when it rolls on.
    assert_eq!(reused[0], 0);
    assert!(reused[1..].iter().all(|&r| r >= 7), "{reused:?}");
    assert!(reused[14..=16].contains(&8) && reused[20] == 7, "{reused:?}");
    assert!(tied >= 5, "the copy won its ties in only {tied} frames");
    // A static instance that moves, and a light that changes, are drawn anew.
    let mut scene = base.clone();
    scene.instances[2].transform = Transform::from_translation(Vec3::new(0.0, 0.0, 0.5));
    scene.lights[0].diffuse = [0.3; 3];
    for _ in 0..2 {
        assert!(layered.render(&scene, &cam).unwrap() == plain.render(&scene, &cam).unwrap());
    }
}

/// `render_covered` shades only the box of what its scene covers: inside the box it gives the
/// pixels of a whole render, outside it leaves the frame as it was, and the box holds every
/// pixel a whole render shows something at.
#[test]
fn a_covered_render_is_the_whole_render_inside_the_box_it_returns() {
    let cam = agentview(96, 80);
    let busy = busy_scene();
    let mut renderer = Renderer::default();
    for (k, bowl) in busy.instances[2..].iter().enumerate() {
        let scene = Scene { instances: vec![bowl.clone()], ..busy.clone() };
        let whole = render(&scene, &cam);
        // The frame holds another render first: outside the box it must stay as it was.
        let mut frame = renderer.render(&busy, &cam).unwrap();
        let before = frame.clone();
        let [x0, y0, x1, y1] = renderer.render_covered(&scene, &cam, &mut frame).unwrap().expect("the bowl is in view");
        assert!(x1 - x0 < 40 && y1 - y0 < 40, "bowl {k}: box {:?}", [x0, y0, x1, y1]);
        let w = cam.width;
        for y in 0..cam.height {
            for x in 0..w {
                let (p, inside) = ((y * w + x) as usize, (x0..=x1).contains(&x) && (y0..=y1).contains(&y));
                let (got, want) = if inside { (&frame, &whole) } else { (&frame, &before) };
                assert_eq!(got.color.data[3 * p..3 * p + 3], want.color.data[3 * p..3 * p + 3], "bowl {k} at ({x}, {y})");
                assert_eq!((got.depth[p].to_bits(), got.segmentation[p]), (want.depth[p].to_bits(), want.segmentation[p]), "bowl {k} at ({x}, {y})");
                if !inside {
                    assert_eq!(whole.segmentation[p], 0, "bowl {k}: ({x}, {y}) shows it outside the box");
                }
            }
        }
    }
    // Nothing in view: no box. A transparent instance: drawn whole.
    let away = Instance { transform: Transform::from_translation(Vec3::new(3.0, 0.0, 2.0)), ..busy.instances[3].clone() };
    let mut frame = Frame::default();
    assert_eq!(renderer.render_covered(&Scene { instances: vec![away], ..busy.clone() }, &cam, &mut frame).unwrap(), None);
    let glass = Instance { material: Material::rgba([0.5, 0.5, 0.9, 0.5]), ..busy.instances[3].clone() };
    let scene = Scene { instances: vec![glass], ..busy.clone() };
    assert_eq!(renderer.render_covered(&scene, &cam, &mut frame).unwrap(), Some([0, 0, 95, 79]));
    assert_eq!(frame, render(&scene, &cam));
}
