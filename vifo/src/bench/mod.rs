//! Speed measurements printed by `vifo bench`. Benches measure; tests never assert timings.

pub mod cues;
pub mod machine;
pub mod memory;
pub mod physics;
pub mod render;
pub mod replay;
pub mod scaling;
pub mod timing;
