//! `vifo bench physics`: control steps per second of the Panda alone and with 10 free boxes on a
//! table, single-threaded.

use std::time::Instant;

use serde::Serialize;
use vifo_physics::rapier::prelude::*;
use vifo_physics::{SimParams, World};
use vifo_robots::action::Action;
use vifo_robots::contact::SCENE_GROUPS;
use vifo_robots::panda::{self, GRIPPER_INIT_QPOS, LIBERO_INIT_QPOS, Mount, Panda, PandaControl};

/// One measured configuration.
#[derive(Debug, Serialize)]
pub struct PhysicsBench {
    pub scene: &'static str,
    pub control_steps: usize,
    pub seconds: f64,
    pub control_steps_per_second: f64,
    pub ms_per_control_step: f64,
}

fn arm_world(boxes: usize) -> (World, Panda, PandaControl) {
    let mut world = World::new(SimParams::LIBERO);
    let robot = Panda::insert(&mut world, Mount::Pedestal, panda::base_pose(Mount::Pedestal, [-0.66, 0.0, 0.0]));
    robot.set_joints(&mut world, &LIBERO_INIT_QPOS, &GRIPPER_INIT_QPOS, &[0.0; 7], &[0.0; 2]);
    let r = world.rapier_mut();
    r.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, 0.0, 0.875)),
        ColliderBuilder::cuboid(0.5, 0.6, 0.025).friction(0.6).collision_groups(SCENE_GROUPS),
    );
    for i in 0..boxes {
        let (row, col) = ((i / 5) as f64, (i % 5) as f64);
        r.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(0.05 + 0.08 * row, -0.2 + 0.1 * col, 0.93)),
            ColliderBuilder::cuboid(0.025, 0.025, 0.025).density(200.0).friction(0.95).collision_groups(SCENE_GROUPS),
        );
    }
    let control = robot.reset_control();
    (world, robot, control)
}

/// A varied but repeatable action sequence (the arm sweeps above the boxes).
fn action(t: usize) -> Action {
    let s = |k: f64| libm::sin(0.11 * t as f64 + k);
    Action::clipped([0.5 * s(0.0), 0.5 * s(1.0), 0.3 * s(2.0), 0.1 * s(3.0), 0.1 * s(4.0), 0.2 * s(5.0), if t % 40 < 20 { -1.0 } else { 1.0 }])
}

fn measure(scene: &'static str, boxes: usize, steps: usize) -> PhysicsBench {
    let (mut world, robot, mut control) = arm_world(boxes);
    for t in 0..10 {
        robot.control_step(&mut world, &mut control, &action(t));
    }
    let start = Instant::now();
    for t in 0..steps {
        robot.control_step(&mut world, &mut control, &action(t));
    }
    let seconds = start.elapsed().as_secs_f64();
    PhysicsBench {
        scene,
        control_steps: steps,
        seconds,
        control_steps_per_second: steps as f64 / seconds,
        ms_per_control_step: 1e3 * seconds / steps as f64,
    }
}

/// Runs both configurations with `steps` control steps each (25 physics steps per control step).
pub fn run(steps: usize) -> Vec<PhysicsBench> {
    vec![measure("panda", 0, steps), measure("panda + 10 boxes on a table", 10, steps)]
}
