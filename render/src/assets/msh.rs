//! MuJoCo's legacy binary `.msh` mesh format.
//!
//! Layout (little-endian): four `i32` counts `nvertex, nnormal, ntexcoord, nface`, then
//! `nvertex × 3` `f32` positions, `nnormal × 3` `f32` normals, `ntexcoord × 2` `f32` texture
//! coordinates and `nface × 3` `i32` vertex indices. Normals and texture coordinates are
//! per vertex, so their counts are either 0 or `nvertex`. The file size must match exactly.

use glam::{Vec2, Vec3};

use super::AssetError;
use crate::mesh::Mesh;

const HEADER: usize = 16;

/// Parses `.msh` bytes; `name` is used in errors.
pub fn parse_msh(bytes: &[u8], name: &str) -> Result<Mesh, AssetError> {
    let err = |problem: String| AssetError::new(name, problem);
    if bytes.len() < HEADER {
        return Err(err(format!("{} bytes is too short for the 16-byte header (4 int32 counts)", bytes.len())));
    }
    let int_at = |off: usize| i32::from_le_bytes([bytes[off], bytes[off + 1], bytes[off + 2], bytes[off + 3]]);
    let counts = [int_at(0), int_at(4), int_at(8), int_at(12)];
    let labels = ["nvertex", "nnormal", "ntexcoord", "nface"];
    for (c, label) in counts.iter().zip(labels) {
        if *c < 0 {
            return Err(err(format!("header {label} = {c} is negative")));
        }
    }
    let [nv, nn, nt, nf] = counts.map(|c| c as usize);
    if nv < 3 || nf < 1 {
        return Err(err(format!("expected at least 3 vertices and 1 face, header says {nv} and {nf}")));
    }
    for (n, label) in [(nn, "nnormal"), (nt, "ntexcoord")] {
        if n != 0 && n != nv {
            return Err(err(format!("header {label} = {n} must be 0 or nvertex = {nv}")));
        }
    }
    // Checked throughout: on a 32-bit target (wasm) the header's counts overflow `usize`.
    let expected = [(3, nv), (3, nn), (2, nt), (3, nf)].iter().try_fold(HEADER, |acc, &(k, n)| acc.checked_add(n.checked_mul(k * 4)?));
    match expected {
        Some(e) if e == bytes.len() => {}
        Some(e) => {
            return Err(err(format!(
                "size mismatch: header ({nv} vertices, {nn} normals, {nt} texcoords, {nf} faces) needs {e} bytes, file has {}",
                bytes.len()
            )))
        }
        None => return Err(err("header counts overflow".into())),
    }
    let float_at = |off: usize| f32::from_le_bytes([bytes[off], bytes[off + 1], bytes[off + 2], bytes[off + 3]]);
    let mut off = HEADER;
    let mut floats = |count: usize, what: &str| -> Result<Vec<f32>, AssetError> {
        let start = off;
        let v: Vec<f32> = (0..count).map(|i| float_at(start + 4 * i)).collect();
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(err(format!("{what} value at byte {} is not finite", start + 4 * i)));
        }
        off += 4 * count;
        Ok(v)
    };
    let pos = floats(3 * nv, "vertex")?;
    let nrm = floats(3 * nn, "normal")?;
    let tex = floats(2 * nt, "texcoord")?;
    let faces_at = off;
    let mut triangles = Vec::with_capacity(nf);
    for f in 0..nf {
        let mut tri = [0u32; 3];
        for (k, t) in tri.iter_mut().enumerate() {
            let at = faces_at + 4 * (3 * f + k);
            let i = int_at(at);
            if i < 0 || i as usize >= nv {
                return Err(err(format!("face {f} at byte {at}: vertex index {i} is outside 0..{nv}")));
            }
            *t = i as u32;
        }
        triangles.push(tri);
    }
    let v3 = |v: &[f32]| v.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect::<Vec<_>>();
    let normals = (nn > 0).then(|| v3(&nrm));
    let uvs = (nt > 0).then(|| tex.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect());
    Mesh::with_mujoco_normals(v3(&pos), normals, uvs, triangles).map_err(|e| err(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-triangle `.msh` with normals and texcoords.
    fn tiny() -> Vec<u8> {
        let mut b = Vec::new();
        for c in [3i32, 3, 3, 1] {
            b.extend_from_slice(&c.to_le_bytes());
        }
        let floats: [f32; 9 + 9 + 6] =
            [0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1., 0., 0., 1.];
        for f in floats {
            b.extend_from_slice(&f.to_le_bytes());
        }
        for i in [0i32, 1, 2] {
            b.extend_from_slice(&i.to_le_bytes());
        }
        b
    }

    #[test]
    fn parses_a_valid_file() {
        let m = parse_msh(&tiny(), "t.msh").unwrap();
        assert_eq!((m.vertex_count(), m.triangle_count()), (3, 1));
        assert_eq!(m.uvs().unwrap()[1], Vec2::new(1.0, 0.0));
    }

    #[test]
    fn truncated_file_names_sizes() {
        let b = tiny();
        let e = parse_msh(&b[..b.len() - 2], "bowl.msh").unwrap_err();
        assert_eq!(e.file, "bowl.msh");
        assert!(e.problem.contains("needs 124 bytes, file has 122"), "{e}");
        let e = parse_msh(&b[..10], "bowl.msh").unwrap_err();
        assert!(e.problem.contains("header"), "{e}");
    }

    #[test]
    fn bad_counts_and_indices_are_errors() {
        let mut b = tiny();
        b[4..8].copy_from_slice(&2i32.to_le_bytes());
        assert!(parse_msh(&b, "x").unwrap_err().problem.contains("nnormal = 2"));
        let mut b = tiny();
        let n = b.len();
        b[n - 4..].copy_from_slice(&7i32.to_le_bytes());
        let e = parse_msh(&b, "x").unwrap_err();
        assert!(e.problem.contains("face 0 at byte 120: vertex index 7"), "{e}");
        let mut b = tiny();
        b[0..4].copy_from_slice(&(-1i32).to_le_bytes());
        assert!(parse_msh(&b, "x").unwrap_err().problem.contains("negative"));
        let mut b = tiny();
        b[0..4].copy_from_slice(&i32::MAX.to_le_bytes());
        assert!(parse_msh(&b, "x").is_err());
        let mut b = tiny();
        b[16..20].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(parse_msh(&b, "x").unwrap_err().problem.contains("byte 16"));
    }
}
