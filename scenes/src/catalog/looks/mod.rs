//! Hand-designed procedural looks, one function per category: recipes that fit the collision
//! geometry, with colours taken from LIBERO's textures and the reference renders (each family
//! module lists its sources).

pub(crate) mod fixtures;
pub(crate) mod groceries;
pub(crate) mod hazards;
mod kit;
pub(crate) mod kitchenware;
pub(crate) mod study;
pub(crate) mod tableware;
