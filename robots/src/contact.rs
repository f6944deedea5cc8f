//! Contact layers: which shapes may touch which (MuJoCo's contype/conaffinity, as rapier
//! interaction groups).

use vifo_physics::rapier::prelude::{Group, InteractionGroups, InteractionTestMode};

use crate::model::ContactRole;

const LINK: Group = Group::GROUP_1;
const FINGER: Group = Group::GROUP_2;
const PAD: Group = Group::GROUP_3;
const SCENE: Group = Group::GROUP_4;

/// Groups for everything that is not the robot (objects, fixtures, tables, floors): they touch
/// everything, the robot included.
pub const SCENE_GROUPS: InteractionGroups = InteractionGroups::new(SCENE, Group::ALL, InteractionTestMode::And);

/// Groups for a robot shape. Links touch the scene only; finger shells touch the scene and the
/// pads but not the other shell (robosuite: contype 0, conaffinity 1); pads touch everything.
pub fn groups(role: ContactRole) -> InteractionGroups {
    let (member, filter) = match role {
        ContactRole::Link => (LINK, SCENE),
        ContactRole::Finger => (FINGER, SCENE.union(PAD)),
        ContactRole::Pad => (PAD, SCENE.union(PAD).union(FINGER)),
    };
    InteractionGroups::new(member, filter, InteractionTestMode::And)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robosuite_pairs() {
        let (link, finger, pad) = (groups(ContactRole::Link), groups(ContactRole::Finger), groups(ContactRole::Pad));
        assert!(link.test(SCENE_GROUPS) && finger.test(SCENE_GROUPS) && pad.test(SCENE_GROUPS));
        assert!(pad.test(pad) && pad.test(finger) && finger.test(pad));
        assert!(!finger.test(finger) && !link.test(link) && !link.test(pad));
        assert!(SCENE_GROUPS.test(SCENE_GROUPS));
    }
}
