//! The closed set of task relations.

use serde::{Deserialize, Serialize};

/// What a step asks for. Placement relations move the source onto/into/beside the target;
/// state relations change an articulated fixture; `PickUp` only lifts.
///
/// Every LIBERO instruction (the 40 evaluation tasks and LIBERO-90) maps onto this set:
/// "on top of" is `On`, "inside"/"into" is `In`, "to the right of" is `RightOf`,
/// "push ... to the front of" is `PushTo`, "stack A on B" is `On`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Relation {
    On,
    In,
    Under,
    LeftOf,
    RightOf,
    FrontOf,
    Behind,
    NextTo,
    PushTo,
    PickUp,
    Open,
    Close,
    TurnOn,
    TurnOff,
}

impl Relation {
    /// Every relation, in declaration order.
    pub const ALL: [Relation; 14] = [
        Relation::On,
        Relation::In,
        Relation::Under,
        Relation::LeftOf,
        Relation::RightOf,
        Relation::FrontOf,
        Relation::Behind,
        Relation::NextTo,
        Relation::PushTo,
        Relation::PickUp,
        Relation::Open,
        Relation::Close,
        Relation::TurnOn,
        Relation::TurnOff,
    ];

    /// The snake_case name used in JSON and cue payloads.
    pub fn name(self) -> &'static str {
        match self {
            Relation::On => "on",
            Relation::In => "in",
            Relation::Under => "under",
            Relation::LeftOf => "left_of",
            Relation::RightOf => "right_of",
            Relation::FrontOf => "front_of",
            Relation::Behind => "behind",
            Relation::NextTo => "next_to",
            Relation::PushTo => "push_to",
            Relation::PickUp => "pick_up",
            Relation::Open => "open",
            Relation::Close => "close",
            Relation::TurnOn => "turn_on",
            Relation::TurnOff => "turn_off",
        }
    }

    /// True when the step carries its source object to a target (a trajectory exists).
    pub fn moves_source(self) -> bool {
        !self.is_state_change()
    }

    /// True for relations that change an articulated fixture instead of moving an object.
    pub fn is_state_change(self) -> bool {
        matches!(self, Relation::Open | Relation::Close | Relation::TurnOn | Relation::TurnOff)
    }

    /// True when the relation needs a target object or region.
    pub fn needs_target(self) -> bool {
        !self.is_state_change() && self != Relation::PickUp
    }

    /// The imperative verb, for captions.
    pub fn verb(self) -> &'static str {
        match self {
            Relation::PushTo => "push",
            Relation::PickUp => "pick up",
            Relation::Open => "open",
            Relation::Close => "close",
            Relation::TurnOn => "turn on",
            Relation::TurnOff => "turn off",
            _ => "put",
        }
    }
}

impl std::fmt::Display for Relation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
