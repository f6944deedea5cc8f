//! Tasks running in the physics world.
//!
//! - [`SceneModel`]: a task built into a template world (arena, Panda, objects, fixtures) with
//!   resolved regions; immutable and shared.
//! - [`Sim`]: one episode's state (world, controller state, step count), with LIBERO's state
//!   loading, predicates and success check, and bit-exact snapshots/forks.
//! - [`Sim::blow_up`]: the physics guard (a NaN or exploding state is no task's).

mod episode;
mod guard;
mod model;
mod placement;
mod predicates;
mod robot;

pub use episode::{RegionBox, Sim, SimSnapshot, StateError, check_robot_joints};
pub(crate) use episode::check_pose;
pub use guard::{Extremes, MAX_ANGULAR_SPEED, MAX_DISTANCE, MAX_LINEAR_SPEED, MAX_PENETRATION};
pub use model::{ARENA_CATEGORIES, BuildError, RegionPlace, SceneEntity, SceneModel, SceneRegion};
pub use placement::{FixturePlacement, FixtureRange, fixture_ranges, sample_fixtures};
pub use predicates::{ON_OBJECT_XY, PredicateError};
pub use robot::{PIPER_GRIPPER_INIT_QPOS, PIPER_INIT_QPOS, Robot, RobotControl};
