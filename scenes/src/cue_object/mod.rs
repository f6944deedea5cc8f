//! Cues as scene objects (paper §4.2): text cards (F1), signs (F6) and code tags (F8) made
//! physical. Each is one rigid body with mass and collision boxes (a foot, a face panel leaning
//! back 15–20°, a post for signs), so the arm can bump, hide or move it; the cue's picture is
//! drawn on the face by whoever renders the scene ([`CueObjectKind::face`] says where).
//!
//! The object frame: origin at the bottom centre (resting on the support), `+x` the face's
//! horizontal normal (towards the viewer), `+z` up. Viewed from `+x`, `+y` is the viewer's
//! right. Placement ([`place`]) is the rule documented there.

mod place;

use std::sync::OnceLock;

use vifo_robots::spatial::{Mat3, Pose, Vec3};

use crate::catalog::ObjectModel;
use crate::catalog::spec::{BodyDef, GeomDef, IDENTITY, LIBERO_SURFACE, ObjectDef};
use crate::catalog::{ColliderShape, ObjectKind, Recipe, VisualPart};
pub use place::{CLEARANCES, Clearance, CuePlaceError, Placement, REACH, place, placement};

/// Name of the cue object's entity in a scene (one cue per episode).
pub const ENTITY_NAME: &str = "vifo_cue_object_1";

/// The physical forms a cue takes, sized like the real thing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum CueObjectKind {
    /// A long tent card for a line of text (caption bar, banner): 20 × 5 cm face.
    TextStrip,
    /// A note card (the sticky note): 12 × 10 cm face.
    Note,
    /// A sign on a short post with a weighted foot: 9 × 12 cm face, 6 cm up.
    Sign,
    /// A square code tag on a stand (QR codes, fiducials): 8 × 8 cm face.
    CodeTag,
    /// A wide code tag (barcodes): 12 × 6 cm face.
    BarcodeTag,
}

/// The numbers a kind is built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dimensions {
    /// Face width and height (m).
    pub face: [f64; 2],
    /// How far the face leans back from vertical (rad).
    pub tilt: f64,
    /// Height of the face's bottom edge above the foot (m): the post of a sign.
    pub lift: f64,
    /// Mass of the foot (kg): what keeps the object standing.
    pub foot_mass: f64,
}

/// Face panel thickness and foot plate thickness (m).
const PANEL: f64 = 0.004;
const FOOT: f64 = 0.006;
/// Mass of the face panel (kg per m² of face: 2 mm card board on a 2 mm backing).
const PANEL_AREAL_MASS: f64 = 2.4;
/// Post cross-section half side (m) and mass (kg per m).
const POST_HALF: f64 = 0.006;
const POST_MASS_PER_M: f64 = 0.4;

impl CueObjectKind {
    pub const ALL: [CueObjectKind; 5] =
        [CueObjectKind::TextStrip, CueObjectKind::Note, CueObjectKind::Sign, CueObjectKind::CodeTag, CueObjectKind::BarcodeTag];

