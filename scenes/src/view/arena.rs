//! The static surroundings of each scene class: floor, table top and its legs or base, walls.
//!
//! Geometry restates LIBERO's scene XMLs and arena classes (visual-only geoms: floor plane,
//! `wall_*_visual` boxes, table legs; the living-room and study tables' collision boxes stand in
//! for their meshes). Materials are plain colours from the scene class (the mean colours of
//! LIBERO's style textures) with the XML materials' specular and shininess.

use std::sync::Arc;

use vifo_render::glam::{Mat3, Vec3};
use vifo_render::{Material, Mesh, Texture, Transform};

use super::material::textured;
use super::meshes::MeshCache;
use crate::catalog::Recipe;
use crate::scene_class::{SceneClass, Table};
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

/// A wall: centre of the box (x, y; all walls are 3 m high, centred at z = 1.5), the
/// horizontal unit normal of its room-facing side, half-width.
type Wall = ([f32; 2], [f32; 2], f32);

const D: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The walls of the tabletop, floor, living-room and study scenes: two corner pieces behind the
/// robot, the long side walls, the rear wall behind the robot and the front wall behind the
/// camera.
const WALLS: [Wall; 6] = [
    ([-1.25, 2.25], [D, -D], 1.06),
    ([-1.25, -2.25], [D, D], 1.06),
    ([1.25, 3.0], [0.0, -1.0], 1.75),
    ([1.25, -3.0], [0.0, 1.0], 1.75),
    ([-2.0, 0.0], [1.0, 0.0], 1.5),
    ([3.0, 0.0], [-1.0, 0.0], 3.0),
];

/// The kitchen's walls: a closed rectangle without corner pieces.
const KITCHEN_WALLS: [Wall; 4] = [
    ([0.5, 3.0], [0.0, -1.0], 2.5),
    ([0.5, -3.0], [0.0, 1.0], 2.5),
    ([-2.0, 0.0], [1.0, 0.0], 3.0),
    ([3.0, 0.0], [-1.0, 0.0], 3.0),
];

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

