//! LIBERO-VIFO scenes: task definitions, objects and fixtures, predicates.

pub mod catalog;
