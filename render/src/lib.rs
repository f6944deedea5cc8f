//! Software rendering for LIBERO-VIFO: the cameras policies see through, and the images every
//! visual cue is drawn on.
//!
//! - Scene description ([`Scene`], [`Instance`], [`Mesh`], [`Material`], [`Texture`], [`Light`]):
//!   plain data, meshes and textures shared by `Arc`.
//! - Procedural meshes ([`Mesh::cuboid`], [`Mesh::cylinder`], [`Mesh::lathe`], …) so that scenes
//!   need no asset files.
//! - [`Camera`]: MuJoCo pose convention, the paper's pixel convention, `project` / `unproject`.
//! - [`Renderer`]: a deterministic, single-threaded z-buffer rasterizer with MuJoCo-like
//!   fixed-function lighting, giving colour, depth and segmentation ([`Frame`]).
//! - [`imageio`]: PNG in/out, animated GIFs, side-by-side images; [`metrics`]: PSNR and SSIM.
//! - [`assets`]: optional loaders for `.msh`, OBJ, STL and PNG files of a LIBERO checkout.
//!
//! This crate depends on no other crate of the workspace and builds for
//! `wasm32-unknown-unknown`.

// `!(x > 0.0)` is used on purpose throughout: it is also true for NaN, which must be rejected.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod assets;
mod camera;
mod cluster;
mod frame;
pub mod imageio;
mod mesh;
pub mod metrics;
mod num;
pub mod pack;
mod raster;
mod scene;
mod shapes;
mod simplify;
mod texture;
mod transform;

pub use camera::{Camera, Intrinsics, Projection, DEFAULT_FAR, DEFAULT_NEAR};
pub use frame::{Frame, RgbImage};
pub use mesh::{BoundingSphere, Mesh, MeshError};
pub use raster::{RenderError, RenderOptions, RenderStats, Renderer, MAX_IMAGE_SIDE};
pub use scene::{Background, Headlight, Instance, Light, LightKind, Material, Mirror, Scene};
pub use texture::{Filter, Texture, TextureError};
pub use transform::{mat3_from_mj_xmat, quat_wxyz_to_mat3, Transform};

/// The math types used in this crate's API.
pub use glam;

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeExamples;
