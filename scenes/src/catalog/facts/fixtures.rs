//! Facts of the fixtures (LIBERO `articulated_objects/` and the TurboSquid wine rack and desk
//! caddy): bodies, joints, collision geoms (position, quaternion wxyz, half-size) and the sites
//! the goal predicates read. Jointless XML sub-bodies are fused into their parent.

use crate::catalog::inertia::MassSource;
use crate::catalog::model::{ColliderShape, JointKind, ObjectKind, SiteShape};
use crate::catalog::spec::{
    BodyDef, Contact, ExplicitInertial, GeomDef, JointDef, ObjectDef, SiteDef, IDENTITY, MUJOCO_DEFAULT_SURFACE, ORIGIN, bx, region,
};

/// The microwave's `micro_collision` class: default friction, softer contacts, 1 mm margin,
/// and contype 0 (it is touched by others but does not seek contacts itself).
const MICROWAVE_SURFACE: Contact = Contact {
    friction: [1.0, 0.005, 0.0001],
    solref: [0.02, 1.0],
    solimp: [0.8, 0.9, 0.01, 0.5, 2.0],
    margin: 0.001,
    contype: 0,
    conaffinity: 1,
    condim: 3,
};

/// Bodies of both cabinets: the carcass (root) and the three drawers.
const CABINET_BODIES: &[BodyDef] = &[
    BodyDef {
        name: "main",
        parent: None,
        pos: ORIGIN,
        quat: IDENTITY,
        joint: None,
        inertial: None,
        geoms: &[
            bx([0.00397, 0.10954, 0.1135], [0.49988, -0.50104, -0.50012, 0.49896], [0.00193, 0.10453, 0.11106]),
            bx([0.00405, 0.01635, 0.00686], [0.70792, 0.00065, 0.70629, -0.00065], [0.00199, 0.0896, 0.12277]),
            bx([-0.11216, 0.01625, 0.11426], [0.0, 0.0, 1.0, 0.0], [0.00517, 0.09542, 0.10584]),
            bx([0.11898, 0.01625, 0.11426], [0.0, 1.0, 0.0, 0.0], [0.00517, 0.09542, 0.10584]),
            bx([0.00211, 0.10938, 0.11426], [0.49997, 0.49997, -0.50003, -0.50003], [0.00231, 0.10584, 0.11912]),
            bx([0.00376, 0.01868, 0.14935], [0.70792, 0.00065, 0.70629, -0.00065], [0.00085, 0.08935, 0.11168]),
            bx([0.00408, 0.01868, 0.00933], [0.00065, -0.70792, 0.00065, 0.70629], [0.00085, 0.08935, 0.11168]),
            bx([0.00392, 0.01868, 0.07928], [0.70792, 0.00065, 0.70629, -0.00065], [0.00085, 0.08935, 0.11168]),
            bx([0.00394, 0.01577, 0.22157], [0.70711, 0.0, 0.70711, 0.0], [0.00142, 0.09409, 0.12729]),
        ],
    },
    BodyDef {
        name: "cabinet_top",
        parent: Some(0),
        pos: ORIGIN,
        quat: IDENTITY,
        joint: Some(JointDef { kind: JointKind::Slide, name: "top_level", axis: [0.0, 1.0, 0.0], pos: [0.0, 0.0, 0.0], range: [-0.16, 0.01], damping: 50.0 }),
        inertial: Some(ExplicitInertial { mass: 3.0, com: [0.0, 0.0, 0.0], diag: [1.0, 1.0, 1.0] }),
        geoms: &[
            bx([0.00334, -0.07524, 0.18309], [0.5, 0.5, -0.5, -0.5], [0.00271, 0.03427, 0.10934]),
            bx([0.00334, -0.06839, 0.18358], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([0.00334, 0.09077, 0.18358], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([-0.10191, 0.01105, 0.18358], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03165, 0.08148]),
            bx([0.10894, 0.01105, 0.18358], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03133, 0.08148]),
            bx([0.00348, 0.01048, 0.15514], [0.70711, 0.0, 0.70711, 0.0], [0.00401, 0.08095, 0.10696]),
            bx([-0.00278, -0.10161, 0.18393], [0.5, 0.5, -0.5, -0.5], [0.0077, 0.00817, 0.04445]),
            bx([0.02916, -0.08348, 0.18393], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.00552, 0.01057]),
            bx([-0.0356, -0.08348, 0.18393], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.0056, 0.01057]),
        ],
    },
    BodyDef {
        name: "cabinet_middle",
        parent: Some(0),
        pos: ORIGIN,
        quat: IDENTITY,
        joint: Some(JointDef { kind: JointKind::Slide, name: "middle_level", axis: [0.0, 1.0, 0.0], pos: [0.0, 0.0, 0.0], range: [-0.16, 0.01], damping: 50.0 }),
        inertial: Some(ExplicitInertial { mass: 3.0, com: [0.0, 0.0, 0.0], diag: [1.0, 1.0, 1.0] }),
        geoms: &[
            bx([0.00334, -0.07524, 0.11338], [0.5, 0.5, -0.5, -0.5], [0.00271, 0.03427, 0.10934]),
            bx([0.00334, 0.09077, 0.11387], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([0.00334, -0.06839, 0.11387], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([0.10894, 0.01105, 0.11387], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03133, 0.08148]),
            bx([-0.10191, 0.01105, 0.11387], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03165, 0.08148]),
            bx([0.00348, 0.01048, 0.08543], [0.70711, 0.0, 0.70711, 0.0], [0.00401, 0.08095, 0.10696]),
            bx([-0.00278, -0.10161, 0.11041], [0.5, 0.5, -0.5, -0.5], [0.0077, 0.00817, 0.04445]),
            bx([0.02916, -0.08348, 0.11041], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.00552, 0.01057]),
            bx([-0.0356, -0.08348, 0.11041], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.0056, 0.01057]),
        ],
    },
    BodyDef {
        name: "cabinet_bottom",
        parent: Some(0),
        pos: ORIGIN,
        quat: IDENTITY,
        joint: Some(JointDef { kind: JointKind::Slide, name: "bottom_level", axis: [0.0, 1.0, 0.0], pos: [0.0, 0.0, 0.0], range: [-0.16, 0.01], damping: 50.0 }),
        inertial: Some(ExplicitInertial { mass: 3.0, com: [0.0, 0.0, 0.0], diag: [1.0, 1.0, 1.0] }),
        geoms: &[
            bx([0.00334, -0.07524, 0.04476], [0.5, 0.5, -0.5, -0.5], [0.00271, 0.03427, 0.10934]),
            bx([0.00334, 0.09077, 0.04525], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([0.00334, -0.06839, 0.04525], [0.5, 0.5, 0.5, 0.5], [0.00356, 0.03214, 0.10679]),
            bx([0.10894, 0.01105, 0.04525], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03133, 0.08148]),
            bx([-0.10191, 0.01105, 0.04525], [0.70711, 0.70711, -0.00115, -0.00115], [0.00241, 0.03165, 0.08148]),
            bx([0.00348, 0.01048, 0.01682], [0.70711, 0.0, 0.70711, 0.0], [0.00401, 0.08095, 0.10696]),
            bx([-0.00278, -0.10161, 0.04114], [0.5, 0.5, -0.5, -0.5], [0.0077, 0.00817, 0.04445]),
            bx([0.02916, -0.08348, 0.04114], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.00552, 0.01057]),
            bx([-0.0356, -0.08348, 0.04114], [0.70711, 0.70711, 0.0, 0.0], [0.00507, 0.0056, 0.01057]),
        ],
    },
];

