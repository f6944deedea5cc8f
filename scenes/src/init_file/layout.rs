//! What each number of a LIBERO state vector means, for a given task.
//!
//! A state row is MuJoCo's `[time, qpos (nq), qvel (nv)]` (robosuite's `sim.get_state().flatten()`).
//! qpos holds the 7 arm joints, the 2 gripper fingers, then for each movable object in
//! `:objects` order a free joint (x, y, z, qw, qx, qy, qz) followed by the object's own joints if
//! it is articulated, then the articulation joints of each fixture in `:fixtures` order. qvel
//! follows the same order with 6 numbers per free joint (linear velocity in the world frame,
//! angular velocity in the body frame). Fixtures themselves are static: their poses are not in
//! the state.

use crate::task::Task;
use std::fmt;

/// The articulation joints of an asset category, in MuJoCo order (depth-first in the asset XML).
/// Categories not listed have none.
pub fn articulation_joints(category: &str) -> &'static [&'static str] {
    match category {
        "wooden_cabinet" | "white_cabinet" => &["top_level", "middle_level", "bottom_level"],
        "flat_stove" => &["button"],
        "microwave" => &["microjoint"],
        // LIBERO-90 assets.
        "short_cabinet" => &["middle_level", "top_region", "bottom_region"],
        "short_fridge" => &["fridge_door_joint_0"],
        "slide_cabinet" => &["slidedoor_joint"],
        "window" => &["window_slide"],
        "faucet" => &["knob_Joint_1"],
        "basin_faucet" => &["hinge"],
        _ => &[],
    }
}

const ARM_JOINTS: usize = 7;
const GRIPPER_JOINTS: usize = 2;

/// One joint of the state, in order.
#[derive(Clone, Debug, PartialEq)]
enum Slot {
    /// An object's free joint: 7 qpos, 6 qvel.
    Free { object: String },
    /// A hinge or slide joint: 1 qpos, 1 qvel.
    Joint { owner: String, joint: &'static str },
}

impl Slot {
    fn nq(&self) -> usize {
        match self {
            Slot::Free { .. } => 7,
            Slot::Joint { .. } => 1,
        }
    }

    fn nv(&self) -> usize {
        match self {
            Slot::Free { .. } => 6,
            Slot::Joint { .. } => 1,
        }
    }
}

/// The state-vector layout of one task.
#[derive(Clone, Debug, PartialEq)]
pub struct StateLayout {
    task: String,
    /// The slots after the arm and gripper.
    slots: Vec<Slot>,
}

/// A movable object's pose and velocity.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectState {
    pub name: String,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    /// World frame.
    pub lin_vel: [f64; 3],
    /// Body frame, as MuJoCo stores it.
    pub ang_vel: [f64; 3],
}

/// One articulation joint (drawer slide, door hinge, knob).
#[derive(Clone, Debug, PartialEq)]
pub struct JointState {
    /// The fixture or object the joint belongs to.
    pub owner: String,
    /// The joint's name in its asset (`top_level`, `microjoint`, `button`).
    pub joint: String,
    pub qpos: f64,
    pub qvel: f64,
}

/// One decoded state row.
#[derive(Clone, Debug, PartialEq)]
pub struct InitState {
    pub time: f64,
    pub arm_qpos: [f64; 7],
    pub arm_qvel: [f64; 7],
    pub gripper_qpos: [f64; 2],
    pub gripper_qvel: [f64; 2],
    /// Movable objects in `:objects` order.
    pub objects: Vec<ObjectState>,
    /// Articulation joints of objects and fixtures, in state order.
    pub joints: Vec<JointState>,
}

/// A state row whose length does not fit the task.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LayoutError {
    pub task: String,
    pub values: usize,
    pub nq: usize,
    pub nv: usize,
}

impl fmt::Display for LayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "state vector has {} values, task {} expects {} = 1 + nq {} + nv {}",
            self.values,
            self.task,
            1 + self.nq + self.nv,
            self.nq,
            self.nv
        )
    }
}

