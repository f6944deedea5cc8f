//! Articulated fixtures (cabinets, stoves): their still frame is a plain fixed body, so what rests
//! on it falls asleep once still, while what lies in a drawer rides the drawer's multibody.

use vifo_robots::action::Action;
use vifo_scenes::init_states;
use vifo_scenes::sim::{SceneModel, Sim};

#[test]
fn a_bowl_on_the_cabinet_sleeps_and_a_bowl_in_its_open_drawer_stays_awake() {
    // libero_spatial/4: bowl 1 in the open top drawer, bowl 2 on the cabinet's top.
    let task = vifo_scenes::task("libero_spatial", 4).unwrap();
    let model = SceneModel::build(task).unwrap();
    let mut sim = Sim::new(model.clone());
    init_states::apply(&mut sim, &init_states::fixed(task).unwrap()[0]).unwrap();
    let (cabinet, _) = model.entity("wooden_cabinet_1").unwrap();
    let (on_top, _) = model.entity("akita_black_bowl_2").unwrap();
    let (in_drawer, _) = model.entity("akita_black_bowl_1").unwrap();
    let start = sim.entity_pose(on_top).pos;

    let r = sim.world().rapier();
    let frame = &model.entities[cabinet];
    assert!(r.multibody_joints.rigid_body_link(frame.bodies[0]).is_none(), "the frame is not in the drawers' multibody");
    assert!(frame.joints.iter().flatten().count() >= 3, "the drawers are jointed");

    // One second of holding still (20 control steps): well past the 0.2 s sleep delay.
    for _ in 0..20 {
        sim.step(&Action::hold(-1.0));
    }
    let r = sim.world().rapier();
    let body = |entity: usize| &r.bodies[model.entities[entity].bodies[0]];
    assert!(body(on_top).is_sleeping(), "a bowl resting on the cabinet top sleeps");
    assert!(!body(in_drawer).is_sleeping(), "a bowl in a drawer is in the drawer's (never sleeping) island");
    let moved = (sim.entity_pose(on_top).pos - start).norm();
    assert!(moved < 1e-4, "the sleeping bowl stayed where the state put it (moved {moved} m)");
}
