//! Scene classes: the arena each LIBERO problem class builds around its task.
//!
//! Facts from LIBERO's problem classes (`envs/problems/*.py`) and the compiled MuJoCo models
//! (`xval/libero_reference/model_facts.json`): where the work surface is, where the robot stands
//! and whether it is on a mount, the `agentview` camera, the lights, and how a ranged BDDL region
//! becomes a site. Colours are plain stand-ins for LIBERO's floor, wall and table textures (their
//! mean colour); we ship no textures.

use crate::task::ProblemClass;

/// A position and a unit quaternion (w, x, y, z), MuJoCo's order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
}

/// A fixed camera; like MuJoCo's, it looks along its local −z with +y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub pose: Pose,
    /// Vertical field of view in degrees.
    pub fovy_deg: f64,
}

/// A scene light as in the scene XMLs (none casts shadows).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    pub name: &'static str,
    pub pos: [f64; 3],
    pub dir: [f64; 3],
    /// Directional lights shine along `dir` from infinity; the others are spot lights at `pos`.
    pub directional: bool,
    pub diffuse: [f64; 3],
    pub specular: [f64; 3],
}

/// The ground plane z = 0, present in every scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// MuJoCo friction (sliding, torsional, rolling).
    pub friction: [f64; 3],
    pub rgb: [f64; 3],
    /// LIBERO's floor texture (path under its `assets/`), whose mean colour `rgb` is.
    pub texture: &'static str,
}

/// An axis-aligned box in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    pub center: [f64; 3],
    pub half_size: [f64; 3],
}

/// The table objects stand on: the collision boxes that form its top, all ending at the same
/// height. The tabletop and kitchen table is one box; the living-room table top is five slabs (a
/// centre and four border pieces); the study desk top is one slab. Legs and bases are left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    pub top: &'static [Cuboid],
    pub friction: [f64; 3],
    pub rgb: [f64; 3],
    /// LIBERO's cube texture of a box table (path under its `assets/`), whose mean colour `rgb`
    /// is; `None` for the tables drawn from meshes (living room, study).
    pub texture: Option<&'static str>,
}

impl Table {
    pub fn top_z(&self) -> f64 {
        self.top[0].center[2] + self.top[0].half_size[2]
    }
}

/// A box site made from a ranged region (LIBERO's `TargetZone`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RegionSite {
    pub center: [f64; 3],
    pub half_size: [f64; 3],
}

/// Everything a problem class fixes about its arena.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneClass {
    pub problem: ProblemClass,
    /// The fixture that is the arena itself (`main_table`, `floor`, ...): it is not loaded as an
    /// asset, and regions targeting it are ranged rectangles.
    pub workspace: &'static str,
    /// Region x, y are relative to this; z is the nominal work-surface height.
    pub workspace_offset: [f64; 3],
    /// World z of workspace region sites.
    pub region_site_z: f64,
    /// Added to the workspace z when a fixture is placed (LIBERO's `z_offset`).
    pub fixture_z_offset: f64,
    pub floor: Floor,
    /// `None` in the floor scene, where objects stand on the floor.
    pub table: Option<Table>,
    /// The robot's base body (`robot0_base`) in the world.
    pub robot_base: Pose,
    /// Whether the Panda stands on robosuite's RethinkMount (`MountedPanda`) or on the ground
    /// (`OnTheGroundPanda`).
    pub robot_on_mount: bool,
    /// Which arm stands at `robot_base`.
    pub arm: ArmKind,
    /// A block the arm stands on (drawn and collided as part of the arena), if any.
    pub robot_riser: Option<Cuboid>,
    /// The `agentview` camera the policy sees.
    pub agentview: Camera,
    pub lights: &'static [Light],
    pub wall_rgb: [f64; 3],
    /// LIBERO's wall texture (path under its `assets/`), whose mean colour `wall_rgb` is.
    pub wall_texture: &'static str,
}

/// The arm a scene is built with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArmKind {
    /// The Franka Panda of every LIBERO scene (OSC_POSE delta end-effector actions).
    Panda,
    /// The AgileX PiPER of the §4.4 study (joint-delta actions, see `vifo_robots::piper`).
    Piper,
}

