//! Contact layers: which shapes may touch which (MuJoCo's contype/conaffinity, as rapier
//! interaction groups).

use vifo_physics::rapier::prelude::{Group, InteractionGroups, InteractionTestMode};

use crate::model::ContactRole;

const LINK: Group = Group::GROUP_1;
const FINGER: Group = Group::GROUP_2;
const PAD: Group = Group::GROUP_3;
const SCENE: Group = Group::GROUP_4;
const ARENA: Group = Group::GROUP_5;
const PART: Group = Group::GROUP_6;
const FRAME: Group = Group::GROUP_7;
/// Every scene-side layer: what robot shapes touch.
const SCENE_SIDE: Group = SCENE.union(ARENA).union(PART).union(FRAME);

/// Groups for objects and fixtures without moving parts (baskets, racks): they touch everything,
/// the robot included.
pub const SCENE_GROUPS: InteractionGroups = InteractionGroups::new(SCENE, Group::ALL, InteractionTestMode::And);

/// Groups for the still body of a fixture with moving parts (a cabinet's frame, a stove): like
/// [`SCENE_GROUPS`], but its own parts never touch it (MuJoCo's parent-child filter; they ride on
/// their joints inside it). The body is a plain fixed body, not the root of the parts' multibody:
/// what rests on it is then an ordinary contact, solved four at a time and asleep once still,
/// rather than a generic multibody row kept awake with the parts (in a sample of the expert pass a
/// quarter of all contact points were objects on such roots). The one loss: a part never touches
/// another fixture's frame either (LIBERO's fixtures stand apart).
pub const FRAME_GROUPS: InteractionGroups = InteractionGroups::new(FRAME, Group::ALL.difference(PART), InteractionTestMode::And);

/// Groups for the arena (table tops, floors): everything but the articulated parts.
pub const ARENA_GROUPS: InteractionGroups =
    InteractionGroups::new(ARENA, Group::ALL.difference(PART), InteractionTestMode::And);

/// Groups for the moving parts of fixtures (drawers, doors, knobs). Their joint carries them,
/// so a contact with the table or floor they rest on only adds friction to the joint; left on,
/// a stove knob's eighteen boxes lying on the table kept 72 contacts (and every object on the
/// stove) in the solver at every substep.
pub const PART_GROUPS: InteractionGroups =
    InteractionGroups::new(PART, Group::ALL.difference(ARENA).difference(FRAME), InteractionTestMode::And);

/// Groups for a robot shape. Finger shells touch the scene and the pads but not the other
/// shell (robosuite: contype 0, conaffinity 1); pads touch everything. Links (with the hand and
/// the mount) touch only the scene here; with `soft` (an arm whose contacts with itself and with
/// the scene's fixed colliders are MuJoCo's soft ones, [`crate::soft_contact`]), not the arena
/// and the fixtures' still bodies either. Parent–child pairs never touch (`joint::one_dof`).
pub fn groups(role: ContactRole, soft: bool) -> InteractionGroups {
    let (member, filter) = match role {
        ContactRole::Link if soft => (LINK, SCENE_SIDE.difference(ARENA).difference(FRAME)),
        ContactRole::Link => (LINK, SCENE_SIDE),
        ContactRole::Finger => (FINGER, SCENE_SIDE.union(PAD)),
        ContactRole::Pad => (PAD, SCENE_SIDE.union(PAD).union(FINGER)),
    };
    InteractionGroups::new(member, filter, InteractionTestMode::And)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robosuite_pairs() {
        let [link, finger, pad] = [ContactRole::Link, ContactRole::Finger, ContactRole::Pad].map(|r| groups(r, false));
        assert!(link.test(SCENE_GROUPS) && finger.test(SCENE_GROUPS) && pad.test(SCENE_GROUPS));
        assert!(pad.test(pad) && pad.test(finger) && finger.test(pad));
        assert!(!link.test(finger) && !finger.test(link) && !link.test(pad) && !pad.test(link) && !link.test(link));
        assert!(!finger.test(finger));
        // A soft arm's links leave the arena and fixture frames to its soft contacts.
        let soft = groups(ContactRole::Link, true);
        assert!(!soft.test(ARENA_GROUPS) && !soft.test(FRAME_GROUPS) && soft.test(SCENE_GROUPS) && soft.test(PART_GROUPS));
        assert!(groups(ContactRole::Finger, true).test(ARENA_GROUPS) && groups(ContactRole::Pad, true).test(FRAME_GROUPS));
        assert!(SCENE_GROUPS.test(SCENE_GROUPS));
        for robot in [link, finger, pad] {
            assert!(robot.test(ARENA_GROUPS) && robot.test(PART_GROUPS));
        }
        assert!(SCENE_GROUPS.test(ARENA_GROUPS) && SCENE_GROUPS.test(PART_GROUPS) && PART_GROUPS.test(PART_GROUPS));
        assert!(!PART_GROUPS.test(ARENA_GROUPS) && !ARENA_GROUPS.test(PART_GROUPS));
        for robot in [link, finger, pad] {
            assert!(robot.test(FRAME_GROUPS));
        }
        assert!(SCENE_GROUPS.test(FRAME_GROUPS) && ARENA_GROUPS.test(FRAME_GROUPS) && FRAME_GROUPS.test(FRAME_GROUPS));
        assert!(!PART_GROUPS.test(FRAME_GROUPS) && !FRAME_GROUPS.test(PART_GROUPS));
    }
}