/// Sites of both cabinets.
const CABINET_SITES: &[SiteDef] = &[
    region("top_side", 0, [0.00354, 0.01567, 0.22152], [1.0, 0.0, 0.0, 0.0], [0.12534, 0.09438, 0.00147]),
    region("top_region", 1, [0.00328, 0.01128, 0.18563], [0.70711, 0.0, 0.70711, 0.0], [0.02993, 0.07561, 0.10224]),
    region("middle_region", 2, [0.00328, 0.01128, 0.1169], [0.70711, 0.0, 0.70711, 0.0], [0.02993, 0.07561, 0.10224]),
    region("bottom_region", 3, [0.00328, 0.01128, 0.04701], [0.70711, 0.0, 0.70711, 0.0], [0.02993, 0.07561, 0.10224]),
];

/// `wooden_cabinet`: three drawers sliding along body y (negative = pulled out towards -y).
/// `top_side` is the `On` region on its lid; `*_region` sites ride in the drawers.
pub(crate) const WOODEN_CABINET: ObjectDef = ObjectDef {
    category: "wooden_cabinet",
    kind: ObjectKind::Fixture,
    bodies: CABINET_BODIES,
    sites: CABINET_SITES,
    bottom: [0.0, 0.0, -0.045],
    top: [0.0, 0.0, 0.045],
    horizontal_radius: 0.045,
};