    /// Category name of the kind's model (not one of LIBERO's categories).
    pub fn category(self) -> &'static str {
        match self {
            CueObjectKind::TextStrip => "vifo_text_strip_card",
            CueObjectKind::Note => "vifo_note_card",
            CueObjectKind::Sign => "vifo_post_sign",
            CueObjectKind::CodeTag => "vifo_code_tag",
            CueObjectKind::BarcodeTag => "vifo_barcode_tag",
        }
    }

    pub fn dimensions(self) -> Dimensions {
        let deg = |d: f64| d * std::f64::consts::PI / 180.0;
        match self {
            CueObjectKind::TextStrip => Dimensions { face: [0.20, 0.05], tilt: deg(15.0), lift: 0.0, foot_mass: 0.12 },
            CueObjectKind::Note => Dimensions { face: [0.12, 0.10], tilt: deg(15.0), lift: 0.0, foot_mass: 0.08 },
            CueObjectKind::Sign => Dimensions { face: [0.09, 0.12], tilt: deg(10.0), lift: 0.06, foot_mass: 0.30 },
            CueObjectKind::CodeTag => Dimensions { face: [0.08, 0.08], tilt: deg(20.0), lift: 0.0, foot_mass: 0.06 },
            CueObjectKind::BarcodeTag => Dimensions { face: [0.12, 0.06], tilt: deg(20.0), lift: 0.0, foot_mass: 0.06 },
        }
    }

    /// The kind's rigid body, collision boxes and plain look (foot and post dark grey, face
    /// panel paper white), built once.
    pub fn model(self) -> &'static ObjectModel {
        static MODELS: OnceLock<Vec<ObjectModel>> = OnceLock::new();
        let models = MODELS.get_or_init(|| CueObjectKind::ALL.iter().map(|k| k.build()).collect());
        &models[CueObjectKind::ALL.iter().position(|k| *k == self).expect("every kind is in ALL")]
    }

    /// Where the picture goes, in the object frame: a rectangle of the given half width and
    /// height whose frame has `+x` along the face's width (the viewer's right), `+y` up the
    /// face and `+z` out of it, half a millimetre in front of the panel.
    pub fn face(self) -> (Pose, [f64; 2]) {
        let d = self.dimensions();
        let (s, c) = (libm::sin(d.tilt), libm::cos(d.tilt));
        let normal = Vec3::new(c, 0.0, s);
        let up = Vec3::new(-s, 0.0, c);
        let centre = self.face_bottom() + up * (d.face[1] / 2.0) + normal * 0.0005;
        let rot = Mat3::from_columns(&[Vec3::y(), up, normal]);
        (Pose::new(centre, rot), [d.face[0] / 2.0, d.face[1] / 2.0])
    }

    /// Front bottom edge's midpoint of the face panel.
    fn face_bottom(self) -> Vec3 {
        let d = self.dimensions();
        Vec3::new(0.0, 0.0, FOOT + d.lift + PANEL * libm::sin(d.tilt))
    }

    /// The footprint in the object frame: centre x and half extents (x, y) of the rectangle
    /// the foot and the leaning face cover.
    pub fn footprint(self) -> (f64, [f64; 2]) {
        let (depth, width) = self.foot();
        (0.01 - depth / 2.0, [depth / 2.0, width.max(self.dimensions().face[0]) / 2.0])
    }

    /// Foot plate depth (along x, reaching behind the face) and width.
    fn foot(self) -> (f64, f64) {
        let d = self.dimensions();
        let lean = d.face[1] * libm::sin(d.tilt);
        match self {
            CueObjectKind::Sign => (0.10, 0.10),
            _ => (lean + 0.04, d.face[0] * 0.9),
        }
    }

    fn build(self) -> ObjectModel {
        let d = self.dimensions();
        let (s, c) = (libm::sin(d.tilt), libm::cos(d.tilt));
        let (depth, width) = self.foot();
        // The foot reaches 1 cm in front of the face and `depth - 1 cm` behind it.
        let foot_pos = [0.01 - depth / 2.0, 0.0, FOOT / 2.0];
        let foot_half = [depth / 2.0, width / 2.0, FOOT / 2.0];
        let up = Vec3::new(-s, 0.0, c);
        let normal = Vec3::new(c, 0.0, s);
        let panel_centre = self.face_bottom() + up * (d.face[1] / 2.0) - normal * (PANEL / 2.0);
        let panel_half = [PANEL / 2.0, d.face[0] / 2.0, d.face[1] / 2.0];
        // A rotation about y by -tilt turns x into the face normal and z into the face's up.
        let panel_quat = [libm::cos(-d.tilt / 2.0), 0.0, libm::sin(-d.tilt / 2.0), 0.0];
        let panel_mass = PANEL_AREAL_MASS * d.face[0] * d.face[1];
        let mut geoms = vec![
            geom(foot_pos, IDENTITY, foot_half, d.foot_mass),
            geom(panel_centre.into(), panel_quat, panel_half, panel_mass),
        ];
        let mut visuals = vec![
            visual(foot_pos, IDENTITY, foot_half, DARK),
            visual(panel_centre.into(), panel_quat, panel_half, PAPER),
        ];
        if d.lift > 0.0 {
            // The post stands under the face's centre line, behind the panel.
            let bottom = self.face_bottom() - normal * PANEL;
            // From the top of the foot to 1 cm up behind the panel (never below the foot).
            let length = d.lift + PANEL * s + 0.01;
            let post_pos = [bottom.x - POST_HALF, 0.0, FOOT + length / 2.0];
            let post_half = [POST_HALF, POST_HALF, length / 2.0];
            geoms.push(geom(post_pos, IDENTITY, post_half, POST_MASS_PER_M * length));
            visuals.push(visual(post_pos, IDENTITY, post_half, DARK));
        }
        let geoms: &'static [GeomDef] = Box::leak(geoms.into_boxed_slice());
        let bodies: &'static [BodyDef] = Box::leak(Box::new([BodyDef {
            name: "main",
            parent: None,
            pos: [0.0; 3],
            quat: IDENTITY,
            joint: None,
            inertial: None,
            geoms,
        }]));
        let top = d.lift + FOOT + d.face[1] * c + PANEL * s;
        let def = ObjectDef {
            category: self.category(),
            kind: ObjectKind::Movable,
            bodies,
            sites: &[],
            bottom: [0.0; 3],
            top: [0.0, 0.0, top],
            horizontal_radius: { let (_, h) = self.footprint(); (h[0] * h[0] + h[1] * h[1]).sqrt() },
        };
        def.build(visuals)
    }
}

const DARK: [f32; 4] = [0.18, 0.18, 0.2, 1.0];
const PAPER: [f32; 4] = [0.96, 0.96, 0.94, 1.0];

fn geom(pos: [f64; 3], quat: [f64; 4], half_size: [f64; 3], mass: f64) -> GeomDef {
    GeomDef {
        shape: ColliderShape::Box { half_size },
        pos,
        quat,
        mass: crate::catalog::inertia::MassSource::Mass(mass),
        contact: &LIBERO_SURFACE,
    }
}

fn visual(pos: [f64; 3], quat: [f64; 4], half: [f64; 3], rgba: [f32; 4]) -> VisualPart {
    VisualPart { body: 0, recipe: Recipe::Box { half }, pos, quat_wxyz: quat, scale: [1.0; 3], rgba }
}

#[cfg(test)]
mod tests;