impl ArmKind {
    /// The values of this arm's 7-D action, as errors about an action name them.
    pub fn action_names(self) -> &'static [&'static str; 7] {
        match self {
            ArmKind::Panda => &vifo_robots::action::END_EFFECTOR_DELTAS,
            ArmKind::Piper => &vifo_robots::action::JOINT_DELTAS,
        }
    }
}

/// Half-height of every region site (`TargetZone`'s `zone_height`).
pub const REGION_SITE_HALF_HEIGHT: f64 = 0.007;

impl SceneClass {
    /// The site LIBERO makes from a region range `[x_min, y_min, x_max, y_max]`: centred on the
    /// range (shifted by the workspace offset), half-size ((x_max−x_min)/2, (y_max−y_min)/2, 0.007),
    /// at [`SceneClass::region_site_z`]. LIBERO uses a region's first range for its site.
    pub fn region_site(&self, range: [f64; 4]) -> RegionSite {
        let [x0, y0, x1, y1] = range;
        RegionSite {
            center: [
                (x1 + x0) / 2.0 + self.workspace_offset[0],
                (y1 + y0) / 2.0 + self.workspace_offset[1],
                self.region_site_z,
            ],
            half_size: [(x1 - x0) / 2.0, (y1 - y0) / 2.0, REGION_SITE_HALF_HEIGHT],
        }
    }

    /// Height objects rest on: the table top, or the floor.
    pub fn support_z(&self) -> f64 {
        self.table.map_or(0.0, |t| t.top_z())
    }
}

/// The scene class of a problem; `None` for the coffee-table class, which no benchmark task uses.
pub fn scene_class(problem: ProblemClass) -> Option<&'static SceneClass> {
    match problem {
        ProblemClass::Tabletop => Some(&TABLETOP),
        ProblemClass::Floor => Some(&FLOOR),
        ProblemClass::KitchenTabletop => Some(&KITCHEN),
        ProblemClass::LivingRoomTabletop => Some(&LIVING_ROOM),
        ProblemClass::StudyTabletop => Some(&STUDY),
        ProblemClass::CoffeeTable => None,
        ProblemClass::PiperTabletop => Some(&PIPER),
    }
}

const IDENTITY: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

/// Agentview orientation of the table scenes (45° fovy, pitched ≈39° down).
const TABLE_VIEW: [f64; 4] = [0.6380177212293417, 0.30484971880648903, 0.3048498380157687, 0.6380177212293417];
/// Agentview orientation of the floor and living-room scenes (pitched ≈32° down).
const LOW_VIEW: [f64; 4] = [0.6182166363517069, 0.34323072246337577, 0.34323140791672746, 0.6182176496305746];

/// `light1` and `light2`, shared by all five scene XMLs.
const TWO_LIGHTS: [Light; 2] = [
    Light {
        name: "light1",
        pos: [1.0, 1.0, 4.0],
        dir: [0.0, -0.15, -1.0],
        directional: false,
        diffuse: [0.8; 3],
        specular: [0.3; 3],
    },
    Light {
        name: "light2",
        pos: [-3.0, -3.0, 4.0],
        dir: [0.0, -0.15, -1.0],
        directional: false,
        diffuse: [0.8; 3],
        specular: [0.3; 3],
    },
];

/// The kitchen adds a directional light from above the robot.
const KITCHEN_LIGHTS: [Light; 3] = [
    Light {
        name: "light_kitchen",
        pos: [-1.75, 0.0, 1.6],
        dir: [0.0, 0.0, -1.0],
        directional: true,
        diffuse: [0.8; 3],
        specular: [0.8; 3],
    },
    TWO_LIGHTS[0],
    TWO_LIGHTS[1],
];

/// MuJoCo's default geom friction, used by every floor and by the kitchen table.
const DEFAULT_FRICTION: [f64; 3] = [1.0, 0.005, 0.0001];
/// Friction of the living-room and study table assets.
const ASSET_FRICTION: [f64; 3] = [0.95, 0.3, 0.1];