impl std::error::Error for LayoutError {}

impl StateLayout {
    pub fn for_task(task: &Task) -> StateLayout {
        let mut slots = Vec::new();
        for object in &task.objects {
            slots.push(Slot::Free { object: object.name.clone() });
            slots.extend(joints_of(&object.name, &object.category));
        }
        for fixture in &task.fixtures {
            slots.extend(joints_of(&fixture.name, &fixture.category));
        }
        StateLayout { task: task.name.clone(), slots }
    }

    pub fn nq(&self) -> usize {
        ARM_JOINTS + GRIPPER_JOINTS + self.slots.iter().map(Slot::nq).sum::<usize>()
    }

    pub fn nv(&self) -> usize {
        ARM_JOINTS + GRIPPER_JOINTS + self.slots.iter().map(Slot::nv).sum::<usize>()
    }

    /// Numbers per state row: 1 + nq + nv.
    pub fn row_len(&self) -> usize {
        1 + self.nq() + self.nv()
    }

    /// A name for every number of a row, as in the headers of the CSV copies of LIBERO's init
    /// files: `time`, `qpos/robot0_joint1`, ..., `qpos/plate_1:qw`, `qvel/flat_stove_1:button`.
    pub fn column_names(&self) -> Vec<String> {
        let mut names = vec!["time".to_string()];
        for (part, free) in [("qpos", ["x", "y", "z", "qw", "qx", "qy", "qz"].as_slice()), ("qvel", &["vx", "vy", "vz", "wx", "wy", "wz"])] {
            names.extend((1..=ARM_JOINTS).map(|i| format!("{part}/robot0_joint{i}")));
            names.extend((1..=GRIPPER_JOINTS).map(|i| format!("{part}/gripper0_finger_joint{i}")));
            for slot in &self.slots {
                match slot {
                    Slot::Free { object } => names.extend(free.iter().map(|c| format!("{part}/{object}:{c}"))),
                    Slot::Joint { owner, joint } => names.push(format!("{part}/{owner}:{joint}")),
                }
            }
        }
        names
    }

    /// Splits a state row into named parts.
    pub fn decode(&self, row: &[f64]) -> Result<InitState, LayoutError> {
        let (nq, nv) = (self.nq(), self.nv());
        if row.len() != 1 + nq + nv {
            return Err(LayoutError { task: self.task.clone(), values: row.len(), nq, nv });
        }
        let mut qpos = Reader(&row[1..1 + nq]);
        let mut qvel = Reader(&row[1 + nq..]);
        let mut state = InitState {
            time: row[0],
            arm_qpos: qpos.take(),
            gripper_qpos: qpos.take(),
            arm_qvel: [0.0; 7],
            gripper_qvel: [0.0; 2],
            objects: Vec::new(),
            joints: Vec::new(),
        };
        state.arm_qvel = qvel.take();
        state.gripper_qvel = qvel.take();
        for slot in &self.slots {
            match slot {
                Slot::Free { object } => state.objects.push(ObjectState {
                    name: object.clone(),
                    pos: qpos.take(),
                    quat_wxyz: qpos.take(),
                    lin_vel: qvel.take(),
                    ang_vel: qvel.take(),
                }),
                Slot::Joint { owner, joint } => state.joints.push(JointState {
                    owner: owner.clone(),
                    joint: joint.to_string(),
                    qpos: qpos.take::<1>()[0],
                    qvel: qvel.take::<1>()[0],
                }),
            }
        }
        Ok(state)
    }
}

fn joints_of(owner: &str, category: &str) -> impl Iterator<Item = Slot> {
    let owner = owner.to_string();
    articulation_joints(category).iter().map(move |&joint| Slot::Joint { owner: owner.clone(), joint })
}