/// `white_cabinet`: same geometry as the wooden cabinet, white wood.
pub(crate) const WHITE_CABINET: ObjectDef = ObjectDef {
    category: "white_cabinet",
    kind: ObjectKind::Fixture,
    bodies: CABINET_BODIES,
    sites: CABINET_SITES,
    bottom: [0.0, 0.0, -0.045],
    top: [0.0, 0.0, 0.045],
    horizontal_radius: 0.045,
};

/// `flat_stove`: burner plate at x = 0.15 (the XML's `burner` body, fused into the root) and the knob
/// body `button` turning about z; `burner` is the red on-indicator site.
pub(crate) const FLAT_STOVE: ObjectDef = ObjectDef {
    category: "flat_stove",
    kind: ObjectKind::Fixture,
    bodies: &[
        BodyDef {
            name: "main",
            parent: None,
            pos: ORIGIN,
            quat: IDENTITY,
            joint: None,
            inertial: None,
            geoms: &[
                GeomDef { shape: ColliderShape::Box { half_size: [0.095, 0.095, 0.02] }, pos: [0.15, 0.0, 0.0], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Density(1000.0), contact: &MUJOCO_DEFAULT_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.095, 0.095, 0.0005] }, pos: [0.15, 0.0, 0.025], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Density(1000.0), contact: &MUJOCO_DEFAULT_SURFACE },
            ],
        },
        BodyDef {
            name: "button",
            parent: Some(0),
            pos: ORIGIN,
            quat: [0.7071068, 0.0, 0.0, 0.7071068],
            joint: Some(JointDef { kind: JointKind::Hinge, name: "button", axis: [0.0, 0.0, 1.0], pos: [0.0, 0.0, 0.0], range: [-0.005, 2.1], damping: 1.0 }),
            inertial: Some(ExplicitInertial { mass: 3.0, com: [0.0, 0.0, 0.0], diag: [1.0, 1.0, 1.0] }),
            geoms: &[
                bx([0.00132, 0.00458, 0.00657], [0.00206, -0.7071, 0.00206, 0.7071], [0.00621, 0.03396, 0.03396]),
                bx([0.00111, -0.03234, 0.00657], [0.49854, 0.49854, -0.50145, -0.50145], [0.00296, 0.00621, 0.02939]),
                bx([0.00111, -0.03234, 0.00657], [0.49854, 0.49854, -0.50145, -0.50145], [0.00296, 0.00621, 0.02939]),
                bx([0.00108, -0.0365, 0.00657], [0.49855, -0.49855, 0.50145, -0.50145], [0.00211, 0.00621, 0.02497]),
                bx([0.00105, -0.04112, 0.00657], [0.49854, 0.49854, -0.50145, -0.50145], [0.00211, 0.00621, 0.01416]),
                bx([0.00158, 0.04983, 0.00657], [0.49855, 0.49855, -0.50145, -0.50145], [0.00211, 0.00621, 0.01416]),
                bx([0.00156, 0.0464, 0.00657], [0.50145, 0.50145, 0.49855, 0.49855], [0.00211, 0.00621, 0.02497]),
                bx([0.00154, 0.04175, 0.00657], [0.50145, 0.50145, 0.49854, 0.49854], [0.00296, 0.00621, 0.02939]),
                bx([0.0385, 0.00412, 0.00657], [0.70709, 0.70709, -0.00429, -0.00429], [0.00296, 0.00621, 0.02939]),
                bx([0.04314, 0.00407, 0.00657], [0.00429, 0.00429, 0.70709, 0.70709], [0.00211, 0.00621, 0.02497]),
                bx([0.04657, 0.00403, 0.00657], [0.70709, 0.70709, -0.00431, -0.00431], [0.00211, 0.00621, 0.01416]),
                bx([-0.04392, 0.00544, 0.00657], [0.70707, 0.70707, -0.00674, -0.00674], [0.00211, 0.00621, 0.01416]),
                bx([-0.04049, 0.00537, 0.00657], [0.00673, 0.00673, 0.70707, 0.70707], [0.00211, 0.00621, 0.02497]),
                bx([-0.03585, 0.00528, 0.00657], [0.70707, -0.70707, 0.00674, -0.00674], [0.00296, 0.00621, 0.02939]),
                bx([0.00139, 0.01737, 0.0257], [0.00205, 0.00205, 0.7071, 0.7071], [0.01214, 0.02432, 0.03454]),
                bx([0.00118, -0.02003, 0.02439], [0.0, -0.70916, -0.70505, 0.0], [0.00776, 0.01214, 0.02048]),
                bx([0.00115, -0.02496, 0.02505], [0.0, -0.70505, 0.70916, 0.0], [0.00776, 0.01214, 0.01739]),
                bx([0.00108, -0.03643, 0.01715], [0.0, -0.70505, 0.70916, 0.0], [0.00415, 0.01214, 0.01661]),
            ],
        },
    ],
    sites: &[
        region("cook_region", 0, [0.15, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.075, 0.075, 0.0025]),
        SiteDef { name: "burner", body: 0, pos: [0.15, 0.0, 0.022], quat: [1.0, 0.0, 0.0, 0.0], shape: SiteShape::Cylinder, half_size: [0.0625, 0.0625, 0.0005], rgba: [0.9, 0.05, 0.05, 1.0] },
    ],
    bottom: [0.0, 0.0, -0.045],
    top: [0.0, 0.0, 0.045],
    horizontal_radius: 0.045,
};