// Mean colours of LIBERO's style textures (sRGB, 0..1).
const LIGHT_GRAY_FLOOR_TILE: [f64; 3] = [0.768, 0.732, 0.698];
const GRAY_CERAMIC_TILE: [f64; 3] = [0.730, 0.669, 0.607];
const WOOD_PLANK_FLOOR: [f64; 3] = [0.915, 0.785, 0.537];
const LIGHT_GRAY_PLASTER: [f64; 3] = [0.873, 0.857, 0.831];
const YELLOW_LINEN: [f64; 3] = [0.862, 0.836, 0.707];
const WOOD_TABLE: [f64; 3] = [0.775, 0.707, 0.634];
// The two table meshes' textures are atlases on black: means of the texels they use (the living-
// room table's non-black texels, the study desk's wood panels).
const LIVING_ROOM_TABLE: [f64; 3] = [0.378, 0.266, 0.210];
const STUDY_DESK: [f64; 3] = [0.582, 0.431, 0.250];

/// The 1.0 × 1.2 × 0.05 m table of the tabletop and kitchen scenes, top at z = 0.90.
const PLAIN_TABLE_TOP: [Cuboid; 1] = [Cuboid { center: [0.0, 0.0, 0.875], half_size: [0.5, 0.6, 0.025] }];

const fn plain_table(friction: [f64; 3]) -> Table {
    Table { top: &PLAIN_TABLE_TOP, friction, rgb: WOOD_TABLE, texture: Some("textures/martin_novak_wood_table.png") }
}

/// The living-room table's top slabs, top at z = 0.43676.
const LIVING_ROOM_TABLE_TOP: [Cuboid; 5] = [
    Cuboid { center: [-0.25, 0.05239, 0.42492], half_size: [0.44432, 0.67171, 0.01184] },
    Cuboid { center: [-0.25, 0.79936, 0.42492], half_size: [0.41675, 0.10133, 0.01184] },
    Cuboid { center: [-0.25, -0.72006, 0.42492], half_size: [0.41675, 0.10133, 0.01184] },
    Cuboid { center: [0.26121, 0.05239, 0.42492], half_size: [0.07752, 0.67171, 0.01184] },
    Cuboid { center: [-0.74665, 0.05239, 0.42492], half_size: [0.07752, 0.67171, 0.01184] },
];

/// The study desk's top slab, top at z = 0.88513.
const STUDY_DESK_TOP: [Cuboid; 1] = [Cuboid { center: [0.0, 0.0, 0.84929], half_size: [0.68946, 1.39273, 0.03584] }];

/// LIBERO's plain-table scene; the PiPER setting differs from it only in the robot and the camera.
const TABLETOP_CLASS: SceneClass = SceneClass {
    problem: ProblemClass::Tabletop,
    workspace: "main_table",
    workspace_offset: [0.0, 0.0, 0.9],
    region_site_z: 0.895,
    fixture_z_offset: 0.01 - 0.05,
    floor: Floor { friction: DEFAULT_FRICTION, rgb: LIGHT_GRAY_FLOOR_TILE, texture: "textures/light-gray-floor-tile.png" },
    table: Some(plain_table([0.6, 0.005, 0.0001])),
    robot_base: Pose { pos: [-0.66, 0.0, 0.912], quat_wxyz: IDENTITY },
    robot_on_mount: true,
    arm: ArmKind::Panda,
    robot_riser: None,
    agentview: Camera {
        pose: Pose { pos: [0.6586131746834771, 0.0, 1.6103500240372424], quat_wxyz: TABLE_VIEW },
        fovy_deg: 45.0,
    },
    lights: &TWO_LIGHTS,
    wall_rgb: LIGHT_GRAY_PLASTER,
    wall_texture: "textures/light-gray-plaster.png",
};

static TABLETOP: SceneClass = TABLETOP_CLASS;

