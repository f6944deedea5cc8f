//! The compact table types the fact tables (`facts/`) are written in, and their assembly into
//! [`ObjectModel`]s: quaternions are normalised and mass properties computed as MuJoCo does.

use super::frames;
use super::inertia::{self, MassSource, MassiveGeom};
use super::model::{
    BodyModel, Collider, ColliderShape, Inertial, JointKind, JointModel, ObjectKind, ObjectModel,
    SiteModel, SiteShape, VisualPart,
};

pub(crate) const ORIGIN: [f64; 3] = [0.0; 3];
pub(crate) const IDENTITY: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

/// A category's facts as read from its asset XML (bodies already fused where jointless).
pub(crate) struct ObjectDef {
    pub category: &'static str,
    pub kind: ObjectKind,
    pub bodies: &'static [BodyDef],
    pub sites: &'static [SiteDef],
    pub bottom: [f64; 3],
    pub top: [f64; 3],
    pub horizontal_radius: f64,
}

pub(crate) struct BodyDef {
    pub name: &'static str,
    pub parent: Option<usize>,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub joint: Option<JointDef>,
    /// An explicit `<inertial>` (principal axes aligned with the body); otherwise from geoms.
    pub inertial: Option<ExplicitInertial>,
    pub geoms: &'static [GeomDef],
}

/// A limited hinge or slide; the assets leave armature and frictionloss at MuJoCo's 0.
pub(crate) struct JointDef {
    pub kind: JointKind,
    pub name: &'static str,
    pub axis: [f64; 3],
    pub pos: [f64; 3],
    pub range: [f64; 2],
    pub damping: f64,
}

pub(crate) struct ExplicitInertial {
    pub mass: f64,
    pub com: [f64; 3],
    pub diag: [f64; 3],
}

pub(crate) struct GeomDef {
    pub shape: ColliderShape,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub mass: MassSource,
    pub contact: &'static Contact,
}

/// Contact parameters shared by a group of geoms.
pub(crate) struct Contact {
    pub friction: [f64; 3],
    pub solref: [f64; 2],
    pub solimp: [f64; 5],
    pub margin: f64,
    pub contype: u32,
    pub conaffinity: u32,
    pub condim: u8,
}

pub(crate) struct SiteDef {
    pub name: &'static str,
    pub body: usize,
    pub pos: [f64; 3],
    pub quat: [f64; 4],
    pub shape: SiteShape,
    pub half_size: [f64; 3],
    pub rgba: [f32; 4],
}

/// The surface every scanned/HOPE/TurboSquid/articulated collision box in LIBERO declares.
pub(crate) const LIBERO_SURFACE: Contact = Contact {
    friction: [0.95, 0.3, 0.1],
    solref: [0.001, 1.0],
    solimp: [0.998, 0.998, 0.001, 0.5, 2.0],
    margin: 0.0,
    contype: 1,
    conaffinity: 1,
    condim: 3,
};

/// MuJoCo's geom defaults (the stove's burner boxes declare nothing).
pub(crate) const MUJOCO_DEFAULT_SURFACE: Contact = Contact {
    friction: [1.0, 0.005, 0.0001],
    solref: [0.02, 1.0],
    solimp: [0.9, 0.95, 0.001, 0.5, 2.0],
    margin: 0.0,
    contype: 1,
    conaffinity: 1,
    condim: 3,
};

/// Density of LIBERO's collision boxes (kg/m³).
pub(crate) const LIBERO_DENSITY: MassSource = MassSource::Density(100.0);

/// A collision box with LIBERO's usual surface and density.
pub(crate) const fn bx(pos: [f64; 3], quat: [f64; 4], half_size: [f64; 3]) -> GeomDef {
    GeomDef {
        shape: ColliderShape::Box { half_size },
        pos,
        quat,
        mass: LIBERO_DENSITY,
        contact: &LIBERO_SURFACE,
    }
}

/// An invisible box site.
pub(crate) const fn region(
    name: &'static str,
    body: usize,
    pos: [f64; 3],
    quat: [f64; 4],
    half_size: [f64; 3],
) -> SiteDef {
    SiteDef {
        name,
        body,
        pos,
        quat,
        shape: SiteShape::Box,
        half_size,
        rgba: [0.0; 4],
    }
}

impl ObjectDef {
    /// The public model of this category, with the given look.
    pub(crate) fn build(&self, visuals: Vec<VisualPart>) -> ObjectModel {
        ObjectModel {
            category: self.category.to_string(),
            kind: self.kind,
            bodies: self.bodies.iter().map(BodyDef::build).collect(),
            sites: self.sites.iter().map(SiteDef::build).collect(),
            bottom_offset: self.bottom,
            top_offset: self.top,
            horizontal_radius: self.horizontal_radius,
            visuals,
        }
    }
}

impl BodyDef {
    fn build(&self) -> BodyModel {
        let inertial = match &self.inertial {
            Some(e) => Inertial {
                mass: e.mass,
                com: e.com,
                inertia: e.diag,
                quat_wxyz: IDENTITY,
            },
            None => inertia::from_geoms(
                &self
                    .geoms
                    .iter()
                    .map(|g| MassiveGeom {
                        shape: &g.shape,
                        pos: g.pos,
                        quat: frames::normalize(g.quat),
                        mass: g.mass,
                    })
                    .collect::<Vec<_>>(),
            ),
        };
        BodyModel {
            name: self.name.to_string(),
            parent: self.parent,
            pos: self.pos,
            quat_wxyz: frames::normalize(self.quat),
            joint: self.joint.as_ref().map(|j| JointModel {
                kind: j.kind,
                name: j.name.to_string(),
                axis: j.axis,
                pos: j.pos,
                range: j.range,
                damping: j.damping,
                armature: 0.0,
                frictionloss: 0.0,
            }),
            inertial,
            colliders: self.geoms.iter().map(GeomDef::build).collect(),
        }
    }
}

impl GeomDef {
    fn build(&self) -> Collider {
        let c = self.contact;
        Collider {
            shape: self.shape.clone(),
            pos: self.pos,
            quat_wxyz: frames::normalize(self.quat),
            friction: c.friction,
            solref: c.solref,
            solimp: c.solimp,
            margin: c.margin,
            contype: c.contype,
            conaffinity: c.conaffinity,
            condim: c.condim,
        }
    }
}

impl SiteDef {
    fn build(&self) -> SiteModel {
        SiteModel {
            name: self.name.to_string(),
            body: self.body,
            pos: self.pos,
            quat_wxyz: frames::normalize(self.quat),
            shape: self.shape,
            half_size: self.half_size,
            rgba: self.rgba,
        }
    }
}
