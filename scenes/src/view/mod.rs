//! Seeing a task: a [`Sim`](crate::sim::Sim) turned into a [`vifo_render::Scene`], and LIBERO's
//! two cameras.
//!
//! - [`SceneView`]: built once per [`SceneModel`](crate::sim::SceneModel) (one mesh per distinct
//!   procedural recipe, shared by `Arc`); [`SceneView::update`] then only moves instances to the
//!   simulation's body poses. It carries the arena (floor, table, walls), the scene class's
//!   lights plus MuJoCo's headlight, and a segmentation legend (one id per object, fixture,
//!   robot body and arena piece).
//! - [`Cameras`]: `agentview` and `robot0_eye_in_hand` as render cameras of any size;
//!   [`ImageOrder`] gives robosuite's bottom-up rows when asked.

mod arena;
mod cameras;
pub(crate) mod material;
mod meshes;
mod scene_view;
mod texgen;

pub use arena::ArenaPiece;
pub use cameras::{CameraName, Cameras, EYE_IN_HAND_FOVY_DEG, ImageOrder, UnknownCamera, camera_at};
pub use meshes::{MeshCache, ROUND_SEGMENTS, mesh_of};
pub use scene_view::{SceneView, Segment, SegmentKind};
