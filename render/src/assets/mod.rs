//! Loaders for meshes and textures from a user's LIBERO checkout, given at run time.
//!
//! Nothing here is needed to render: scenes can be built from procedural meshes alone. Every
//! loader has a `parse_*` form taking bytes (usable in wasm) and a `load_*` form taking a path.
//! Errors name the file, the position (byte offset or line) and what was expected.
//!
//! Conventions match MuJoCo: texture `v = 0` is the top image row (OBJ's bottom-up `v` is
//! flipped on load, `.msh` UVs are used as stored); meshes without UVs get MuJoCo's hard-edge
//! normals ([`crate::Mesh::with_mujoco_normals`], which also shares equal vertices). Vertex
//! positions are returned as stored: MuJoCo's compiler re-centres meshes but moves the geom frame
//! to compensate, so raw vertices placed at the XML geom pose (and `scale`) appear where MuJoCo
//! draws them.

mod msh;
mod obj;
mod stl;

use std::path::Path;

use thiserror::Error;

use crate::imageio::decode_png_rgba;
use crate::mesh::Mesh;
use crate::texture::Texture;

pub use msh::parse_msh;
pub use obj::parse_obj;
pub use stl::parse_stl;

/// A file that could not be loaded, and why.
#[derive(Debug, Error, PartialEq)]
#[error("{file}: {problem}")]
pub struct AssetError {
    pub file: String,
    pub problem: String,
}

impl AssetError {
    pub(crate) fn new(file: &str, problem: impl Into<String>) -> AssetError {
        AssetError { file: file.to_string(), problem: problem.into() }
    }
}

fn read(path: &Path) -> Result<Vec<u8>, AssetError> {
    std::fs::read(path).map_err(|e| AssetError::new(&path.display().to_string(), format!("cannot read: {e}")))
}

/// Loads a mesh file, choosing the format by extension (`.msh`, `.obj`, `.stl`).
pub fn load_mesh(path: impl AsRef<Path>) -> Result<Mesh, AssetError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let parse = parser_for(&name)?;
    parse(&read(path)?, &name)
}

/// Parses a mesh file's bytes, choosing the format by the extension of its `name` (`.msh`,
/// `.obj`, `.stl`).
pub fn parse_mesh(bytes: &[u8], name: &str) -> Result<Mesh, AssetError> {
    parser_for(name)?(bytes, name)
}

/// A mesh format's parser: bytes and the file's name to the mesh.
type MeshParser = fn(&[u8], &str) -> Result<Mesh, AssetError>;

fn parser_for(name: &str) -> Result<MeshParser, AssetError> {
    let ext = Path::new(name).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("msh") => Ok(parse_msh),
        Some("obj") => Ok(parse_obj),
        Some("stl") => Ok(parse_stl),
        _ => Err(AssetError::new(name, "unknown mesh format: expected a .msh, .obj or .stl file")),
    }
}

/// Decodes a PNG texture (any PNG colour type; converted to RGBA8).
pub fn parse_texture_png(bytes: &[u8], name: &str) -> Result<Texture, AssetError> {
    let (w, h, rgba) = decode_png_rgba(bytes, name).map_err(|e| AssetError::new(name, e.to_string()))?;
    Texture::from_rgba8(w, h, &rgba).map_err(|e| AssetError::new(name, e.to_string()))
}

/// Loads a PNG texture file.
pub fn load_texture_png(path: impl AsRef<Path>) -> Result<Texture, AssetError> {
    let path = path.as_ref();
    parse_texture_png(&read(path)?, &path.display().to_string())
}