/// `microwave`: box shell plus a door hinged about z at its left front edge; the door handle is three
/// capsules. Collision geoms have an explicit mass and MuJoCo's margin 0.001.
pub(crate) const MICROWAVE: ObjectDef = ObjectDef {
    category: "microwave",
    kind: ObjectKind::Fixture,
    bodies: &[
        BodyDef {
            name: "main",
            parent: None,
            pos: ORIGIN,
            quat: IDENTITY,
            joint: None,
            inertial: None,
            geoms: &[
                GeomDef { shape: ColliderShape::Box { half_size: [0.0145, 0.09955, 0.0935] }, pos: [-0.158, 0.0115, 0.0935], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.0545, 0.09955, 0.0935] }, pos: [0.118, 0.0115, 0.0935], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.1035, 0.015, 0.0935] }, pos: [-0.0405, 0.0955, 0.0935], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.1035, 0.0845, 0.0095] }, pos: [-0.04, -0.0035, 0.1775], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.1035, 0.084, 0.012] }, pos: [-0.04, -0.004, 0.012], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.0425, 0.012, 0.0935] }, pos: [0.13, -0.0985, 0.0935], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.5), contact: &MICROWAVE_SURFACE },
            ],
        },
        BodyDef {
            name: "microdoorroot",
            parent: Some(0),
            pos: [-0.1725, -0.088, 0.096],
            quat: IDENTITY,
            joint: Some(JointDef { kind: JointKind::Hinge, name: "microjoint", axis: [0.0, 0.0, 1.0], pos: [0.0, 0.0, 0.0], range: [-2.094, 0.0], damping: 0.5 }),
            inertial: None,
            geoms: &[
                GeomDef { shape: ColliderShape::Capsule { radius: 0.01, half_length: 0.065 }, pos: [0.2375, -0.054, 0.0], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.02), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Capsule { radius: 0.01, half_length: 0.015 }, pos: [0.2375, -0.0375, 0.065], quat: [0.7073882691671998, 0.706825181105366, 0.0, 0.0], mass: MassSource::Mass(0.02), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Capsule { radius: 0.01, half_length: 0.015 }, pos: [0.2375, -0.0375, -0.065], quat: [0.7073882691671998, 0.706825181105366, 0.0, 0.0], mass: MassSource::Mass(0.02), contact: &MICROWAVE_SURFACE },
                GeomDef { shape: ColliderShape::Box { half_size: [0.1295, 0.012, 0.0925] }, pos: [0.1295, -0.013, 0.0], quat: [1.0, 0.0, 0.0, 0.0], mass: MassSource::Mass(0.2), contact: &MICROWAVE_SURFACE },
            ],
        },
    ],
    sites: &[
        region("top_side", 0, [0.0, 0.01, 0.2], [1.0, 0.0, 0.0, 0.0], [0.12, 0.0835, 0.005]),
        region("heating_region", 0, [0.0, 0.01, 0.096], [1.0, 0.0, 0.0, 0.0], [0.12, 0.0835, 0.08]),
    ],
    bottom: [0.0, 0.0, -0.06],
    top: [0.0, 0.0, 0.06],
    horizontal_radius: 0.015,
};

