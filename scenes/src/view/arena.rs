//! The static surroundings of each scene class: floor, table top and its legs or base, walls.
//!
//! Geometry restates LIBERO's scene XMLs and arena classes (visual-only geoms: floor plane,
//! `wall_*_visual` boxes, table legs; the living-room and study tables' collision boxes stand in
//! for their meshes). Materials have the XML materials' specular and shininess; with LIBERO's
//! texture files ([`ArenaTextures`]) the floor, the walls and a box table's faces are textured as
//! MuJoCo maps them ([`super::texgen`]), and otherwise drawn in their textures' mean colours (the
//! scene class's). The table legs keep the mean colour in both looks: MuJoCo looks their cube
//! texture up by direction per pixel, which no per-vertex UV can restate.

use std::sync::Arc;

use vifo_render::glam::{Mat3, Vec2, Vec3};
use vifo_render::{Material, Mesh, Texture, Transform, quat_wxyz_to_mat3};

use super::material::textured;
use super::meshes::MeshCache;
use super::texgen::{cube_mapped_box, projected, with_uvs};
use crate::catalog::Recipe;
use crate::scene_class::SceneClass;
use crate::task::ProblemClass;

/// Which segment an arena piece belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArenaPiece {
    Floor,
    /// The work surface and what holds it up.
    Table,
    Walls,
    /// The block the arm stands on (the PiPER's).
    Riser,
}

/// One placed mesh of the arena.
pub struct ArenaPart {
    pub piece: ArenaPiece,
    pub mesh: Arc<Mesh>,
    pub transform: Transform,
    pub material: Material,
}

/// A wall box (all are 3 m high, centred at z = 1.5).
struct Wall {
    /// Centre (x, y).
    center: [f32; 2],
    /// Horizontal unit normal of the room-facing side.
    normal: [f32; 2],
    half_width: f32,
    /// MuJoCo's orientation of the box (w, x, y, z): its local x and y carry the texture.
    quat: [f32; 4],
}

const D: f32 = std::f32::consts::FRAC_1_SQRT_2;
const LEFT_CORNER: [f32; 4] = [0.6532815, 0.6532815, 0.2705981, 0.2705981];
const RIGHT_CORNER: [f32; 4] = [0.6532815, 0.6532815, -0.2705981, -0.2705981];
// LIBERO's XML writes 0.7071, and the walls' texture coordinates follow these numbers as the
// pinned asset look draws them.
#[allow(clippy::approx_constant)]
const LEFT: [f32; 4] = [0.7071, 0.7071, 0.0, 0.0];
#[allow(clippy::approx_constant)]
const RIGHT: [f32; 4] = [0.7071, -0.7071, 0.0, 0.0];
const REAR: [f32; 4] = [0.5, 0.5, 0.5, 0.5];
const FRONT: [f32; 4] = [0.5, 0.5, -0.5, -0.5];

const fn wall(center: [f32; 2], normal: [f32; 2], half_width: f32, quat: [f32; 4]) -> Wall {
    Wall { center, normal, half_width, quat }
}

/// The walls of the tabletop, floor, living-room and study scenes: two corner pieces behind the
/// robot, the long side walls, the rear wall behind the robot and the front wall behind the
/// camera.
const WALLS: [Wall; 6] = [
    wall([-1.25, 2.25], [D, -D], 1.06, LEFT_CORNER),
    wall([-1.25, -2.25], [D, D], 1.06, RIGHT_CORNER),
    wall([1.25, 3.0], [0.0, -1.0], 1.75, LEFT),
    wall([1.25, -3.0], [0.0, 1.0], 1.75, RIGHT),
    wall([-2.0, 0.0], [1.0, 0.0], 1.5, REAR),
    wall([3.0, 0.0], [-1.0, 0.0], 3.0, FRONT),
];

/// The kitchen's walls: a closed rectangle without corner pieces.
const KITCHEN_WALLS: [Wall; 4] = [
    wall([0.5, 3.0], [0.0, -1.0], 2.5, LEFT),
    wall([0.5, -3.0], [0.0, 1.0], 2.5, RIGHT),
    wall([-2.0, 0.0], [1.0, 0.0], 3.0, REAR),
    wall([3.0, 0.0], [-1.0, 0.0], 3.0, FRONT),
];

