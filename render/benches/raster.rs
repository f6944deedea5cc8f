//! Rasterizer speed on a synthetic LIBERO-like tabletop scene.
//!
//! `cargo bench -p vifo-render --bench raster` prints ms/frame for one and two cameras
//! (LIBERO's agentview and eye-in-hand poses) at 128², 224² and 256², and the triangle counts.
//! `-- --save DIR` also writes the 256² frames as PNG for a look. One thread; each figure is
//! the fastest of 5 batches of about 250 ms, in thread CPU time on Linux. The scene never moves,
//! so the static layer is off: with it every frame after the first would be a copy of the last.

use std::sync::Arc;
use std::time::Instant;

use vifo_render::glam::{Vec2, Vec3};
use vifo_render::{Background, Camera, Frame, Headlight, Instance, Light, Material, Mesh, RenderOptions, Renderer, Scene, Transform};

fn main() {
    let save = std::env::args().skip_while(|a| a != "--save").nth(1);
    let clock = if Clock::cpu_ns().is_some() { "thread CPU time" } else { "wall-clock time" };
    println!("timing: {clock}, fastest of {BATCHES} batches of about {BATCH_MS} ms, every frame drawn whole (no static layer)");
    // The same scene with round objects and arm links at 24 and at 48 segments.
    for detail in [1, 2] {
        bench_scene(&libero_like_scene(detail), if detail == 2 { None } else { save.as_deref() });
    }
}

/// Timed batches per figure, and how long each lasts.
const BATCHES: usize = 5;
const BATCH_MS: f64 = 250.0;

fn bench_scene(scene: &Scene, save: Option<&str>) {
    let tris: usize = scene.instances.iter().map(|i| i.mesh.triangle_count()).sum();
    println!("scene: {} instances, {} triangles", scene.instances.len(), tris);
    let mut renderer = Renderer::new(RenderOptions { static_layer: false, ..RenderOptions::default() });
    let mut frames = [Frame::default(), Frame::default()];
    for size in [128u32, 224, 256] {
        let cams = [agentview(size), eye_in_hand(size)];
        let mut seen = [0usize; 2];
        for (k, cam) in cams.iter().enumerate() {
            renderer.render_into(scene, cam, &mut frames[k]).unwrap();
            seen[k] = renderer.stats().triangles_rasterized;
            if size == 256 {
                let st = renderer.stats();
                println!("  256² camera {k}: {} triangles in view, {} rasterized, {} vertices lit", st.triangles_in_view, st.triangles_rasterized, st.vertices_lit);
            }
        }
        // The machine is shared: time is this thread's CPU time where Linux reports it (so
        // waiting for a core does not count), and the fastest of several batches. That clock
        // advances in scheduler ticks, so a batch lasts long enough for a tick to be a small
        // error; the first, calibrating batch warms up.
        let mut time_for = |cams: &[Camera]| {
            let mut step = || {
                for (k, cam) in cams.iter().enumerate() {
                    renderer.render_into(scene, cam, &mut frames[k]).unwrap();
                }
            };
            let (start, mut calls) = (Clock::now(), 0usize);
            while calls < 10 || start.elapsed_ms() < BATCH_MS / 2.0 {
                step();
                calls += 1;
            }
            let per_batch = ((calls as f64 * BATCH_MS / start.elapsed_ms().max(1e-3)) as usize).max(1);
            let mut best = f64::INFINITY;
            for _ in 0..BATCHES {
                let start = Clock::now();
                for _ in 0..per_batch {
                    step();
                }
                best = best.min(start.elapsed_ms() / per_batch as f64);
            }
            best
        };
        let one = time_for(&cams[..1]);
        let two = time_for(&cams);
        println!(
            "{size}x{size}: agentview {one:.3} ms/frame ({} triangles rasterized); agentview + eye_in_hand {two:.3} ms/step ({} + {} triangles)",
            seen[0], seen[0], seen[1]
        );
        if let (Some(dir), 256) = (save, size) {
            for (k, name) in ["agentview", "eye_in_hand"].iter().enumerate() {
                renderer.render_into(scene, &cams[k], &mut frames[k]).unwrap();
                let path = std::path::Path::new(dir).join(format!("bench_{name}.png"));
                vifo_render::imageio::save_png(&frames[k].color, &path).unwrap();
                println!("wrote {}", path.display());
            }
        }
    }
}

/// This thread's CPU time (Linux `schedstat`), or wall-clock time elsewhere.
enum Clock {
    Cpu(u64),
    Wall(Instant),
}

impl Clock {
    fn cpu_ns() -> Option<u64> {
        std::fs::read_to_string("/proc/thread-self/schedstat").ok()?.split_whitespace().next()?.parse().ok()
    }

    fn now() -> Clock {
        Clock::cpu_ns().map_or_else(|| Clock::Wall(Instant::now()), Clock::Cpu)
    }

    fn elapsed_ms(&self) -> f64 {
        match self {
            Clock::Cpu(start) => Clock::cpu_ns().map_or(f64::NAN, |now| (now - start) as f64 * 1e-6),
            Clock::Wall(start) => start.elapsed().as_secs_f64() * 1e3,
        }
    }
}

/// LIBERO Tabletop agentview (model_facts.json).
fn agentview(size: u32) -> Camera {
    Camera::new(Vec3::new(0.6586, 0.0, 1.6104), [0.6380, 0.3048, 0.3048, 0.6380], 45.0, size, size)
}

/// robot0_eye_in_hand at the initial joint configuration (model_facts.json).
fn eye_in_hand(size: u32) -> Camera {
    Camera::new(Vec3::new(-0.1566, -0.0190, 1.2703), [0.6878, -0.0119, 0.0200, -0.7255], 75.0, size, size)
}