/// `wine_rack`: tilted planks on a stand; `top_region` (tilted about x) is where the bottle goes.
pub(crate) const WINE_RACK: ObjectDef = ObjectDef {
    category: "wine_rack",
    kind: ObjectKind::Fixture,
    bodies: &[
        BodyDef {
            name: "main",
            parent: None,
            pos: ORIGIN,
            quat: IDENTITY,
            joint: None,
            inertial: None,
            geoms: &[
                bx([0.0, -0.0061, 0.25118], [0.68093, 0.19061, 0.68093, 0.19061], [0.0045, 0.07894, 0.13438]),
                bx([0.0, -0.04273, 0.12727], [0.68093, 0.19061, -0.68093, -0.19061], [0.0045, 0.07894, 0.13438]),
                bx([0.0, -0.07477, 0.22072], [0.6102, -0.35728, -0.6102, 0.35728], [0.00108, 0.00867, 0.13222]),
                bx([0.0, -0.10912, 0.09735], [0.35728, 0.6102, -0.35728, -0.6102], [0.00108, 0.00867, 0.13222]),
                bx([0.0, 0.0, 0.00657], [0.5, -0.5, 0.5, 0.5], [0.0045, 0.06646, 0.09302]),
                bx([0.0, 0.06935, 0.01006], [0.7056, -0.04613, -0.7056, 0.04613], [0.00447, 0.06004, 0.08995]),
                bx([0.0, -0.0643, 0.01263], [0.04959, -0.70537, -0.04959, 0.70537], [0.00447, 0.06004, 0.08995]),
                bx([0.0, 0.0, 0.0205], [0.70711, 0.0, 0.70711, 0.0], [0.0045, 0.0141, 0.09045]),
                bx([0.0, 0.00886, 0.17026], [0.0, 0.0, -0.13781, -0.99046], [0.00762, 0.00905, 0.16165]),
            ],
        },
    ],
    sites: &[
        region("top_region", 0, [0.0, -0.08003, 0.21745], [0.8549119, -0.5187733, 0.0, 0.0], [0.10087, 0.022, 0.00251]),
    ],
    bottom: [0.0, 0.0, -0.06],
    top: [0.0, 0.0, 0.04],
    horizontal_radius: 0.025,
};

