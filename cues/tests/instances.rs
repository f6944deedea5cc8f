//! The instance set over LIBERO's 40 tasks: compatibility, composition against the paper,
//! determinism and JSON round trip.

mod common;

use vifo_cues::instances::{InstanceSet, TaskDescription};
use vifo_cues::{Family, Inserter, VARIANTS};

fn set() -> InstanceSet {
    InstanceSet::build(&common::descriptions()).unwrap()
}

#[test]
fn composition_is_close_to_the_paper() {
    let set = set();
    let total = set.instances.len();
    assert!((1212..=1482).contains(&total), "{total} instances, paper 1,347 ± 10 %");
    let c = set.composition();
    for (family, count) in &c {
        println!(
            "{family} {:<24} {:>4} instances {:>5.1} % on {:>2} tasks",
            family.name(),
            count.instances,
            count.share * 100.0,
            count.tasks
        );
    }
    // Seven families on all 40 tasks, ghosts on the 38 that move an object.
    for family in Family::ALL {
        let expected_tasks = if family == Family::F3 { 38 } else { 40 };
        assert_eq!(c[&family].tasks, expected_tasks, "{family}");
    }
    // The three largest families are geometric, highlight and pictorial (paper: 23.8, 20.8, 20.0 %).
    let mut by_size: Vec<_> = c.iter().collect();
    by_size.sort_by_key(|(_, c)| std::cmp::Reverse(c.instances));
    let top: Vec<Family> = by_size[..3].iter().map(|(f, _)| **f).collect();
    assert_eq!(top, [Family::F2, Family::F4, Family::F7]);
    for (family, paper) in [(Family::F2, 0.238), (Family::F7, 0.208), (Family::F4, 0.200)] {
        assert!((c[&family].share - paper).abs() < 0.04, "{family}: {:.3} vs {paper}", c[&family].share);
    }
}

#[test]
fn compatibility_follows_the_task_semantics() {
    let set = set();
    let of_task = |key: &str| -> Vec<&str> {
        set.instances.iter().filter(|s| s.task == key).map(|s| s.variant.as_str()).collect()
    };
    // "open the middle drawer of the cabinet": no moving object, no target.
    let drawer = of_task("libero_goal/0");
    assert!(
        !drawer.contains(&"ghost_fade")
            && !drawer.contains(&"straight_arrow_red")
            && !drawer.contains(&"hand_grasp_source")
    );
    assert!(
        drawer.contains(&"caption_bar")
            && drawer.contains(&"target_crosshair_magenta")
            && drawer.contains(&"glow_halo")
    );
    // A long instruction gets no sticky note; a short one does.
    assert!(!of_task("libero_spatial/0").contains(&"sticky_note"));
    assert!(of_task("libero_goal/8").contains(&"sticky_note"));
    // Arrows for "open the top drawer and put the bowl inside" show the second step.
    let arrow = set.instances.iter().find(|s| s.task == "libero_goal/3" && s.variant == "straight_arrow_red").unwrap();
    assert_eq!((arrow.step, arrow.source.as_str(), arrow.target.as_deref()), (1, "bowl", Some("top drawer")));
    assert_eq!(arrow.id(), "libero_goal/3/F2/straight_arrow_red");
    // Ids are unique.
    let mut ids: Vec<String> = set.instances.iter().map(|s| s.id()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), set.instances.len());
}

#[test]
fn the_set_is_deterministic_and_round_trips_through_json() {
    let a = set();
    assert_eq!(a, set());
    let json = serde_json::to_string(&a).unwrap();
    let back: InstanceSet = serde_json::from_str(&json).unwrap();
    assert_eq!(back, a);
    let tasks: Vec<TaskDescription> =
        serde_json::from_str(&serde_json::to_string(&common::descriptions()).unwrap()).unwrap();
    assert_eq!(tasks, common::descriptions());
}

#[test]
fn every_instance_passes_its_own_checks() {
    for spec in &set().instances {
        spec.check().unwrap_or_else(|e| panic!("{}: {e}", spec.id()));
        assert!(VARIANTS.iter().any(|v| v.name == spec.variant));
    }
    let _ = Inserter::new();
}

#[test]
fn an_unparseable_task_is_reported_by_key() {
    let mut tasks = common::descriptions();
    tasks[5].instruction = "juggle the bowls".into();
    let err = InstanceSet::build(&tasks).unwrap_err();
    assert_eq!(err.task, "libero_spatial/5");
    assert!(err.to_string().contains("juggle"));
}