/// `walls_mat` in every scene XML: `texrepeat` 3 3 with `texuniform`.
const WALL_TEXREPEAT: [f32; 2] = [3.0, 3.0];

const WALL_HALF_HEIGHT: f32 = 1.5;
/// The PiPER's riser: dark grey aluminium.
const ROBOT_RISER_RGB: [f64; 3] = [0.3, 0.3, 0.32];
/// Half-thickness of LIBERO's wall boxes; only their room-facing side is drawn.
const WALL_HALF_THICKNESS: f32 = 0.01;

/// Boxes (centre, half-size, world axis-aligned) holding a table up.
fn table_supports(problem: ProblemClass) -> &'static [([f64; 3], [f64; 3])] {
    match problem {
        // The living-room table's lower cabinet.
        ProblemClass::LivingRoomTabletop => &[([-0.25, 0.25, 0.2041], [0.4116, 0.4352, 0.2088])],
        // The study desk's four legs and two floor rails.
        ProblemClass::StudyTabletop => &[
            ([-0.5005, -0.6906, 0.3943], [0.02, 0.0503, 0.3941]),
            ([0.4962, -0.6906, 0.3943], [0.02, 0.0503, 0.3941]),
            ([0.4962, 0.7097, 0.3943], [0.02, 0.0503, 0.3941]),
            ([-0.5005, 0.7147, 0.3943], [0.02, 0.0503, 0.3941]),
            ([-0.0049, 0.7147, 0.0253], [0.5126, 0.0503, 0.02]),
            ([-0.0049, -0.6976, 0.0253], [0.5126, 0.0503, 0.02]),
        ],
        _ => &[],
    }
}

/// The four round legs of the 1.0 × 1.2 m table (tabletop and kitchen scenes).
const TABLE_LEGS: [[f64; 2]; 4] = [[0.4, 0.5], [-0.4, 0.5], [-0.4, -0.5], [0.4, -0.5]];
const TABLE_LEG_RADIUS: f64 = 0.025;

/// A textured MuJoCo material drawn in its texture's mean colour `rgb`.
fn surface(rgb: [f64; 3], specular: f32, shininess: f32) -> Material {
    textured([rgb[0] as f32, rgb[1] as f32, rgb[2] as f32, 1.0], specular, shininess)
}

/// Specular and shininess of the table top and of the walls, from each scene XML: the plain
/// tables' `table_texture`, the living-room and study tables' asset materials (MuJoCo defaults),
/// and `walls_mat`.
fn finishes(problem: ProblemClass) -> ((f32, f32), (f32, f32)) {
    match problem {
        ProblemClass::Tabletop | ProblemClass::Floor | ProblemClass::PiperTabletop => ((0.2, 0.0), (0.8, 0.1)),
        ProblemClass::KitchenTabletop => ((0.2, 0.0), (0.8, 0.3)),
        ProblemClass::LivingRoomTabletop => ((0.5, 0.5), (0.9, 0.2)),
        ProblemClass::StudyTabletop | ProblemClass::CoffeeTable => ((0.5, 0.5), (0.8, 0.1)),
    }
}

