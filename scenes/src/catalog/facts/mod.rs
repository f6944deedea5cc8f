//! Per-family fact tables restated from LIBERO's asset XMLs (numbers only, in our own format).
//! Kept one geom per line, so rustfmt leaves them alone.

// Quaternions such as 0.70711 are the XML's rounded values; MuJoCo normalises them and so do we.
#![allow(clippy::approx_constant)]

#[rustfmt::skip]
pub(crate) mod fixtures;
#[rustfmt::skip]
pub(crate) mod groceries;
#[rustfmt::skip]
pub(crate) mod hazards;
#[rustfmt::skip]
pub(crate) mod kitchenware;
#[rustfmt::skip]
pub(crate) mod tableware;
#[rustfmt::skip]
pub(crate) mod study;
