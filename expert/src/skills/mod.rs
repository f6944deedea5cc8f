//! The skills, one recipe each: a short list of [`crate::stages`] run one control step at a
//! time, with what is particular to the skill (which grasp, which way a part moves) worked
//! out in its own file.

mod door;
mod drawer;
mod insert;
mod knob;
mod lean;
mod pick_place;
mod push;
mod stack;

pub use door::Door;
pub use drawer::{Drawer, DrawerGoal, PARTLY_OPEN, drawer_of};
pub use insert::{Insert, needed as insert_needed};
pub use knob::Knob;
pub use pick_place::{PickPlace, Placement, Spot};
pub use push::{Push, inside_floor, pushes};
pub use stack::Stack;

use vifo_scenes::sim::Sim;

use crate::stages::Step;

/// One thing the expert does, a control step at a time.
pub trait Skill: Send {
    /// The next step: an action, done, or failed.
    fn step(&mut self, sim: &Sim) -> Step;
    /// The stage it is in, for traces.
    fn describe(&self) -> String;
}
