//! Task definitions: the data model of one LIBERO task and the 40 built-in tasks.
//!
//! A [`Task`] holds the facts of one BDDL file in our own terms: the problem class, the fixtures
//! and movable objects with their categories, the regions, and the `:init` and `:goal` atoms.
//! The built-in tasks live in `scenes/tasks/*.json` (our format, not BDDL) and are parsed once.

mod builtin;
mod instruction;
mod predicate;
mod problem_class;

pub use builtin::{PIPER_SUITE, SAFETY_SUITE, Suite, all_tasks, study_suites, suite, suite_names, suites, task};
pub use instruction::instruction_from_file_name;
pub use predicate::{Arity, Predicate};
pub use problem_class::ProblemClass;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// One LIBERO task.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Task {
    /// The benchmark suite (`libero_spatial`, ...) when the task belongs to one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub suite: Option<String>,
    /// The position in the suite's evaluation order (0..9).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    /// The BDDL file stem, e.g. `KITCHEN_SCENE3_turn_on_the_stove_and_put_the_moka_pot_on_it`.
    pub name: String,
    /// What evaluations feed the policy ([`instruction_from_file_name`] of `name`).
    pub instruction: String,
    /// The BDDL `:language` text (words joined by single spaces, case kept). Not what
    /// evaluations use; kept for reference.
    pub language: String,
    pub problem: ProblemClass,
    /// Static scene parts in `:fixtures` order, including the workspace itself (`main_table`).
    pub fixtures: Vec<Entity>,
    /// Movable objects (one free joint each) in `:objects` order.
    pub objects: Vec<Entity>,
    /// Regions whose target exists, in declaration order.
    pub regions: Vec<Region>,
    /// Names (objects, fixtures or region keys) the task is about.
    pub obj_of_interest: Vec<String>,
    /// Initial-placement atoms.
    pub init: Vec<Atom>,
    /// Goal atoms; success is their conjunction.
    pub goal: Vec<Atom>,
}

/// A named fixture or object and its category (the asset it is built from).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entity {
    pub name: String,
    pub category: String,
}

/// A BDDL region. Regions with `ranges` are rectangles on the workspace (x, y relative to the
/// problem class's workspace offset); regions without name a site inside their target's asset
/// (`cook_region` of `flat_stove_1`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// `target + "_" + name`, the name atoms use (LIBERO's `bddl_utils.get_regions`).
    pub key: String,
    pub name: String,
    /// The fixture or object the region belongs to.
    pub target: String,
    /// Rectangles `[x_min, y_min, x_max, y_max]` in metres.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ranges: Vec<[f64; 4]>,
    /// Uniform yaw range `[min, max]` in radians for a fixture placed here (LIBERO's default is 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yaw_rotation: Option<[f64; 2]>,
    /// Site colour (LIBERO's default is invisible `[0, 0, 1, 0]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rgba: Option<[f64; 4]>,
}

/// A predicate applied to names, e.g. `(On akita_black_bowl_1 plate_1)`.
/// Serialized as a JSON array: `["On", "akita_black_bowl_1", "plate_1"]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Atom {
    pub predicate: Predicate,
    pub args: Vec<String>,
}

/// What a name in an atom refers to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Referent<'a> {
    Object(&'a Entity),
    Fixture(&'a Entity),
    Region(&'a Region),
}

impl Task {
    /// The object or fixture called `name`.
    pub fn entity(&self, name: &str) -> Option<&Entity> {
        self.object(name).or_else(|| self.fixture(name))
    }

    pub fn object(&self, name: &str) -> Option<&Entity> {
        self.objects.iter().find(|e| e.name == name)
    }

    pub fn fixture(&self, name: &str) -> Option<&Entity> {
        self.fixtures.iter().find(|e| e.name == name)
    }

    /// The region with this key (`main_table_plate_region`).
    pub fn region(&self, key: &str) -> Option<&Region> {
        self.regions.iter().find(|r| r.key == key)
    }

    /// What `name` (an atom argument) refers to: an object, a fixture or a region key.
    pub fn resolve(&self, name: &str) -> Option<Referent<'_>> {
        if let Some(e) = self.object(name) {
            Some(Referent::Object(e))
        } else if let Some(e) = self.fixture(name) {
            Some(Referent::Fixture(e))
        } else {
            self.region(name).map(Referent::Region)
        }
    }

    /// The objects that get a free joint, in state-vector order.
    pub fn movable_objects(&self) -> &[Entity] {
        &self.objects
    }

    /// Every atom (init, then goal) that mentions `name`.
    pub fn atoms_mentioning<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Atom> + 'a {
        self.init
            .iter()
            .chain(&self.goal)
            .filter(move |a| a.args.iter().any(|arg| arg == name))
    }

    /// `suite[index]` or the bare name, for messages.
    pub fn label(&self) -> String {
        match (&self.suite, self.index) {
            (Some(suite), Some(index)) => format!("{suite}[{index}] {}", self.name),
            _ => self.name.clone(),
        }
    }
}