fn at(p: [f64; 3]) -> Transform {
    Transform::from_translation(Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
}

/// LIBERO's texture files of the arena where they were found (the asset look); a piece whose
/// texture is `None` is drawn in that texture's mean colour.
#[derive(Clone, Default)]
pub struct ArenaTextures {
    pub floor: Option<Arc<Texture>>,
    /// The box table's cube texture (`table_texture`).
    pub table: Option<Arc<Texture>>,
    /// `walls_mat`'s texture.
    pub walls: Option<Arc<Texture>>,
}

/// Largest quad of a textured box face, in metres, for per-vertex lighting across the table top.
const TEXTURED_QUAD: f32 = 0.05;

/// Every static piece of `class`'s arena.
pub fn arena(class: &SceneClass, meshes: &mut MeshCache, textures: &ArenaTextures) -> Vec<ArenaPart> {
    let mut parts = Vec::new();
    // Floor: MuJoCo draws its 3 × 3 m plane as a grid; ours is split finely enough for the spot
    // lights' fall-off.
    let ((table_specular, table_shininess), (wall_specular, wall_shininess)) = finishes(class.problem);
    let floor = match &textures.floor {
        Some(texture) => floor_material(texture.clone()),
        None => surface(class.floor.rgb, 0.0, 0.0),
    };
    parts.push(ArenaPart { piece: ArenaPiece::Floor, mesh: Arc::new(Mesh::grid(3.0, 3.0, 16, 16)), transform: Transform::IDENTITY, material: floor });

    if let Some(table) = &class.table {
        let top = surface(table.rgb, table_specular, table_shininess);
        for slab in table.top {
            let (mesh, material) = match &textures.table {
                Some(texture) => {
                    let half = Vec3::new(slab.half_size[0] as f32, slab.half_size[1] as f32, slab.half_size[2] as f32);
                    let material = Material { specular: table_specular, shininess: table_shininess, texture: Some(texture.clone()), ..Material::default() };
                    (Arc::new(cube_mapped_box(half, TEXTURED_QUAD)), material)
                }
                None => (meshes.get(&Recipe::Box { half: slab.half_size }), top.clone()),
            };
            parts.push(ArenaPart { piece: ArenaPiece::Table, mesh, transform: at(slab.center), material });
        }
        if matches!(class.problem, ProblemClass::Tabletop | ProblemClass::KitchenTabletop | ProblemClass::PiperTabletop) {
            let half_height = table.top_z() / 2.0 - table.top[0].half_size[2];
            let leg = meshes.get(&Recipe::Cylinder { radius: TABLE_LEG_RADIUS, half_height });
            for [x, y] in TABLE_LEGS {
                // `table_legs`: MuJoCo's default specular, shininess 0.8.
                let material = surface(table.rgb, 0.5, 0.8);
                parts.push(ArenaPart { piece: ArenaPiece::Table, mesh: leg.clone(), transform: at([x, y, half_height]), material });
            }
        }
        if let Some(riser) = &class.robot_riser {
            let material = surface(ROBOT_RISER_RGB, 0.5, 0.5);
            parts.push(ArenaPart { piece: ArenaPiece::Riser, mesh: meshes.get(&Recipe::Box { half: riser.half_size }), transform: at(riser.center), material });
        }
        for &(center, half) in table_supports(class.problem) {
            parts.push(ArenaPart { piece: ArenaPiece::Table, mesh: meshes.get(&Recipe::Box { half }), transform: at(center), material: top.clone() });
        }
    }

    let walls: &[Wall] = if class.problem == ProblemClass::KitchenTabletop { &KITCHEN_WALLS } else { &WALLS };
    let plain_wall = surface(class.wall_rgb, wall_specular, wall_shininess);
    for w in walls {
        // A grid facing local +z = the room, local y = world up.
        let ([x, y], [nx, ny]) = (w.center, w.normal);
        let normal = Vec3::new(nx, ny, 0.0);
        let axes = Mat3::from_cols(Vec3::Z.cross(normal), Vec3::Z, normal);
        let face = Vec3::new(x, y, WALL_HALF_HEIGHT) + normal * WALL_HALF_THICKNESS;
        let transform = Transform::from_pos_mat3(face, axes);
        let grid = Mesh::grid(w.half_width, WALL_HALF_HEIGHT, 4, 4);
        let (mesh, material) = match &textures.walls {
            Some(texture) => {
                // The texture follows MuJoCo's box frame, whose axes need not be the grid's.
                let to_box = quat_wxyz_to_mat3(w.quat).transpose();
                let center = Vec3::new(x, y, WALL_HALF_HEIGHT);
                let half = Vec3::new(w.half_width, WALL_HALF_HEIGHT, WALL_HALF_THICKNESS);
                let mesh = with_uvs(&grid, |p, _| projected(to_box * (transform.transform_point(p) - center), half, WALL_TEXREPEAT));
                let material = Material { specular: wall_specular, shininess: wall_shininess, texture: Some(texture.clone()), ..Material::default() };
                (mesh, material)
            }
            None => (grid, plain_wall.clone()),
        };
        parts.push(ArenaPart { piece: ArenaPiece::Walls, mesh: Arc::new(mesh), transform, material });
    }
    parts
}

/// LIBERO's `floorplane` material with its texture: specular and shininess 0, `texrepeat` 3 with
/// `texuniform`, which MuJoCo draws as 9 repeats across the 6 m floor (the render crate's README).
fn floor_material(texture: Arc<Texture>) -> Material {
    Material { specular: 0.0, shininess: 0.0, texture: Some(texture), uv_scale: Vec2::splat(9.0), ..Material::default() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_class::scene_class;

    fn solid() -> Option<Arc<Texture>> {
        Some(Arc::new(Texture::solid([200, 180, 150, 255])))
    }

    /// Both looks: mean colours, and every texture found.
    fn looks() -> [ArenaTextures; 2] {
        [ArenaTextures::default(), ArenaTextures { floor: solid(), table: solid(), walls: solid() }]
    }

    #[test]
    fn walls_face_the_room() {
        for (class, textures) in ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)).flat_map(|c| looks().map(|t| (c, t))) {
            let parts = arena(class, &mut MeshCache::default(), &textures);
            let walls: Vec<_> = parts.iter().filter(|p| p.piece == ArenaPiece::Walls).collect();
            assert!(walls.len() >= 4, "{:?}", class.problem);
            for w in walls {
                // The face normal (local +z) points from the wall towards the table's centre.
                let normal = w.transform.transform_vector(Vec3::Z);
                let to_centre = Vec3::new(0.0, 0.0, 1.5) - w.transform.translation;
                assert!(normal.dot(to_centre) > 0.0, "{:?}: wall at {}", class.problem, w.transform.translation);
                assert_eq!(w.material.texture.is_some(), textures.walls.is_some());
            }
        }
    }

    #[test]
    fn table_pieces_stay_below_the_work_surface() {
        for (class, textures) in ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)).flat_map(|c| looks().map(|t| (c, t))) {
            let Some(table) = class.table else { continue };
            for p in arena(class, &mut MeshCache::default(), &textures).iter().filter(|p| p.piece == ArenaPiece::Table) {
                let top = p.mesh.positions().iter().map(|&v| p.transform.transform_point(v).z).fold(f32::MIN, f32::max);
                assert!(top <= table.top_z() as f32 + 1e-4, "{:?}: {top}", class.problem);
            }
        }
    }

    #[test]
    fn the_textured_table_is_the_same_box_with_the_image_on_each_face() {
        let class = scene_class(ProblemClass::Tabletop).unwrap();
        let [plain, textured] = looks().map(|t| arena(class, &mut MeshCache::default(), &t));
        let slab = |parts: &[ArenaPart]| parts.iter().find(|p| p.piece == ArenaPiece::Table).map(|p| (p.mesh.half_extent(), p.transform.translation, p.material.texture.is_some())).unwrap();
        let ((h0, c0, t0), (h1, c1, t1)) = (slab(&plain), slab(&textured));
        assert!(h0 == h1 && c0 == c1 && !t0 && t1, "{h0} {h1} {c0} {c1}");
        // The legs keep their mean colour in both looks.
        let legs = textured.iter().filter(|p| p.piece == ArenaPiece::Table && p.material.texture.is_none()).count();
        assert_eq!(legs, TABLE_LEGS.len());
        // The living room's and the study's tables are meshes: no box texture.
        assert!(scene_class(ProblemClass::LivingRoomTabletop).unwrap().table.unwrap().texture.is_none());
    }

    #[test]
    fn wall_textures_follow_mujocos_box_axes_at_one_and_a_half_repeats_per_metre() {
        let class = scene_class(ProblemClass::Tabletop).unwrap();
        let parts = arena(class, &mut MeshCache::default(), &looks()[1]);
        // The side walls at y = +3 and y = -3: MuJoCo turns the first's box y up and the
        // second's down, and both boxes' x along world +x (their XML quats).
        for (y, up) in [(3.0f32, -1.5f32), (-3.0, 1.5)] {
            let wall = parts.iter().find(|p| p.piece == ArenaPiece::Walls && (p.transform.translation.y.abs() - 2.99).abs() < 0.02 && p.transform.translation.y.signum() == y.signum()).unwrap();
            let uvs = wall.mesh.uvs().unwrap();
            let world: Vec<Vec3> = wall.mesh.positions().iter().map(|&p| wall.transform.transform_point(p)).collect();
            for i in 1..world.len() {
                let (dp, duv) = (world[i] - world[0], uvs[i] - uvs[0]);
                assert!((duv.x - 1.5 * dp.x).abs() < 1e-4 && (duv.y - up * dp.z).abs() < 1e-4, "y {y}: {dp} {duv}");
            }
        }
    }
}
