//! Texture coordinates for the arena's boxes, as MuJoCo 2.3.7 generates them.
//!
//! MuJoCo draws a box as the unit box `[-1, 1]³` scaled to its size, and OpenGL generates the
//! texture coordinates from those unit coordinates (`settexture` in `render_gl3.c`,
//! `GL_OBJECT_LINEAR`):
//! - a 2D texture is projected along the box's z: `s = ½·k₀·x − ½`, `t = −½·k₁·y − ½`, with
//!   `k = texrepeat`, times the box's half-size under `texuniform` (so it repeats per metre; the
//!   only form LIBERO uses);
//! - a cube texture is looked up by the direction `(x, y, z)`. Without `texuniform` the major
//!   axis on each face of the unit box is that face's own, so every face shows the whole image
//!   once, turned as OpenGL's cube-map faces are.
//!
//! Meshes carry the result as UVs (`v = t`: rows from the image's first, as [`Mesh`] counts them).

use vifo_render::Mesh;
use vifo_render::glam::{Vec2, Vec3};

/// The UV of a 2D texture at `local` (metres, in the box's own frame) on a box of half-size
/// `half`, repeated `repeat` times per unit length (`texuniform`, as on every 2D-textured box
/// LIBERO has: its walls).
pub fn projected(local: Vec3, half: Vec3, repeat: [f32; 2]) -> Vec2 {
    let k = Vec2::new(repeat[0] * half.x, repeat[1] * half.y);
    Vec2::new(0.5 * k.x * (local.x / half.x) - 0.5, -0.5 * k.y * (local.y / half.y) - 0.5)
}

/// The UV of a cube texture at `unit` (a point of the unit box) on the face whose outward normal
/// is `normal`: OpenGL's cube-map face table, `(sc / |ma| + 1) / 2` and `(tc / |ma| + 1) / 2`.
fn cube_face(unit: Vec3, normal: Vec3) -> Vec2 {
    let a = normal.abs();
    let (sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if normal.x > 0.0 { (-unit.z, -unit.y, unit.x) } else { (unit.z, -unit.y, unit.x) }
    } else if a.y >= a.z {
        if normal.y > 0.0 { (unit.x, unit.z, unit.y) } else { (unit.x, -unit.z, unit.y) }
    } else if normal.z > 0.0 {
        (unit.x, -unit.y, unit.z)
    } else {
        (-unit.x, -unit.y, unit.z)
    };
    let ma = ma.abs();
    Vec2::new(0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
}

/// A box of half-size `half` with a cube texture on every face as MuJoCo maps it (no
/// `texuniform`), each face split into quads at most `quad` metres on a side: lighting is per
/// vertex, as in MuJoCo, and a large face lit only at its corners shows no spot-light fall-off.
pub fn cube_mapped_box(half: Vec3, quad: f32) -> Mesh {
    with_uvs(&Mesh::cuboid_with_quads_at_most(half, quad), |p, n| cube_face(p / half, n))
}

/// `mesh` with each vertex's UV given by `uv(position, normal)`; positions, normals and
/// triangles stay as they are.
pub fn with_uvs(mesh: &Mesh, uv: impl Fn(Vec3, Vec3) -> Vec2) -> Mesh {
    let uvs = mesh.positions().iter().zip(mesh.normals()).map(|(&p, &n)| uv(p, n)).collect();
    Mesh::new(mesh.positions().to_vec(), mesh.normals().to_vec(), Some(uvs), mesh.triangles().to_vec())
        .expect("finite positions give finite generated UVs")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_2d_texture_repeats_per_metre_under_texuniform() {
        let half = Vec3::new(1.75, 1.5, 0.01);
        // texrepeat 3 with texuniform: 1.5 repeats per metre of the box's own x and y.
        let a = projected(Vec3::new(0.0, 0.0, 0.01), half, [3.0, 3.0]);
        let b = projected(Vec3::new(1.0, -2.0, 0.01), half, [3.0, 3.0]);
        assert_eq!(a, Vec2::new(-0.5, -0.5));
        assert!((b - a - Vec2::new(1.5, 3.0)).length() < 1e-5, "{b}");
    }

    #[test]
    fn cube_faces_follow_opengl_and_show_the_image_once() {
        // +z: s along x, t against y; the top face's corners are the image's.
        assert_eq!(cube_face(Vec3::new(-1.0, 1.0, 1.0), Vec3::Z), Vec2::new(0.0, 0.0));
        assert_eq!(cube_face(Vec3::new(1.0, -1.0, 1.0), Vec3::Z), Vec2::new(1.0, 1.0));
        // +x: s against z, t against y. -y: s along x, t against z.
        assert_eq!(cube_face(Vec3::new(1.0, 1.0, 1.0), Vec3::X), Vec2::new(0.0, 0.0));
        assert_eq!(cube_face(Vec3::new(1.0, -1.0, 1.0), Vec3::NEG_Y), Vec2::new(1.0, 0.0));
        // A face's own axis decides even where another coordinate ties it (the box's edges).
        assert_eq!(cube_face(Vec3::new(1.0, 0.0, 1.0), Vec3::Z), Vec2::new(1.0, 0.5));
    }

    #[test]
    fn a_cube_mapped_box_covers_each_face_with_the_whole_image() {
        let half = Vec3::new(0.5, 0.6, 0.025);
        let mesh = cube_mapped_box(half, 0.05);
        let (lo, hi) = mesh.positions().iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        assert!((lo + half).abs().max_element() < 1e-6 && (hi - half).abs().max_element() < 1e-6, "{lo} {hi}");
        let uvs = mesh.uvs().unwrap();
        for n in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z] {
            let on: Vec<Vec2> = mesh.normals().iter().zip(uvs).filter(|(m, _)| **m == n).map(|(_, &uv)| uv).collect();
            let (a, b) = on.iter().fold((Vec2::MAX, Vec2::MIN), |(a, b), &uv| (a.min(uv), b.max(uv)));
            assert!(a.abs().max_element() < 1e-6 && (b - Vec2::ONE).abs().max_element() < 1e-6, "{n}: {a} {b}");
        }
        // The top: 20 × 24 quads of 5 cm, two triangles each.
        let top = mesh.triangles().iter().filter(|t| mesh.normals()[t[0] as usize] == Vec3::Z).count();
        assert_eq!(top, 2 * 20 * 24);
    }
}