impl Region {
    /// Whether this is a workspace rectangle (as opposed to a site of its target's asset).
    pub fn is_ranged(&self) -> bool {
        !self.ranges.is_empty()
    }
}

impl fmt::Display for Atom {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}", self.predicate)?;
        for arg in &self.args {
            write!(f, " {arg}")?;
        }
        f.write_str(")")
    }
}

impl Serialize for Atom {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut items = Vec::with_capacity(1 + self.args.len());
        items.push(self.predicate.name());
        items.extend(self.args.iter().map(String::as_str));
        items.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Atom {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let mut items = Vec::<String>::deserialize(deserializer)?;
        if items.is_empty() {
            return Err(D::Error::custom("an atom needs a predicate name"));
        }
        let name = items.remove(0);
        let predicate = Predicate::from_name(&name).ok_or_else(|| {
            D::Error::custom(format!(
                "unknown predicate '{name}' (expected one of {})",
                Predicate::known_names()
            ))
        })?;
        Ok(Atom { predicate, args: items })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small_task() -> Task {
        Task {
            suite: None,
            index: None,
            name: "put_the_cup_on_the_tray".into(),
            instruction: "put the cup on the tray".into(),
            language: "Put the cup on the tray".into(),
            problem: ProblemClass::Tabletop,
            fixtures: vec![Entity { name: "main_table".into(), category: "table".into() }],
            objects: vec![
                Entity { name: "cup_1".into(), category: "cup".into() },
                Entity { name: "tray_1".into(), category: "tray".into() },
            ],
            regions: vec![Region {
                key: "main_table_cup_region".into(),
                name: "cup_region".into(),
                target: "main_table".into(),
                ranges: vec![[0.0, 0.1, 0.02, 0.12]],
                yaw_rotation: None,
                rgba: None,
            }],
            obj_of_interest: vec!["cup_1".into()],
            init: vec![Atom {
                predicate: Predicate::On,
                args: vec!["cup_1".into(), "main_table_cup_region".into()],
            }],
            goal: vec![Atom { predicate: Predicate::On, args: vec!["cup_1".into(), "tray_1".into()] }],
        }
    }

    #[test]
    fn helpers_resolve_names() {
        let task = small_task();
        assert!(matches!(task.resolve("cup_1"), Some(Referent::Object(e)) if e.category == "cup"));
        assert!(matches!(task.resolve("main_table"), Some(Referent::Fixture(_))));
        assert!(matches!(task.resolve("main_table_cup_region"), Some(Referent::Region(r)) if r.is_ranged()));
        assert_eq!(task.resolve("cup_region"), None);
        assert_eq!(task.entity("tray_1").map(|e| e.category.as_str()), Some("tray"));
        assert_eq!(task.movable_objects().len(), 2);
        assert_eq!(task.atoms_mentioning("tray_1").count(), 1);
        assert_eq!(task.atoms_mentioning("cup_1").count(), 2);
    }

    #[test]
    fn atoms_serialize_as_arrays_and_display_as_sexprs() {
        let atom = &small_task().goal[0];
        assert_eq!(serde_json::to_string(atom).unwrap(), r#"["On","cup_1","tray_1"]"#);
        assert_eq!(atom.to_string(), "(On cup_1 tray_1)");
        let back: Atom = serde_json::from_str(r#"["turnon","flat_stove_1"]"#).unwrap();
        assert_eq!(back.predicate, Predicate::TurnOn);
        assert!(serde_json::from_str::<Atom>(r#"["Stack","a","b"]"#).is_err());
        assert!(serde_json::from_str::<Atom>("[]").is_err());
    }

    #[test]
    fn tasks_round_trip_through_json() {
        let task = small_task();
        let json = serde_json::to_string(&task).unwrap();
        assert!(!json.contains("suite"), "unset suite is omitted: {json}");
        let back: Task = serde_json::from_str(&json).unwrap();
        assert_eq!(back, task);
    }
}
