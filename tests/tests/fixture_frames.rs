//! Articulated fixtures (cabinets, stoves): their still frame is a plain fixed body, so what rests
//! on it falls asleep once still; a drawer sleeps with what lies in it, and a write to its joint
//! wakes it.

use vifo_robots::action::Action;
use vifo_scenes::init_states;
use vifo_scenes::sim::{SceneModel, Sim};

#[test]
fn bowls_on_the_cabinet_and_in_its_still_drawer_sleep_and_a_joint_write_wakes_the_drawer() {
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

    // 1.5 s of holding still (30 control steps): past the bowls' 0.2 s and the drawers' 0.5 s
    // sleep delays.
    let in_drawer_start = sim.entity_pose(in_drawer).pos;
    for _ in 0..30 {
        sim.step(&Action::hold(-1.0));
    }
    let (drawer, joint) = frame.model.bodies.iter().enumerate().find_map(|(b, body)| body.joint.as_ref().map(|j| (b, j.name.clone()))).unwrap();
    {
        let r = sim.world().rapier();
        let body = |entity: usize| &r.bodies[model.entities[entity].bodies[0]];
        assert!(body(on_top).is_sleeping(), "a bowl resting on the cabinet top sleeps");
        assert!(body(in_drawer).is_sleeping(), "a bowl in a still drawer sleeps");
        assert!(r.bodies[frame.bodies[drawer]].is_sleeping(), "a still drawer sleeps");
        for (entity, from) in [(on_top, start), (in_drawer, in_drawer_start)] {
            let moved = (sim.entity_pose(entity).pos - from).norm();
            assert!(moved < 1e-4, "a sleeping bowl stayed where the state put it (moved {moved} m)");
        }
    }

    let at = sim.joint_position(cabinet, &joint).unwrap();
    sim.set_joint(cabinet, &joint, at - 0.01);
    assert!(!sim.world().rapier().bodies[frame.bodies[drawer]].is_sleeping(), "a joint write wakes the drawer");
    sim.step(&Action::hold(-1.0));
    let moved = sim.joint_position(cabinet, &joint).unwrap() - (at - 0.01);
    assert!(moved.abs() < 1e-3, "the woken drawer holds its new position (moved {moved} m)");
}
