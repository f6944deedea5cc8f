//! The predicates LIBERO's BDDL files may use, and how many arguments each takes.

use std::fmt;

/// A predicate of LIBERO's dispatch table (`envs/predicates/__init__.py`). LIBERO lower-cases
/// every BDDL file before parsing, so names match case-insensitively (`On`, `on`, `ON`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Predicate {
    /// Always true; takes any number of arguments.
    True,
    /// Always false; takes any number of arguments.
    False,
    /// `(In a region)`: a's origin inside the region's box.
    In,
    /// `(On a b)`: a resting on object b or above region b.
    On,
    /// `(Up a)`: a's origin at z >= 1.0.
    Up,
    /// `(PrintJointState a)`: LIBERO's debug predicate; prints and is true.
    PrintJointState,
    /// `(Open x)`: a drawer, door or microwave joint past its open threshold.
    Open,
    /// `(Close x)`: every joint of x past its closed threshold.
    Close,
    /// `(TurnOn x)`: a knob past its on threshold.
    TurnOn,
    /// `(TurnOff x)`: every knob of x at its off position.
    TurnOff,
}

/// How many arguments a predicate takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arity {
    Exactly(usize),
    Any,
}

impl Predicate {
    /// Every predicate, in LIBERO's dispatch-table order.
    pub const ALL: [Predicate; 10] = [
        Predicate::True,
        Predicate::False,
        Predicate::In,
        Predicate::On,
        Predicate::Up,
        Predicate::PrintJointState,
        Predicate::Open,
        Predicate::Close,
        Predicate::TurnOn,
        Predicate::TurnOff,
    ];

    /// The spelling we print and store (LIBERO's class names).
    pub fn name(self) -> &'static str {
        match self {
            Predicate::True => "True",
            Predicate::False => "False",
            Predicate::In => "In",
            Predicate::On => "On",
            Predicate::Up => "Up",
            Predicate::PrintJointState => "PrintJointState",
            Predicate::Open => "Open",
            Predicate::Close => "Close",
            Predicate::TurnOn => "TurnOn",
            Predicate::TurnOff => "TurnOff",
        }
    }

    /// Looks a predicate up by name, ignoring case as LIBERO does.
    pub fn from_name(name: &str) -> Option<Predicate> {
        Predicate::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(name))
    }

    pub fn arity(self) -> Arity {
        match self {
            Predicate::True | Predicate::False => Arity::Any,
            Predicate::In | Predicate::On => Arity::Exactly(2),
            Predicate::Up
            | Predicate::PrintJointState
            | Predicate::Open
            | Predicate::Close
            | Predicate::TurnOn
            | Predicate::TurnOff => Arity::Exactly(1),
        }
    }

    /// The lower-case names, comma-separated, for error messages.
    pub fn known_names() -> String {
        Predicate::ALL
            .iter()
            .map(|p| p.name().to_ascii_lowercase())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl fmt::Display for Predicate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_match_case_insensitively() {
        assert_eq!(Predicate::from_name("Turnon"), Some(Predicate::TurnOn));
        assert_eq!(Predicate::from_name("ON"), Some(Predicate::On));
        assert_eq!(Predicate::from_name("printjointstate"), Some(Predicate::PrintJointState));
        assert_eq!(Predicate::from_name("stack"), None);
        for p in Predicate::ALL {
            assert_eq!(Predicate::from_name(&p.name().to_uppercase()), Some(p));
        }
    }

    #[test]
    fn arities_follow_libero() {
        assert_eq!(Predicate::On.arity(), Arity::Exactly(2));
        assert_eq!(Predicate::Open.arity(), Arity::Exactly(1));
        assert_eq!(Predicate::True.arity(), Arity::Any);
    }
}
