//! Wavefront OBJ meshes through `tobj`. All objects in the file are merged into one mesh;
//! materials (`.mtl`) are ignored (colours and textures come from the scene's materials).

use std::io::Cursor;

use glam::{Vec2, Vec3};

use super::AssetError;
use crate::mesh::Mesh;

/// Parses OBJ text; `name` is used in errors. OBJ's `v` runs bottom-up, so it is flipped to
/// this crate's top-down convention.
pub fn parse_obj(bytes: &[u8], name: &str) -> Result<Mesh, AssetError> {
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _materials) = tobj::load_obj_buf(&mut Cursor::new(bytes), &options, |_| Err(tobj::LoadError::OpenFileFailed))
        .map_err(|e| {
            let at = locate_error(bytes, &e).map_or(String::new(), |line| format!("line {line}: "));
            AssetError::new(name, format!("{at}{e}"))
        })?;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut triangles = Vec::new();
    let all_normals = models.iter().all(|m| m.mesh.normals.len() == m.mesh.positions.len());
    let all_uvs = models.iter().all(|m| m.mesh.texcoords.len() / 2 == m.mesh.positions.len() / 3);
    for m in &models {
        let base = positions.len() as u32;
        let mesh = &m.mesh;
        positions.extend(mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        if all_normals {
            normals.extend(mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        }
        if all_uvs {
            uvs.extend(mesh.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], 1.0 - c[1])));
        }
        triangles.extend(mesh.indices.chunks_exact(3).map(|c| [c[0] + base, c[1] + base, c[2] + base]));
    }
    if triangles.is_empty() {
        return Err(AssetError::new(name, "no faces: expected `f` lines with at least 3 vertices"));
    }
    let uvs = (all_uvs && !uvs.is_empty()).then_some(uvs);
    let normals = (all_normals && !normals.is_empty()).then_some(normals);
    Mesh::with_mujoco_normals(positions, normals, uvs, triangles).map_err(|e| AssetError::new(name, e.to_string()))
}

/// `tobj` reports what went wrong but not where: find the first line of the offending kind
/// that does not parse (1-based).
fn locate_error(bytes: &[u8], e: &tobj::LoadError) -> Option<usize> {
    use tobj::LoadError as E;
    let text = String::from_utf8_lossy(bytes);
    let floats_ok = |args: &[&str], counts: &[usize]| counts.contains(&args.len()) && args.iter().all(|a| a.parse::<f32>().is_ok());
    let (mut nv, mut nt, mut nn) = (0i64, 0i64, 0i64);
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let tag = words.next().unwrap_or("");
        let args: Vec<&str> = words.collect();
        let bad = match (tag, e) {
            ("v", E::PositionParseError) => !floats_ok(&args, &[3, 4, 6, 7]),
            ("vn", E::NormalParseError) => !floats_ok(&args, &[3]),
            ("vt", E::TexcoordParseError) => !floats_ok(&args, &[1, 2, 3]),
            ("f", E::FaceParseError | E::InvalidPolygon | E::FaceVertexOutOfBounds | E::FaceTexCoordOutOfBounds | E::FaceNormalOutOfBounds) => {
                args.len() < 3
                    || args.iter().any(|corner| {
                        corner.split('/').zip([nv, nt, nn]).any(|(idx, count)| {
                            !idx.is_empty() && idx.parse::<i64>().map_or(true, |k| k == 0 || k > count || -k > count)
                        })
                    })
            }
            _ => false,
        };
        if bad {
            return Some(i + 1);
        }
        match tag {
            "v" => nv += 1,
            "vt" => nt += 1,
            "vn" => nn += 1,
            _ => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

    #[test]
    fn parses_and_flips_v() {
        let m = parse_obj(QUAD.as_bytes(), "q.obj").unwrap();
        assert_eq!(m.triangle_count(), 2);
        // OBJ vt (0, 0) is the image's bottom-left: v = 1 here.
        let uv = m.uvs().unwrap();
        let i = m.positions().iter().position(|p| *p == Vec3::ZERO).unwrap();
        assert_eq!(uv[i], Vec2::new(0.0, 1.0));
        // Normals computed facing +z for a counter-clockwise face.
        assert!(m.normals().iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
    }

    #[test]
    fn errors_name_the_line() {
        let bad = "v 0 0 0\nv 1 0 0\nv 1 x 0\nf 1 2 3\n";
        let e = parse_obj(bad.as_bytes(), "bad.obj").unwrap_err();
        assert_eq!(e.file, "bad.obj");
        assert!(e.problem.starts_with("line 3:"), "{e}");
        let oob = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
        let e = parse_obj(oob.as_bytes(), "oob.obj").unwrap_err();
        assert!(e.problem.starts_with("line 4:"), "{e}");
        assert!(parse_obj(b"v 0 0 0\n", "empty.obj").unwrap_err().problem.contains("no faces"));
    }
}
