//! The instance sets over LIBERO's 40 tasks: compatibility, per-step instances, the `full` and
//! `paper` sets against the paper, determinism and JSON round trip.

mod common;

use std::collections::BTreeSet;

use vifo_cues::composition::coverage;
use vifo_cues::instances::{InstanceError, InstanceSet, TaskDescription};
use vifo_cues::signage::Category;
use vifo_cues::variants::Form;
use vifo_cues::{Family, Inserter, VARIANTS};

fn set() -> InstanceSet {
    InstanceSet::build(&common::descriptions()).unwrap()
}

fn print(name: &str, set: &InstanceSet) {
    println!("{name}: {} instances", set.instances.len());
    for (family, count) in set.composition() {
        println!(
            "{family} {:<24} {:>4} instances {:>5.1} % on {:>2} tasks",
            family.name(),
            count.instances,
            count.share * 100.0,
            count.tasks
        );
    }
}

/// Seven families on all 40 tasks, ghosts on the 38 that move an object.
fn assert_task_coverage(set: &InstanceSet) {
    for (family, count) in set.composition() {
        assert_eq!(count.tasks, if family == Family::F3 { 38 } else { 40 }, "{family}");
    }
}

#[test]
fn the_full_set_has_every_variant_on_every_task_it_fits() {
    let set = set();
    print("full", &set);
    assert_task_coverage(&set);
    let variants: BTreeSet<&str> = set.instances.iter().map(|s| s.variant.as_str()).collect();
    assert_eq!(variants.len(), VARIANTS.len(), "every catalogued variant fits some task");
    // Every signage category is on some F6 instance.
    let categories: BTreeSet<String> = set
        .instances
        .iter()
        .filter_map(|s| match vifo_cues::variants::find(&s.variant).unwrap().form {
            Form::Sign(c) => Some(format!("{c:?}")),
            _ => None,
        })
        .collect();
    assert_eq!(categories.len(), Category::ALL.len(), "{categories:?}");
}

#[test]
fn the_paper_set_has_the_papers_size_and_stated_shares() {
    let full = set();
    let paper = full.paper().unwrap();
    print("paper", &paper);
    assert_eq!(paper.instances.len(), 1347);
    let variants: BTreeSet<&str> = paper.instances.iter().map(|s| s.variant.as_str()).collect();
    assert_eq!(variants.len(), 33);
    assert_eq!(variants.len(), vifo_cues::instances::paper::kept_variants().len());
    let c = paper.composition();
    for (family, share) in vifo_cues::instances::paper::STATED_SHARES {
        assert!((c[&family].share - share).abs() <= 0.005, "{family}: {:.4} vs {share}", c[&family].share);
    }
    assert_task_coverage(&paper);
    // A subset of the full set, in its order, chosen the same way every time.
    let full_ids: Vec<String> = full.instances.iter().map(|s| s.id()).collect();
    let ids: Vec<String> = paper.instances.iter().map(|s| s.id()).collect();
    let mut at = 0;
    for id in &ids {
        at += full_ids[at..].iter().position(|f| f == id).expect("paper ids are full ids, in order") + 1;
    }
    assert_eq!(paper, full.paper().unwrap());
}

#[test]
fn what_the_paper_set_encodes_is_near_the_papers_figure() {
    let paper = set().paper().unwrap();
    for (component, c) in coverage(&paper.instances) {
        println!("{:<30} {:>5.1} % (paper {:>4.1} %)", component.label(), c.percent, c.paper_percent);
        assert!((c.percent - c.paper_percent).abs() <= 5.0, "{component:?}");
    }
}

#[test]
fn scene_anchored_variants_show_each_step_that_marks_something_new() {
    let set = set();
    let ids: BTreeSet<String> = set.instances.iter().map(|s| s.id()).collect();
    // "put the white mug on the left plate and put the yellow and white mug on the right plate":
    // an arrow per step; the text shows the whole task once.
    let second = set.instances.iter().find(|s| s.id() == "libero_10/4/F2/straight_arrow_red@2").unwrap();
    assert_eq!((second.step, second.source.as_str()), (1, "yellow and white mug"));
    assert!(!ids.contains("libero_10/4/F1/caption_bar@2"));
    // "put both the alphabet soup and the tomato sauce in the basket": one crosshair on the
    // basket, a glow on each object.
    assert!(ids.contains("libero_10/0/F2/target_crosshair_magenta"));
    assert!(!ids.contains("libero_10/0/F2/target_crosshair_magenta@2"));
    assert!(ids.contains("libero_10/0/F7/glow_halo@2"));
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
    assert!(matches!(&err, InstanceError::Parse { task, .. } if task == "libero_spatial/5"), "{err}");
    assert!(err.to_string().contains("juggle"));
}

#[test]
fn a_task_described_twice_is_refused() {
    let mut tasks = common::descriptions();
    tasks.push(tasks[3].clone());
    let err = InstanceSet::build(&tasks).unwrap_err();
    assert_eq!(err, InstanceError::Repeated("libero_spatial/3".into()));
}