/// Every static piece of `class`'s arena.
pub fn arena(class: &SceneClass, meshes: &mut MeshCache) -> Vec<ArenaPart> {
    let mut parts = Vec::new();
    // Floor: MuJoCo draws its 3 × 3 m plane as a grid; ours is split finely enough for the spot
    // lights' fall-off.
    let ((table_specular, table_shininess), (wall_specular, wall_shininess)) = finishes(class.problem);
    let floor = surface(class.floor.rgb, 0.0, 0.0);
    parts.push(ArenaPart { piece: ArenaPiece::Floor, mesh: Arc::new(Mesh::grid(3.0, 3.0, 16, 16)), transform: Transform::IDENTITY, material: floor });

    if let Some(table) = &class.table {
        let top = surface(table.rgb, table_specular, table_shininess);
        for slab in table.top {
            let mesh = meshes.get(&Recipe::Box { half: slab.half_size });
            parts.push(ArenaPart { piece: ArenaPiece::Table, mesh, transform: at(slab.center), material: top.clone() });
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
    let wall = surface(class.wall_rgb, wall_specular, wall_shininess);
    for &([x, y], [nx, ny], half_width) in walls {
        // A grid facing local +z = the room, local y = world up.
        let normal = Vec3::new(nx, ny, 0.0);
        let axes = Mat3::from_cols(Vec3::Z.cross(normal), Vec3::Z, normal);
        let face = Vec3::new(x, y, WALL_HALF_HEIGHT) + normal * WALL_HALF_THICKNESS;
        let mesh = Arc::new(Mesh::grid(half_width, WALL_HALF_HEIGHT, 4, 4));
        parts.push(ArenaPart { piece: ArenaPiece::Walls, mesh, transform: Transform::from_pos_mat3(face, axes), material: wall.clone() });
    }
    parts
}

/// Height of the textured cover above the table top: far below a pixel, far above depth noise.
const COVER_LIFT: f64 = 5e-4;
/// Quads per metre of the cover, for per-vertex lighting as on the box faces.
const COVER_QUADS_PER_M: f64 = 20.0;

/// The top faces of a box table drawn with its texture (LIBERO's `table_texture`: a cube
/// texture, `texrepeat` 1 without `texuniform`, specular 0.2, shininess 0). MuJoCo generates
/// cube-map coordinates from the unit box, so the top face shows the whole image once, stretched
/// over the top; the grain (the image's rows) runs along world x, as in MuJoCo's frames.
pub fn table_cover(table: &Table, texture: Arc<Texture>) -> Vec<ArenaPart> {
    let material = Material { specular: 0.2, shininess: 0.0, texture: Some(texture), ..Material::default() };
    table
        .top
        .iter()
        .map(|slab| {
            let [hx, hy, hz] = slab.half_size;
            let quads = |h: f64| ((2.0 * h * COVER_QUADS_PER_M).ceil() as u32).max(1);
            let mesh = Arc::new(Mesh::grid(hx as f32, hy as f32, quads(hx), quads(hy)));
            let [x, y, z] = slab.center;
            ArenaPart { piece: ArenaPiece::Table, mesh, transform: at([x, y, z + hz + COVER_LIFT]), material: material.clone() }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_class::scene_class;

    #[test]
    fn walls_face_the_room() {
        for class in ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)) {
            let parts = arena(class, &mut MeshCache::default());
            let walls: Vec<_> = parts.iter().filter(|p| p.piece == ArenaPiece::Walls).collect();
            assert!(walls.len() >= 4, "{:?}", class.problem);
            for w in walls {
                // The face normal (local +z) points from the wall towards the table's centre.
                let normal = w.transform.transform_vector(Vec3::Z);
                let to_centre = Vec3::new(0.0, 0.0, 1.5) - w.transform.translation;
                assert!(normal.dot(to_centre) > 0.0, "{:?}: wall at {}", class.problem, w.transform.translation);
            }
        }
    }

    #[test]
    fn table_pieces_stay_below_the_work_surface() {
        for class in ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)) {
            let Some(table) = class.table else { continue };
            for p in arena(class, &mut MeshCache::default()).iter().filter(|p| p.piece == ArenaPiece::Table) {
                let top = p.mesh.positions().iter().map(|&v| p.transform.transform_point(v).z).fold(f32::MIN, f32::max);
                assert!(top <= table.top_z() as f32 + 1e-4, "{:?}: {top}", class.problem);
            }
        }
    }

    #[test]
    fn the_table_cover_spans_the_top_once_just_above_it() {
        let class = scene_class(ProblemClass::Tabletop).unwrap();
        let table = class.table.unwrap();
        let cover = table_cover(&table, Arc::new(Texture::solid([200, 180, 150, 255])));
        assert_eq!(cover.len(), table.top.len());
        let part = &cover[0];
        assert!(part.material.texture.is_some() && part.material.uv_scale == vifo_render::glam::Vec2::ONE);
        let world: Vec<Vec3> = part.mesh.positions().iter().map(|&v| part.transform.transform_point(v)).collect();
        let (lo, hi) = world.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let [cx, cy, _] = table.top[0].center;
        let [hx, hy, _] = table.top[0].half_size;
        assert!((lo.x as f64 - (cx - hx)).abs() < 1e-6 && (hi.y as f64 - (cy + hy)).abs() < 1e-6, "{lo} {hi}");
        let lift = lo.z as f64 - table.top_z();
        assert!(lo.z == hi.z && lift > 0.0 && lift < 1e-3, "{lift}");
        let uvs = part.mesh.uvs().unwrap();
        let (umin, umax) = uvs.iter().fold((f32::MAX, f32::MIN), |(a, b), t| (a.min(t.x), b.max(t.x)));
        assert!(umin == 0.0 && umax == 1.0);
        // The living room's and the study's tables are meshes: no box texture.
        assert!(scene_class(ProblemClass::LivingRoomTabletop).unwrap().table.unwrap().texture.is_none());
    }
}