/// Table, floor, walls, ten turned objects and a twelve-link arm, lit like LIBERO; `detail`
/// multiplies the segment counts of round shapes.
fn libero_like_scene(detail: u32) -> Scene {
    let mut instances = Vec::new();
    let mut seg = 0;
    let mut add = |mesh: &Arc<Mesh>, t: Transform, m: Material| {
        seg += 1;
        instances.push(Instance::new(mesh.clone(), t, seg).with_material(m));
    };
    let at = Transform::from_translation;
    let matte = |r: f32, g: f32, b: f32| Material { rgba: [r, g, b, 1.0], specular: 0.2, shininess: 0.1, ..Material::default() };

    add(&Arc::new(Mesh::grid(3.0, 3.0, 24, 24)), Transform::IDENTITY, Material { uv_scale: Vec2::splat(3.0), ..matte(0.45, 0.45, 0.47) });
    let wall = Arc::new(Mesh::cuboid_tessellated(Vec3::new(1.5, 0.01, 1.5), 4));
    add(&wall, Transform::from_pos_quat(Vec3::new(-2.0, 0.0, 1.5), [std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2]), matte(0.8, 0.8, 0.78));
    add(&wall, at(Vec3::new(0.0, 3.0, 1.5)), matte(0.8, 0.8, 0.78));
    add(&wall, at(Vec3::new(0.0, -3.0, 1.5)), matte(0.8, 0.8, 0.78));
    add(&Arc::new(Mesh::cuboid_tessellated(Vec3::new(0.5, 0.6, 0.025), 4)), at(Vec3::new(0.0, 0.0, 0.875)), matte(0.75, 0.6, 0.45));
    let leg = Arc::new(Mesh::cylinder(0.025, 0.4375, 16 * detail));
    for (x, y) in [(0.4, 0.5), (-0.4, 0.5), (-0.4, -0.5), (0.4, -0.5)] {
        add(&leg, at(Vec3::new(x, y, 0.4375)), matte(0.7, 0.7, 0.7));
    }

    let bowl = Arc::new(Mesh::lathe(&[(0.0, 0.0), (0.035, 0.0), (0.05, 0.03), (0.054, 0.05), (0.05, 0.05), (0.045, 0.03), (0.03, 0.006), (0.0, 0.006)], 24 * detail));
    let plate = Arc::new(Mesh::lathe(&[(0.0, 0.0), (0.05, 0.0), (0.069, 0.015), (0.066, 0.016), (0.048, 0.004), (0.0, 0.004)], 32 * detail));
    let mug = Arc::new(Mesh::lathe_capped(&[(0.04, 0.0), (0.045, 0.1), (0.04, 0.1), (0.036, 0.008), (0.0, 0.008)], 24 * detail));
    let bottle = Arc::new(Mesh::lathe_capped(&[(0.0, 0.0), (0.022, 0.0), (0.022, 0.1), (0.012, 0.13), (0.01, 0.158), (0.0, 0.158)], 20 * detail));
    let can = Arc::new(Mesh::cylinder(0.031, 0.035, 20 * detail));
    let objects: [(&Arc<Mesh>, f32, f32, Material); 10] = [
        (&bowl, -0.05, 0.1, matte(0.08, 0.08, 0.08)),
        (&bowl, 0.1, -0.15, matte(0.08, 0.08, 0.08)),
        (&plate, 0.05, 0.25, matte(0.9, 0.9, 0.9)),
        (&plate, -0.15, -0.2, matte(0.9, 0.9, 0.9)),
        (&mug, 0.2, 0.05, matte(0.85, 0.2, 0.2)),
        (&mug, -0.2, 0.25, matte(0.95, 0.95, 0.9)),
        (&bottle, 0.25, -0.3, matte(0.3, 0.05, 0.1)),
        (&bottle, -0.05, -0.35, matte(0.2, 0.4, 0.1)),
        (&can, 0.15, 0.3, matte(0.7, 0.3, 0.1)),
        (&can, 0.0, -0.05, matte(0.9, 0.8, 0.2)),
    ];
    for (mesh, x, y, m) in objects {
        add(mesh, at(Vec3::new(x, y, 0.9)), m);
    }

    // A Panda-sized chain of capsules and boxes from the base at (−0.66, 0, 0.912).
    let link = Arc::new(Mesh::capsule(0.06, 0.1, 24 * detail));
    let block = Arc::new(Mesh::cuboid(Vec3::new(0.05, 0.05, 0.08)));
    let white = Material { rgba: [0.95, 0.95, 0.95, 1.0], ..Material::default() };
    let mut p = Vec3::new(-0.66, 0.0, 0.95);
    for k in 0..12 {
        let step = Vec3::new(0.045, 0.0, if k < 6 { 0.06 } else { -0.03 });
        p += step;
        let mesh = if k % 3 == 2 { &block } else { &link };
        add(mesh, Transform::from_pos_quat(p, [0.96, 0.0, 0.28, 0.0]), if k % 4 == 3 { matte(0.1, 0.1, 0.1) } else { white.clone() });
    }

    // LIBERO's two scene lights plus MuJoCo's default headlight.
    let light = |pos: Vec3| Light { diffuse: [0.8; 3], cast_shadow: false, ..Light::mujoco_spot(pos, Vec3::new(0.0, -0.15, -1.0)) };
    Scene {
        instances,
        lights: vec![light(Vec3::new(1.0, 1.0, 4.0)), light(Vec3::new(-3.0, -3.0, 4.0))],
        headlight: Headlight::default(),
        background: Background::Gradient { up: [0.9, 0.9, 1.0], down: [0.2, 0.3, 0.4] },
        mirror: None,
    }
}
