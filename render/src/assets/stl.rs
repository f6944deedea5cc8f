//! STL meshes (binary and ASCII) through `stl_io`, with MuJoCo's hard-edge normals.

use std::io::Cursor;

use glam::Vec3;

use super::AssetError;
use crate::mesh::Mesh;

const BINARY_HEADER: usize = 84;
const BINARY_FACE: usize = 50;

/// Parses STL bytes; `name` is used in errors.
pub fn parse_stl(bytes: &[u8], name: &str) -> Result<Mesh, AssetError> {
    let err = |problem: String| AssetError::new(name, problem);
    let ascii = bytes.trim_ascii_start().starts_with(b"solid") && !binary_size_matches(bytes);
    if !ascii {
        // Check the size up front: stl_io would only report an unexpected end of file.
        if bytes.len() < BINARY_HEADER {
            return Err(err(format!("{} bytes is too short for a binary STL header (84 bytes)", bytes.len())));
        }
        let n = triangle_count(bytes);
        let need = binary_size(n);
        if (bytes.len() as u64) < need {
            return Err(err(format!("binary STL declares {n} triangles ({need} bytes) but the file has {} bytes", bytes.len())));
        }
    }
    let indexed = stl_io::read_stl(&mut Cursor::new(bytes)).map_err(|e| err(format!("invalid STL: {e}")))?;
    let positions: Vec<Vec3> = indexed.vertices.iter().map(|v| Vec3::from(v.0)).collect();
    let triangles: Vec<[u32; 3]> = indexed.faces.iter().map(|f| f.vertices.map(|i| i as u32)).collect();
    if triangles.is_empty() {
        return Err(err("no triangles".into()));
    }
    Mesh::with_mujoco_normals(positions, None, None, triangles).map_err(|e| err(e.to_string()))
}

/// Some binary STLs start with "solid" too; trust the size field when it fits exactly.
fn binary_size_matches(bytes: &[u8]) -> bool {
    bytes.len() >= BINARY_HEADER && bytes.len() as u64 == binary_size(triangle_count(bytes))
}

/// The header's triangle count (the file is at least [`BINARY_HEADER`] long).
fn triangle_count(bytes: &[u8]) -> u32 {
    u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]])
}

/// Bytes of a binary STL of `n` triangles, in 64 bits: on a 32-bit target (wasm) the header's
/// count times 50 overflows `usize`.
fn binary_size(n: u32) -> u64 {
    BINARY_HEADER as u64 + u64::from(n) * BINARY_FACE as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary_triangle() -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b.extend_from_slice(&1u32.to_le_bytes());
        let floats: [f32; 12] = [0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0.];
        for f in floats {
            b.extend_from_slice(&f.to_le_bytes());
        }
        b.extend_from_slice(&[0, 0]);
        b
    }

    #[test]
    fn reads_binary_and_ascii() {
        let m = parse_stl(&binary_triangle(), "t.stl").unwrap();
        assert_eq!(m.triangle_count(), 1);
        assert!(m.normals().iter().all(|n| (*n - Vec3::Z).length() < 1e-6));
        let ascii = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        assert_eq!(parse_stl(ascii, "a.stl").unwrap().triangle_count(), 1);
    }

    #[test]
    fn truncated_binary_is_a_sized_error() {
        let b = binary_triangle();
        let e = parse_stl(&b[..100], "micro.stl").unwrap_err();
        assert_eq!(e.file, "micro.stl");
        assert!(e.problem.contains("declares 1 triangles (134 bytes) but the file has 100"), "{e}");
        assert!(parse_stl(b"solid x\nfacet nonsense", "x.stl").is_err());
    }
}
