//! Speed measurements printed by `vifo bench`. Benches measure; tests never assert timings.

pub mod physics;
pub mod render;
