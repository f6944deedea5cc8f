//! The LIBERO problem classes a BDDL file can name in `(problem ...)`.

use serde::{Deserialize, Serialize};
use std::fmt;

/// A LIBERO problem class (`envs/problems/*.py`). It decides the arena, the robot mount, the
/// cameras and how workspace regions become sites; see [`crate::scene_class`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ProblemClass {
    /// One table, mounted Panda (libero_spatial, libero_goal).
    #[serde(rename = "LIBERO_Tabletop_Manipulation")]
    Tabletop,
    /// Objects on the floor, Panda without mount (libero_object).
    #[serde(rename = "LIBERO_Floor_Manipulation")]
    Floor,
    /// Kitchen table, mounted Panda (libero_10 / libero_90 KITCHEN_SCENE*).
    #[serde(rename = "LIBERO_Kitchen_Tabletop_Manipulation")]
    KitchenTabletop,
    /// Living-room table, Panda without mount (LIVING_ROOM_SCENE*).
    #[serde(rename = "LIBERO_Living_Room_Tabletop_Manipulation")]
    LivingRoomTabletop,
    /// Study desk, mounted Panda (STUDY_SCENE*).
    #[serde(rename = "LIBERO_Study_Tabletop_Manipulation")]
    StudyTabletop,
    /// Coffee table; registered by LIBERO but used by none of the 130 benchmark tasks.
    #[serde(rename = "LIBERO_Coffee_Table_Manipulation")]
    CoffeeTable,
    /// Not LIBERO's: the AgileX PiPER on a riser on the plain table (the §4.4 study).
    #[serde(rename = "VIFO_Piper_Tabletop_Manipulation")]
    PiperTabletop,
}

impl ProblemClass {
    pub const ALL: [ProblemClass; 7] = [
        ProblemClass::Tabletop,
        ProblemClass::Floor,
        ProblemClass::KitchenTabletop,
        ProblemClass::LivingRoomTabletop,
        ProblemClass::StudyTabletop,
        ProblemClass::CoffeeTable,
        ProblemClass::PiperTabletop,
    ];

    /// The name as BDDL files spell it.
    pub fn name(self) -> &'static str {
        match self {
            ProblemClass::Tabletop => "LIBERO_Tabletop_Manipulation",
            ProblemClass::Floor => "LIBERO_Floor_Manipulation",
            ProblemClass::KitchenTabletop => "LIBERO_Kitchen_Tabletop_Manipulation",
            ProblemClass::LivingRoomTabletop => "LIBERO_Living_Room_Tabletop_Manipulation",
            ProblemClass::StudyTabletop => "LIBERO_Study_Tabletop_Manipulation",
            ProblemClass::CoffeeTable => "LIBERO_Coffee_Table_Manipulation",
            ProblemClass::PiperTabletop => "VIFO_Piper_Tabletop_Manipulation",
        }
    }

    /// Looks a class up by name, ignoring case (LIBERO registers them lower-cased).
    pub fn from_name(name: &str) -> Option<ProblemClass> {
        ProblemClass::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(name))
    }
}

impl fmt::Display for ProblemClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_case_insensitively() {
        for class in ProblemClass::ALL {
            assert_eq!(ProblemClass::from_name(&class.name().to_lowercase()), Some(class));
            let json = serde_json::to_string(&class).unwrap();
            assert_eq!(json, format!("\"{}\"", class.name()));
        }
        assert_eq!(ProblemClass::from_name("LIBERO_Garage_Manipulation"), None);
    }
}