/// Hands out consecutive values; lengths were checked against the layout beforehand.
struct Reader<'a>(&'a [f64]);

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [f64; N] {
        let (head, rest) = self.0.split_at(N);
        self.0 = rest;
        head.try_into().expect("split_at yields N values")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::task;

    #[test]
    fn sizes_of_the_builtin_tasks_match_the_research_notes() {
        // (suite, index, row length, nq, nv) of the converted init files (`init_states_index.json`).
        let expected = [
            ("libero_spatial", 0, 92, 48, 43),
            ("libero_object", 0, 110, 58, 51),
            ("libero_goal", 0, 79, 41, 37),
            ("libero_10", 0, 123, 65, 57),
            ("libero_10", 2, 47, 24, 22),
            ("libero_10", 3, 51, 26, 24),
            ("libero_10", 5, 45, 23, 21),
            ("libero_10", 6, 71, 37, 33),
            ("libero_10", 9, 47, 24, 22),
        ];
        for (suite, index, len, nq, nv) in expected {
            let layout = StateLayout::for_task(task(suite, index).unwrap());
            assert_eq!((layout.row_len(), layout.nq(), layout.nv()), (len, nq, nv), "{suite}[{index}]");
            assert_eq!(layout.column_names().len(), len);
        }
    }

    #[test]
    fn decodes_a_row_into_named_parts() {
        // libero_10 task 9: two mugs, then the microwave door.
        let layout = StateLayout::for_task(task("libero_10", 9).unwrap());
        let row: Vec<f64> = (0..layout.row_len()).map(|i| i as f64).collect();
        let state = layout.decode(&row).unwrap();
        assert_eq!(state.time, 0.0);
        assert_eq!(state.arm_qpos, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        assert_eq!(state.gripper_qpos, [8.0, 9.0]);
        assert_eq!(state.objects[0].name, "porcelain_mug_1");
        assert_eq!(state.objects[0].pos, [10.0, 11.0, 12.0]);
        assert_eq!(state.objects[0].quat_wxyz, [13.0, 14.0, 15.0, 16.0]);
        assert_eq!(state.objects[1].name, "white_yellow_mug_1");
        let door = &state.joints[0];
        assert_eq!((door.owner.as_str(), door.joint.as_str(), door.qpos), ("microwave_1", "microjoint", 24.0));
        assert_eq!(state.arm_qvel[0], 25.0);
        assert_eq!(state.objects[0].lin_vel, [34.0, 35.0, 36.0]);
        assert_eq!(state.objects[1].ang_vel, [43.0, 44.0, 45.0]);
        assert_eq!(door.qvel, 46.0);
        let names = layout.column_names();
        assert_eq!(names[24], "qpos/microwave_1:microjoint");
        assert_eq!(names[46], "qvel/microwave_1:microjoint");
    }

    #[test]
    fn a_row_of_the_wrong_length_is_refused_with_the_arithmetic() {
        let layout = StateLayout::for_task(task("libero_spatial", 0).unwrap());
        let err = layout.decode(&[0.0; 91]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "state vector has 91 values, task pick_up_the_black_bowl_between_the_plate_and_the_ramekin_and_place_it_on_the_plate \
             expects 92 = 1 + nq 48 + nv 43"
        );
        assert!(layout.decode(&[]).is_err());
    }

    #[test]
    fn articulated_movable_objects_carry_their_joints_after_the_free_joint() {
        let mut t = task("libero_10", 9).unwrap().clone();
        t.objects.push(crate::task::Entity { name: "cab_1".into(), category: "short_cabinet".into() });
        let names = StateLayout::for_task(&t).column_names();
        let at = names.iter().position(|n| n == "qpos/cab_1:qz").unwrap();
        assert_eq!(names[at + 1..at + 4], ["qpos/cab_1:middle_level", "qpos/cab_1:top_region", "qpos/cab_1:bottom_region"]);
        assert_eq!(names[at + 4], "qpos/microwave_1:microjoint");
    }
}