static FLOOR: SceneClass = SceneClass {
    problem: ProblemClass::Floor,
    workspace: "floor",
    workspace_offset: [0.0, 0.0, -0.035],
    region_site_z: 0.02,
    fixture_z_offset: -0.025,
    floor: Floor { friction: DEFAULT_FRICTION, rgb: LIGHT_GRAY_FLOOR_TILE, texture: "textures/light-gray-floor-tile.png" },
    table: None,
    robot_base: Pose { pos: [-0.6, 0.0, 0.0], quat_wxyz: IDENTITY },
    robot_on_mount: false,
    arm: ArmKind::Panda,
    robot_riser: None,
    agentview: Camera {
        pose: Pose { pos: [0.8965773716836134, 5.216182733499864e-07, 0.65], quat_wxyz: LOW_VIEW },
        fovy_deg: 45.0,
    },
    lights: &TWO_LIGHTS,
    wall_rgb: LIGHT_GRAY_PLASTER,
    wall_texture: "textures/light-gray-plaster.png",
};

static KITCHEN: SceneClass = SceneClass {
    problem: ProblemClass::KitchenTabletop,
    workspace: "kitchen_table",
    workspace_offset: [0.0, 0.0, 0.9],
    // Sites go 0.90 below the workspace height in a table body at 0.875.
    region_site_z: 0.875,
    fixture_z_offset: 0.01 - 0.05,
    floor: Floor { friction: DEFAULT_FRICTION, rgb: GRAY_CERAMIC_TILE, texture: "textures/gray_ceramic_tile.png" },
    table: Some(plain_table(DEFAULT_FRICTION)),
    robot_base: Pose { pos: [-0.66, 0.0, 0.912], quat_wxyz: IDENTITY },
    robot_on_mount: true,
    arm: ArmKind::Panda,
    robot_riser: None,
    agentview: Camera {
        pose: Pose { pos: [0.6586131746834771, 0.0, 1.6103500240372424], quat_wxyz: TABLE_VIEW },
        fovy_deg: 45.0,
    },
    lights: &KITCHEN_LIGHTS,
    wall_rgb: YELLOW_LINEN,
    wall_texture: "textures/yellow_linen_wall_texture.png",
};

static LIVING_ROOM: SceneClass = SceneClass {
    problem: ProblemClass::LivingRoomTabletop,
    workspace: "living_room_table",
    workspace_offset: [0.0, 0.0, 0.41],
    region_site_z: 0.41,
    fixture_z_offset: 0.01 - 0.024,
    floor: Floor { friction: DEFAULT_FRICTION, rgb: WOOD_PLANK_FLOOR, texture: "textures/seamless_wood_planks_floor.png" },
    table: Some(Table { top: &LIVING_ROOM_TABLE_TOP, friction: ASSET_FRICTION, rgb: LIVING_ROOM_TABLE, texture: None }),
    robot_base: Pose { pos: [-0.51, 0.0, 0.42], quat_wxyz: IDENTITY },
    robot_on_mount: false,
    arm: ArmKind::Panda,
    robot_riser: None,
    agentview: Camera { pose: Pose { pos: [0.6065773716836134, 0.0, 0.96], quat_wxyz: LOW_VIEW }, fovy_deg: 45.0 },
    lights: &TWO_LIGHTS,
    wall_rgb: LIGHT_GRAY_PLASTER,
    wall_texture: "textures/light-gray-plaster.png",
};

static STUDY: SceneClass = SceneClass {
    problem: ProblemClass::StudyTabletop,
    workspace: "study_table",
    workspace_offset: [-0.2, 0.0, 0.867],
    region_site_z: 0.867,
    fixture_z_offset: 0.01 - 0.05,
    floor: Floor { friction: DEFAULT_FRICTION, rgb: LIGHT_GRAY_FLOOR_TILE, texture: "textures/light-gray-floor-tile.png" },
    table: Some(Table { top: &STUDY_DESK_TOP, friction: ASSET_FRICTION, rgb: STUDY_DESK, texture: None }),
    robot_base: Pose { pos: [-0.75, 0.0, 0.912], quat_wxyz: IDENTITY },
    robot_on_mount: true,
    arm: ArmKind::Panda,
    robot_riser: None,
    agentview: Camera {
        pose: Pose { pos: [0.4586131746834771, 0.0, 1.6103500240372424], quat_wxyz: TABLE_VIEW },
        fovy_deg: 45.0,
    },
    lights: &TWO_LIGHTS,
    wall_rgb: LIGHT_GRAY_PLASTER,
    wall_texture: "textures/light-gray-plaster.png",
};

