//! The project's own initial states (`scenes/init_states/*.json`): every task ships 50 that
//! load, hold their init atoms after LIBERO's wait steps and stay still; regenerating reproduces
//! them bit for bit; they follow LIBERO's placement rules; bad states are refused clearly.

use std::sync::Arc;

use vifo_scenes::init_states::{self, EpisodeStart, MAX_DRIFT, ShippedError, TaskStates};
use vifo_scenes::sim::{SceneModel, Sim, StateError};
use vifo_scenes::task::{Predicate, ProblemClass};
use vifo_scenes::{Task, all_tasks};

fn model(task: &Task) -> Arc<SceneModel> {
    SceneModel::build(task).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs `job` on every task, two at a time (physics-heavy checks).
fn per_task(job: impl Fn(&'static Task) + Sync) {
    let tasks: Vec<&'static Task> = all_tasks().collect();
    std::thread::scope(|s| {
        for half in tasks.chunks(tasks.len().div_ceil(2)) {
            s.spawn(|| half.iter().for_each(|t| job(t)));
        }
    });
}

#[test]
fn every_task_ships_50_states_that_load() {
    for task in all_tasks() {
        let model = model(task);
        let starts = init_states::fixed(task).unwrap_or_else(|e| panic!("{}: {e}", task.label()));
        assert_eq!(starts.len(), 50, "{}", task.label());
        for (k, start) in starts.iter().enumerate() {
            let mut sim = Sim::new(model.clone());
            init_states::apply(&mut sim, start).unwrap_or_else(|e| panic!("{} state {k}: {e}", task.label()));
            assert_eq!(start.state.objects.len(), task.objects.len());
            for (i, o) in start.state.objects.iter().enumerate() {
                let (entity, _) = model.entity(&o.name).unwrap();
                let at = sim.entity_pose(entity).pos;
                assert!((at.x - o.pos[0]).abs() < 1e-9 && (at.z - o.pos[2]).abs() < 1e-9, "{} state {k} object {i}", task.label());
            }
        }
    }
}

/// The stability gate on one state per task (a different one per task, so the suite covers
/// many): init atoms hold after the 10 wait steps, nothing sinks below the table or floor, and
/// nothing moves more than 1 mm over 200 zero-action steps. `vifo init-states check --drift`
/// measures all 2000.
#[test]
fn shipped_states_hold_their_init_atoms_and_stay_still() {
    per_task(|task| {
        let k = (task.index.unwrap() * 7 + task.name.len()) % 50;
        let start = &init_states::fixed(task).unwrap()[k];
        let check = init_states::check(&model(task), start, true).unwrap();
        assert!(check.ok(), "{} state {k}: {:?}", task.label(), check.problems);
        let (drift, who) = check.drift.clone().unwrap();
        assert!(drift <= MAX_DRIFT, "{} state {k}: {who} drifts {drift}", task.label());
    });
}

#[test]
fn regenerating_reproduces_the_shipped_states() {
    for (suite, index, states) in [("libero_10", 8, 0..3), ("libero_spatial", 4, 10..11), ("libero_object", 2, 49..50)] {
        let task = vifo_scenes::task(suite, index).unwrap();
        let model = model(task);
        let shipped = init_states::fixed(task).unwrap();
        for k in states {
            let again = init_states::sample(&model, init_states::seed(suite, index, k)).unwrap();
            assert_eq!(&again, &shipped[k], "{} state {k}", task.label());
        }
    }
}

#[test]
fn shipped_states_follow_libero_placement_rules() {
    // How far settling may move an object from where it was drawn.
    const SETTLE: f64 = 0.005;
    for task in all_tasks() {
        let model = model(task);
        let class = model.class;
        for (k, start) in init_states::fixed(task).unwrap().iter().enumerate() {
            let at = |name: &str| start.state.objects.iter().find(|o| o.name == name).unwrap();
            for atom in task.init.iter().filter(|a| a.predicate == Predicate::On) {
                let (Some(region), Some((_, e))) = (task.region(&atom.args[1]), model.entity(&atom.args[0])) else { continue };
                if !region.is_ranged() || !e.movable() {
                    continue;
                }
                // Tabletop and floor shrink the range by the radius (crossing for tiny regions).
                let r = if matches!(class.problem, ProblemClass::Tabletop | ProblemClass::Floor) { e.model.horizontal_radius } else { 0.0 };
                let [x0, y0, x1, y1] = region.ranges[0];
                let o = at(&atom.args[0]);
                for (v, lo, hi, off) in [(o.pos[0], x0 + r, x1 - r, class.workspace_offset[0]), (o.pos[1], y0 + r, y1 - r, class.workspace_offset[1])] {
                    let (lo, hi) = (lo.min(hi) + off - SETTLE, lo.max(hi) + off + SETTLE);
                    assert!(lo <= v && v <= hi, "{} state {k}: {} at {v} outside [{lo}, {hi}]", task.label(), atom);
                }
            }
            for (q, q0) in start.state.arm_qpos.iter().zip(vifo_robots::panda::LIBERO_INIT_QPOS) {
                assert!((q - q0).abs() < 5.0 * init_states::ARM_NOISE_STD, "{} state {k}: arm {q} vs {q0}", task.label());
            }
            assert_eq!(start.state.gripper_qpos, vifo_robots::panda::GRIPPER_INIT_QPOS);
            if let Some(book) = start.state.objects.iter().find(|o| o.name == "black_book_1") {
                let [w, _, _, z] = book.quat_wxyz;
                let yaw = (2.0 * z.atan2(w)).rem_euclid(std::f64::consts::TAU).to_degrees();
                assert!((224.0..=271.0).contains(&yaw), "{} state {k}: book yaw {yaw}", task.label());
            }
        }
    }
}

#[test]
fn articulation_atoms_draw_from_libero_ranges() {
    let drawer = vifo_scenes::task("libero_spatial", 4).unwrap();
    let knob = vifo_scenes::task("libero_10", 8).unwrap();
    let door = vifo_scenes::task("libero_10", 9).unwrap();
    for (task, joint, lo, hi) in [(drawer, "top_level", -0.16, -0.14), (knob, "button", 0.5, 2.1), (door, "microjoint", -2.094, -1.3)] {
        let values: Vec<f64> =
            init_states::fixed(task).unwrap().iter().map(|s| s.state.joints.iter().find(|j| j.joint == joint).unwrap().qpos).collect();
        // Settling may nudge a joint a little.
        assert!(values.iter().all(|v| (lo - 0.002..=hi + 0.002).contains(v)), "{}: {values:?}", task.label());
        let spread = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - values.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(spread > 0.5 * (hi - lo), "{}: values barely vary: {values:?}", task.label());
    }
}

/// A stored fixture where its placement could not have put it (off the table, under the
/// floor, turned over) is a problem of the state; `vifo init-states check` passed such files.
#[test]
fn fixtures_outside_their_placement_region_are_problems() {
    let task = vifo_scenes::task("libero_goal", 0).unwrap();
    let model = model(task);
    let good: &EpisodeStart = &init_states::fixed(task).unwrap()[0];
    assert!(init_states::check(&model, good, false).unwrap().ok());
    type Spoil = fn(&mut [f64; 3], &mut [f64; 4]);
    let spoils: [Spoil; 4] = [
        |pos, _| pos[0] = 1e300,
        |pos, _| pos[2] = -10.0,
        |pos, _| pos[1] += 0.5,
        |_, quat| *quat = [0.0, 1.0, 0.0, 0.0],
    ];
    for spoil in spoils {
        let mut start = good.clone();
        let fixture = &mut start.fixtures[0];
        spoil(&mut fixture.pos, &mut fixture.quat_wxyz);
        let check = init_states::check(&model, &start, false).unwrap();
        let says = format!("fixture {} at", start.fixtures[0].name);
        assert!(check.problems.iter().any(|p| p.starts_with(&says) && p.ends_with("lies outside its placement region")), "{:?}", check.problems);
    }
}

#[test]
fn bad_states_are_refused_with_clear_errors() {
    let task = vifo_scenes::task("libero_goal", 0).unwrap();
    let model = model(task);
    let good: &EpisodeStart = &init_states::fixed(task).unwrap()[0];

    let mut unknown = good.clone();
    unknown.state.objects[1].name = "teapot_1".into();
    let err = init_states::apply(&mut Sim::new(model.clone()), &unknown).unwrap_err();
    assert_eq!(err, StateError::UnknownObject("teapot_1".into()));
    assert_eq!(err.to_string(), "state names object teapot_1, which the scene does not have");
    let mut fixture = good.clone();
    fixture.fixtures[0].name = "plate_1".into();
    assert_eq!(init_states::apply(&mut Sim::new(model.clone()), &fixture).unwrap_err(), StateError::UnknownObject("plate_1".into()));
    let mut nan = good.clone();
    nan.fixtures[0].pos[2] = f64::NAN;
    assert!(matches!(init_states::apply(&mut Sim::new(model.clone()), &nan), Err(StateError::NotFinite { .. })));

    // A stored state with a pose one number short names the file, task, state and layout.
    let suite = init_states::SuiteStates {
        suite: "libero_goal".into(),
        tasks: vec![TaskStates { index: 0, name: task.name.clone(), starts: vec![good.clone()] }],
    };
    let text = init_states::write(&suite);
    let first = format!("[{},", good.state.objects[0].pos[0]);
    let broken = text.replacen(&first, "[", 1);
    let err = init_states::parse(&broken, "goal.json").unwrap_err().to_string();
    assert!(
        err.starts_with("goal.json: task 0 (open_the_middle_drawer_of_the_cabinet) state 0: object")
            && err.ends_with("has 6 numbers, expected 7 (x y z qw qx qy qz)"),
        "{err}"
    );

    // States stored for another task's objects are refused before use.
    let mut other = init_states::parse(&text, "goal.json").unwrap();
    other.tasks[0].starts[0].state.objects.swap(0, 1);
    let err = init_states::starts_for(&other, task).unwrap_err();
    assert!(matches!(err, ShippedError::Mismatch { .. }), "{err}");
    assert!(err.to_string().contains("names objects"), "{err}");
    let spatial = vifo_scenes::task("libero_spatial", 0).unwrap();
    assert!(matches!(init_states::starts_for(&other, spatial), Err(ShippedError::WrongSuite { .. })));
}