/// `desk_caddy`: four compartments; `back_contain_region` is the `In` goal region of STUDY_SCENE1.
pub(crate) const DESK_CADDY: ObjectDef = ObjectDef {
    category: "desk_caddy",
    kind: ObjectKind::Fixture,
    bodies: &[
        BodyDef {
            name: "main",
            parent: None,
            pos: ORIGIN,
            quat: IDENTITY,
            joint: None,
            inertial: None,
            geoms: &[
                bx([0.0, 0.0, 0.0076], [0.5, -0.5, 0.5, 0.5], [0.00621, 0.0755, 0.21688]),
                bx([0.0, -0.06804, 0.08502], [0.0, 0.70711, 0.70711, 0.0], [0.0062, 0.07062, 0.08239]),
                bx([0.0, -0.2094, 0.08502], [0.70711, 0.0, 0.0, -0.70711], [0.0062, 0.07062, 0.08239]),
                bx([0.0668, 0.0, 0.08677], [0.70711, 0.70711, 0.0, 0.0], [0.00403, 0.08152, 0.2098]),
                bx([-0.00156, 0.0, 0.05524], [0.70711, 0.70711, 0.0, 0.0], [0.00403, 0.04341, 0.06684]),
                bx([0.0, 0.20861, 0.04523], [0.5, 0.5, -0.5, -0.5], [0.00359, 0.0333, 0.07062]),
                bx([0.03452, 0.07058, 0.07485], [0.0, 0.70711, 0.70711, 0.0], [0.00359, 0.02992, 0.03675]),
                bx([-0.06687, 0.0, 0.03952], [0.70711, 0.70711, 0.0, 0.0], [0.00403, 0.03455, 0.2098]),
                bx([-0.06687, -0.13977, 0.08769], [0.0, 0.0, 1.0, 0.0], [0.00403, 0.07663, 0.07961]),
                bx([0.0, 0.07058, 0.09451], [0.62692, 0.32706, 0.32706, 0.62692], [0.00359, 0.02094, 0.07062]),
                bx([0.04227, 0.07058, 0.13866], [0.62756, -0.32583, 0.32583, -0.62757], [0.00359, 0.01135, 0.02792]),
                bx([0.0, 0.07073, 0.04523], [0.5, 0.5, -0.5, -0.5], [0.00359, 0.0333, 0.07062]),
                bx([0.04179, 0.20821, 0.13866], [0.62756, -0.32583, 0.32583, -0.62757], [0.00359, 0.01135, 0.02792]),
                bx([0.0, 0.20821, 0.09451], [0.32706, 0.62692, -0.62692, -0.32706], [0.00359, 0.02094, 0.07062]),
                bx([0.03452, 0.20821, 0.07485], [0.0, -0.70711, 0.70711, 0.0], [0.00359, 0.02992, 0.03675]),
                bx([0.05494, 0.20821, 0.12363], [0.70709, 0.00466, -0.00466, -0.70709], [0.00359, 0.01135, 0.01882]),
                bx([0.05494, 0.07035, 0.12363], [0.70709, 0.00466, -0.00466, -0.70709], [0.00359, 0.01135, 0.01882]),
            ],
        },
    ],
    sites: &[
        region("right_contain_region", 0, [0.00631, -0.14339, 0.06558], [0.0, 0.0, 1.0, 0.0], [0.06196, 0.06216, 0.06046]),
        region("left_contain_region", 0, [0.00631, 0.14551, 0.06558], [0.0, 0.0, 1.0, 0.0], [0.06196, 0.06216, 0.06046]),
        region("back_contain_region", 0, [0.03364, -0.00064, 0.08558], [0.0, 0.0, 1.0, 0.0], [0.02775, 0.06216, 0.06046]),
        region("front_contain_region", 0, [-0.03102, -0.00064, 0.04054], [0.0, 0.0, 0.70711, -0.70711], [0.02775, 0.03595, 0.06216]),
    ],
    bottom: [0.0, 0.0, -0.06],
    top: [0.0, 0.0, 0.04],
    horizontal_radius: 0.025,
};