/// The §4.4 setting: the plain table, the PiPER on a 10 cm riser 0.4 m behind the table's
/// centre (so its straight-down gripper reaches above a stack of cups: pointing down, the PiPER
/// only reaches about 10 cm above its own base), and an agentview camera facing it from across
/// the table, 0.7 m from the cups, pitched as LIBERO's table views.
static PIPER: SceneClass = SceneClass {
    problem: ProblemClass::PiperTabletop,
    robot_base: Pose { pos: [-0.4, 0.0, 1.0], quat_wxyz: IDENTITY },
    robot_on_mount: false,
    arm: ArmKind::Piper,
    robot_riser: Some(Cuboid { center: [-0.41, 0.0, 0.95], half_size: [0.08, 0.08, 0.05] }),
    agentview: Camera { pose: Pose { pos: [0.35, 0.0, 1.35], quat_wxyz: TABLE_VIEW }, fovy_deg: 45.0 },
    ..TABLETOP_CLASS
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::task::all_tasks;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn region_sites_follow_the_research_notes() {
        // libero_goal's stove_front_region on the main table.
        let site = TABLETOP.region_site([-0.09, 0.17, -0.01, 0.25]);
        assert!(close(site.center, [-0.05, 0.21, 0.895]), "{site:?}");
        assert!(close(site.half_size, [0.04, 0.04, 0.007]), "{site:?}");
        // libero_10 task 6: plate_right_region on the living-room table.
        let site = LIVING_ROOM.region_site([0.1, 0.05, 0.2, 0.15]);
        assert!(close(site.center, [0.15, 0.10, 0.41]), "{site:?}");
        // The study shifts x by its workspace offset.
        let site = STUDY.region_site([-0.025, 0.125, 0.025, 0.175]);
        assert!(close(site.center, [-0.2, 0.15, 0.867]), "{site:?}");
    }

    #[test]
    fn every_builtin_task_has_a_scene_whose_workspace_it_declares() {
        for task in all_tasks() {
            let class = scene_class(task.problem).expect("the 40 tasks use the five supported classes");
            assert_eq!(class.problem, task.problem);
            assert!(task.fixture(class.workspace).is_some(), "{}", task.label());
            for region in task.regions.iter().filter(|r| r.is_ranged()) {
                assert_eq!(region.target, class.workspace, "{}: {}", task.label(), region.key);
            }
        }
        assert_eq!(scene_class(ProblemClass::CoffeeTable), None);
    }

    #[test]
    fn surfaces_lights_and_mounts() {
        assert!((TABLETOP.support_z() - 0.9).abs() < 1e-12);
        assert!((LIVING_ROOM.support_z() - 0.43676).abs() < 1e-9);
        assert!((STUDY.support_z() - 0.88513).abs() < 1e-9);
        assert_eq!(FLOOR.support_z(), 0.0);
        for class in [&TABLETOP, &KITCHEN, &LIVING_ROOM, &STUDY] {
            let table = class.table.unwrap();
            for slab in table.top {
                assert!((slab.center[2] + slab.half_size[2] - table.top_z()).abs() < 1e-12, "{:?}", class.problem);
            }
        }
        assert_eq!(KITCHEN.lights.len(), 3);
        assert!(KITCHEN.lights[0].directional);
        let mounted: Vec<bool> = ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)).map(|c| c.robot_on_mount).collect();
        assert_eq!(mounted, [true, false, true, false, true, false]);
        for class in ProblemClass::ALL.iter().filter_map(|&p| scene_class(p)) {
            let q = class.agentview.pose.quat_wxyz;
            let norm: f64 = q.iter().map(|x| x * x).sum();
            assert!((norm - 1.0).abs() < 1e-6, "{:?}", class.problem);
        }
    }
}
