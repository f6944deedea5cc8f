//! The render crate's camera against LIBERO's own agentview image: the Tabletop table and floor
//! rendered from model_facts.json's agentview pose must land where MuJoCo drew them (skipped
//! when `../shared` is absent). A side-by-side image is written for a look by eye.

use std::path::Path;
use std::sync::Arc;

use vifo_render::assets::load_texture_png;
use vifo_render::glam::{Vec2, Vec3};
use vifo_render::imageio::{load_png, save_png, side_by_side};
use vifo_render::{Background, Camera, Headlight, Instance, Light, Material, Mesh, Renderer, Scene, Transform};
use vifo_tests::shared;

const TABLE: u32 = 1;

/// LIBERO's Tabletop arena from the facts in the scene XML and model_facts.json: floor plane
/// (half-size 3 m, tile texture repeated 3× per unit of half-size), table top box, four legs,
/// walls, and the two spot lights.
fn tabletop(textures: &Path) -> Scene {
    let tex = |name: &str| Some(Arc::new(load_texture_png(textures.join(name)).unwrap()));
    let floor = Material { specular: 0.0, shininess: 0.0, texture: tex("light-gray-floor-tile.png"), uv_scale: Vec2::splat(9.0), ..Material::default() };
    let wood = Material { specular: 0.2, shininess: 0.0, texture: tex("martin_novak_wood_table.png"), ..Material::default() };
    let legs = Material { shininess: 0.8, texture: wood.texture.clone(), ..Material::default() };
    let walls = Material { specular: 0.8, shininess: 0.1, texture: tex("light-gray-plaster.png"), uv_scale: Vec2::splat(3.0), ..Material::default() };
    let mut instances = vec![
        Instance::new(Arc::new(Mesh::grid(3.0, 3.0, 24, 24)), Transform::IDENTITY, 2).with_material(floor),
        Instance::new(Arc::new(Mesh::cuboid_tessellated(Vec3::new(0.5, 0.6, 0.025), 4)), Transform::from_translation(Vec3::new(0.0, 0.0, 0.875)), TABLE)
            .with_material(wood),
    ];
    let leg = Arc::new(Mesh::cylinder(0.025, 0.4375, 28));
    for (x, y) in [(0.4, 0.5), (-0.4, 0.5), (-0.4, -0.5), (0.4, -0.5)] {
        instances.push(Instance::new(leg.clone(), Transform::from_translation(Vec3::new(x, y, 0.4375)), 3).with_material(legs.clone()));
    }
    // Walls: (position, quaternion w x y z, half-size).
    const H: f32 = std::f32::consts::FRAC_1_SQRT_2;
    let wall_geoms = [
        ([-1.25, 2.25, 1.5], [0.6532815, 0.6532815, 0.2705981, 0.2705981], [1.06, 1.5, 0.01]),
        ([-1.25, -2.25, 1.5], [0.6532815, 0.6532815, -0.2705981, -0.2705981], [1.06, 1.5, 0.01]),
        ([1.25, 3.0, 1.5], [H, H, 0.0, 0.0], [1.75, 1.5, 0.01]),
        ([1.25, -3.0, 1.5], [H, -H, 0.0, 0.0], [1.75, 1.5, 0.01]),
        ([-2.0, 0.0, 1.5], [0.5, 0.5, 0.5, 0.5], [1.5, 1.5, 0.01]),
        ([3.0, 0.0, 1.5], [0.5, 0.5, -0.5, -0.5], [3.0, 1.5, 0.01]),
    ];
    for (pos, quat, half) in wall_geoms {
        let mesh = Arc::new(Mesh::cuboid_tessellated(Vec3::from(half), 4));
        instances.push(Instance::new(mesh, Transform::from_pos_quat(Vec3::from(pos), quat), 4).with_material(walls.clone()));
    }
    let light = |x: f32, y: f32| Light {
        diffuse: [0.8; 3],
        cast_shadow: false,
        ..Light::mujoco_spot(Vec3::new(x, y, 4.0), Vec3::new(0.0, -0.15, -1.0))
    };
    Scene {
        instances,
        lights: vec![light(1.0, 1.0), light(-3.0, -3.0)],
        headlight: Headlight::default(),
        background: Background::Gradient { up: [0.9, 0.9, 1.0], down: [0.2, 0.3, 0.4] },
        mirror: None,
    }
}

#[test]
fn agentview_puts_the_table_where_libero_draws_it() {
    let Some(textures) = shared("libero/libero/libero/assets/textures", "agentview_table") else { return };
    let Some(reference) = shared("xval/libero_reference/libero_spatial_task0_init0_agentview_step00.png", "agentview_table") else {
        return;
    };
    // model_facts.json, LIBERO_Tabletop_Manipulation, agentview world pose; fovy 45°.
    let cam = Camera::new(Vec3::new(0.658_613_2, 0.0, 1.610_35), [0.638_017_7, 0.304_849_7, 0.304_849_8, 0.638_017_7], 45.0, 256, 256);
    let frame = Renderer::default().render(&tabletop(&textures), &cam).unwrap();
    let reference = load_png(reference).unwrap();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("libero_agentview_table.png");
    save_png(&side_by_side(&frame.color, &reference, 4), &out).unwrap();
    println!("side by side (ours | LIBERO): {}", out.display());

    // Where LIBERO's image shows only the arena (not the robot or objects, which are not in
    // our scene), colours agree to within a few levels: same camera, lights, lighting model and
    // texture mapping. About 30 % of the image is robot, cabinet and objects.
    let close = (0..256u32)
        .flat_map(|y| (0..256u32).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (a, b) = (frame.color.pixel(x, y), reference.pixel(x, y));
            (0..3).all(|c| (a[c] as i32 - b[c] as i32).abs() <= 8)
        })
        .count();
    let fraction = close as f32 / (256.0 * 256.0);
    println!("{:.1} % of pixels within 8 levels of LIBERO's", 100.0 * fraction);
    assert!(fraction > 0.65, "only {:.1} % of pixels match", 100.0 * fraction);

    // The table's far edge, in the columns right of the robot where nothing stands on it: the
    // first row of table in our segmentation against the first row of wood (red well above
    // blue) in LIBERO's image.
    let wood = |x: u32, y: u32| {
        let [r, _, b] = reference.pixel(x, y);
        r as i32 - b as i32 > 18
    };
    for x in (176..256).step_by(8) {
        let ours = (0..256).find(|&y| frame.segment_at(x, y) == TABLE).unwrap();
        let theirs = (0..256).find(|&y| wood(x, y)).unwrap();
        assert!((ours as i32 - theirs as i32).abs() <= 1, "column {x}: table edge at row {ours}, LIBERO's at {theirs}");
    }
}
