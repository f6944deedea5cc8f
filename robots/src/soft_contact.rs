//! The arm touching itself, and the scene's fixed bodies, as MuJoCo's soft contacts do.
//!
//! When the Panda's hand folds onto its forearm, MuJoCo's contact gives like a critically damped
//! spring with a 20 ms time constant (robosuite keeps the default `solref`/`solimp`): a link that
//! hits another sinks into it for several physics steps and is stopped gradually. rapier's
//! contacts stop it within a step, which left the end effector 23 mm from MuJoCo's after the hand
//! hit link 5 in the `j5_hi_j2_hi` limit sequence. So rapier never pairs a link (or the hand, or
//! the mount) with another part of the arm ([`crate::contact::groups`]), and those contacts are
//! rows of MuJoCo's soft constraint instead ([`crate::soft`]), solved with the joint limits:
//! - the pairs MuJoCo makes: different welded bodies, no parent–child pair unless one of them is
//!   welded to the world, at least one link-layer shape (fingers and pads among themselves stay
//!   rapier's, where they hold objects);
//! - the moving links and hand against the fixed scene colliders the scene hands over
//!   ([`SoftContacts::with_fixed`]: floor, table tops, the still bodies of fixtures with moving
//!   parts), each with its own `solref`/`solimp`, margin and friction: where link 6 grazed the
//!   stove's burner in the `j5_hi_j2_hi` limit sequence, MuJoCo's contact gave for one record and
//!   rapier's held for four;
//! - found at the start of each physics step on MuJoCo's shapes (each body's full hull,
//!   [`crate::model::Body::self_hull`], where rapier has a few corners or boxes), one point per
//!   pair (MuJoCo's convex–convex collision), at the midpoint of the two surfaces;
//! - with MuJoCo's elliptic friction cone (robosuite's `impratio` 20 makes the friction rows 20
//!   times stiffer than the normal one): without it the hand, once on link 5, slid along it and
//!   turned joint 7 by a quarter radian where MuJoCo's stays put;
//! - with the torsional row of the finger shells' `condim` 4, as MuJoCo's contacts have it (a
//!   finger landing on link 2 in the `fast_j2_lo_j4_lo` limit sequence: one step from MuJoCo's
//!   state 0.51 mrad off without it, 0.43 with it).

use vifo_physics::rapier::parry::bounding_volume::BoundingSphere;
use vifo_physics::rapier::parry::query;
use vifo_physics::rapier::math::Pose as RPose;
use vifo_physics::rapier::parry::shape::{Ball, Cuboid};
use vifo_physics::World;
use vifo_physics::rapier::prelude::{ColliderHandle, SharedShape};

use crate::arm::{hull, shape, shape_frame};
use crate::convert::{rapier_pose, vec3, vector};
use crate::dynamics::{ArmDynamics, BodyPoses, Jacobian};
use crate::model::{Collider, ContactRole};
use crate::soft::{Cone, Friction, Softness};
use crate::spatial::{Coords, Pose, Vec3};

/// robosuite's finger pads are stiffer than the rest (`solref="0.01 0.5"`).
const PAD: Softness = Softness { solref: [0.01, 0.5], ..Softness::MUJOCO_DEFAULT };

/// Torsional friction of a `condim` 4 contact: robosuite's finger shells (`friction="1 0.005
/// 0.0001" condim="4"`) and every other geom the arm touches keep MuJoCo's default 0.005, so
/// their mix (the larger) is 0.005.
const TORSIONAL: f64 = 0.005;

/// robosuite's ratio of frictional to normal impedance (`<option impratio="20">`).
const IMPRATIO: f64 = 20.0;

/// One contact shape, with its bounding box (in the shape's frame) to rule out pairs cheaply: a
/// hull's support map scans all its corners.
#[derive(Clone, Debug)]
struct Geom {
    on: On,
    shape: SharedShape,
    bound: BoundingSphere,
    /// The sphere's centre in the frame that poses the shape (the arm body's, or the scene
    /// collider's own).
    centre: Vec3,
    box_centre: Vec3,
    box_shape: Cuboid,
    softness: Softness,
    friction: Friction,
}

/// What a shape is fixed to.
#[derive(Clone, Copy, Debug, PartialEq)]
enum On {
    /// An arm body, at this pose in the body's frame.
    Arm(usize, Pose),
    /// A fixed collider of the scene, posed by the world (fixtures are placed per episode).
    Scene(ColliderHandle),
}

impl Geom {
    fn new(on: On, shape: SharedShape, softness: Softness, friction: Friction) -> Geom {
        let aabb = shape.compute_local_aabb();
        let bound = shape.compute_local_bounding_sphere();
        let centre = match on {
            On::Arm(_, local) => local.transform_point(&vec3(bound.center)),
            On::Scene(_) => vec3(bound.center),
        };
        Geom {
            on,
            bound,
            centre,
            box_centre: vec3(aabb.center()),
            box_shape: Cuboid::new(aabb.half_extents()),
            shape,
            softness,
            friction,
        }
    }

    fn body(&self) -> Option<usize> {
        match self.on {
            On::Arm(b, _) => Some(b),
            On::Scene(_) => None,
        }
    }
}

/// A fixed collider of the scene the arm's links touch softly, with MuJoCo's parameters.
#[derive(Clone, Copy, Debug)]
pub struct FixedShape {
    pub collider: ColliderHandle,
    pub softness: Softness,
}

/// A pair of shapes that may touch, with their mixed softness and friction (the larger of
/// each, and the torsional row where either shape has `condim` 4).
#[derive(Clone, Debug)]
struct Pair {
    geoms: [usize; 2],
    softness: Softness,
    friction: Friction,
}

impl Pair {
    fn of(geoms: &[Geom], i: usize, j: usize) -> Pair {
        let (a, b) = (geoms[i].friction, geoms[j].friction);
        let spin = a.spin.or(b.spin).map(|_| a.spin.unwrap_or(TORSIONAL).max(b.spin.unwrap_or(TORSIONAL)));
        Pair { geoms: [i, j], softness: geoms[i].softness.mixed(&geoms[j].softness), friction: Friction { slide: a.slide.max(b.slide), spin } }
    }
}

/// One contact point between two bodies of the arm, or one and the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoftContact {
    /// Arm bodies; `None`: the scene.
    pub bodies: [Option<usize>; 2],
    /// Midpoint of the two surfaces (world).
    pub pos: Vec3,
    /// From the first body towards the second.
    pub normal: Vec3,
    /// Negative when the shapes overlap.
    pub dist: f64,
}

/// The arm's soft-contact pairs and MuJoCo's per-body weights for their rows.
#[derive(Clone, Debug, Default)]
pub struct SoftContacts {
    geoms: Vec<Geom>,
    /// The arm geoms that touch the fixed scene: link-layer shapes on moving bodies.
    moving_links: Vec<usize>,
    pairs: Vec<Pair>,
    /// Translational inverse weight of each body at `q = 0` (MuJoCo's `body_invweight0[0]`).
    invweight0: Vec<f64>,
}

impl SoftContacts {
    /// The pairs of `dynamics`' model; none unless the model has [`crate::model::ArmModel::self_contact`].
    pub fn new<const N: usize>(dynamics: &ArmDynamics<N>) -> Self {
        let model = dynamics.model();
        if !model.self_contact {
            return SoftContacts::default();
        }
        // The body each body is welded to (`None`: the world, through the fixed base).
        let mut weld: Vec<Option<usize>> = Vec::with_capacity(model.bodies.len());
        for (b, body) in model.bodies.iter().enumerate() {
            weld.push(match (&body.joint, body.parent) {
                (Some(_), _) => Some(b),
                (None, Some(p)) => weld[p],
                (None, None) => None,
            });
        }
        let weld_parent = |w: usize| model.bodies[w].parent.and_then(|p| weld[p]);
        let softness = |role: ContactRole| if role == ContactRole::Pad { PAD } else { Softness::MUJOCO_DEFAULT };
        let friction = |c: &Collider| Friction { slide: c.friction, spin: (c.role == ContactRole::Finger).then_some(TORSIONAL) };
        let (mut geoms, mut roles) = (Vec::new(), Vec::new());
        for (b, body) in model.bodies.iter().enumerate() {
            let mut add = |shape: SharedShape, local: Pose, c: &Collider| {
                geoms.push(Geom::new(On::Arm(b, local), shape, softness(c.role), friction(c)));
                roles.push(c.role);
            };
            // MuJoCo's hull where the body has one (rapier's few corners lie 1-2.5 mm inside it,
            // and with them the hand met link 5 a step later than MuJoCo's did), with the role and
            // friction of the body's colliders.
            match (body.self_hull, body.colliders.first()) {
                (Some(points), Some(c)) => add(hull(points), Pose::IDENTITY, c),
                _ => body.colliders.iter().for_each(|c| add(shape(&c.shape), shape_frame(&c.shape, &c.local), c)),
            }
        }
        let weld_of = |g: &Geom| g.body().and_then(|b| weld[b]);
        let mut pairs = Vec::new();
        for i in 0..geoms.len() {
            for j in i + 1..geoms.len() {
                let (w1, w2) = (weld_of(&geoms[i]), weld_of(&geoms[j]));
                let parent_child = match (w1, w2) {
                    (Some(a), Some(b)) => weld_parent(a) == Some(b) || weld_parent(b) == Some(a),
                    _ => false,
                };
                let rapiers = roles[i] != ContactRole::Link && roles[j] != ContactRole::Link;
                if w1 != w2 && !parent_child && !rapiers {
                    pairs.push(Pair::of(&geoms, i, j));
                }
            }
        }
        let moving_links = (0..geoms.len()).filter(|&i| roles[i] == ContactRole::Link && weld_of(&geoms[i]).is_some()).collect();
        SoftContacts { geoms, moving_links, pairs, invweight0: translational_invweight0(dynamics) }
    }

    /// Adds pairs of the arm's moving links and hand with the `fixed` colliders of `world`'s scene
    /// (none for an arm without soft contacts).
    pub fn with_fixed(mut self, world: &World, fixed: &[FixedShape]) -> Self {
        for f in fixed {
            let shape = world.rapier().colliders[f.collider].shared_shape().clone();
            let friction = Friction { slide: world.rapier().colliders[f.collider].friction(), spin: None };
            self.geoms.push(Geom::new(On::Scene(f.collider), shape, f.softness, friction));
            let j = self.geoms.len() - 1;
            for &i in &self.moving_links {
                self.pairs.push(Pair::of(&self.geoms, i, j));
            }
        }
        self
    }

    /// The bodies of every pair, by name (`scene` for the fixed scene; for tests and reports).
    pub fn pair_bodies<'a, const N: usize>(&self, dynamics: &'a ArmDynamics<N>) -> Vec<[&'a str; 2]> {
        let name = |g: usize| self.geoms[g].body().map_or("scene", |b| dynamics.model().bodies[b].name);
        self.pairs.iter().map(|p| [name(p.geoms[0]), name(p.geoms[1])]).collect()
    }

    /// MuJoCo's `body_invweight0[0]` of each body.
    pub fn invweight0(&self) -> &[f64] {
        &self.invweight0
    }

    /// The contacts at `poses` in `world`, with each pair's softness.
    fn contacts(&self, poses: &BodyPoses, world: &World) -> Vec<(SoftContact, &Pair)> {
        let colliders = &world.rapier().colliders;
        // Bounding-sphere centres first: most pairs end there, before any pose is composed.
        let centres: Vec<Vec3> = self
            .geoms
            .iter()
            .map(|g| match g.on {
                On::Arm(b, _) => poses.poses[b].transform_point(&g.centre),
                On::Scene(h) => vec3(colliders[h].position().transform_point(vector(&g.centre))),
            })
            .collect();
        // Full poses only for shapes whose spheres meet another's, each composed once.
        let mut placed: Vec<Option<RPose>> = vec![None; self.geoms.len()];
        let mut place = |g: usize| {
            *placed[g].get_or_insert_with(|| match self.geoms[g].on {
                On::Arm(b, local) => rapier_pose(&poses.poses[b].mul(&local)),
                On::Scene(h) => *colliders[h].position(),
            })
        };
        // One sphere around the moving links rules out most of the scene's shapes at once.
        let links = &self.moving_links;
        let middle = links.iter().fold(Vec3::zeros(), |sum, &i| sum + centres[i]) / links.len().max(1) as f64;
        let span = links.iter().fold(0.0f64, |r, &i| r.max((centres[i] - middle).norm() + self.geoms[i].bound.radius));
        let near: Vec<bool> = self
            .geoms
            .iter()
            .zip(&centres)
            .map(|(g, c)| matches!(g.on, On::Arm(..)) || (c - middle).norm() <= span + g.bound.radius + g.softness.margin)
            .collect();
        let mut found = Vec::new();
        for pair in self.pairs.iter().filter(|p| near[p.geoms[1]]) {
            let [i, j] = pair.geoms;
            let (gi, gj) = (&self.geoms[i], &self.geoms[j]);
            let margin = pair.softness.margin;
            let reach = gi.bound.radius + gj.bound.radius + margin;
            if (centres[i] - centres[j]).norm_squared() > reach * reach {
                continue;
            }
            let pj = place(j);
            let apart = match gj.on {
                // A scene shape (a box or capsule) against the arm shape's sphere: cheap and tight
                // for the table tops, whose own spheres hold the whole arm.
                On::Scene(_) => {
                    let ball = Ball::new(gi.bound.radius + margin);
                    !query::intersection_test(&RPose::from_translation(vector(&centres[i])), &ball, &pj, &*gj.shape).expect("convex").intersecting
                }
                On::Arm(..) => {
                    let pi = place(i);
                    let boxed = |p: &RPose, g: &Geom| *p * RPose::from_translation(vector(&g.box_centre));
                    margin == 0.0 && !query::intersection_test(&boxed(&pi, gi), &gi.box_shape, &boxed(&pj, gj), &gj.box_shape).expect("boxes").intersecting
                }
            };
            if apart {
                continue;
            }
            let pi = place(i);
            let contact = query::contact(&pi, &*gi.shape, &pj, &*gj.shape, margin);
            if let Some(c) = contact.expect("the arm's and the scene's shapes are convex").filter(|c| c.dist < margin) {
                let contact = SoftContact {
                    bodies: [gi.body(), gj.body()],
                    pos: (vec3(c.point1) + vec3(c.point2)) * 0.5,
                    normal: vec3(c.normal1),
                    dist: c.dist,
                };
                found.push((contact, pair));
            }
        }
        found
    }

    /// The contacts at `poses` in `world` (world frame).
    pub fn at(&self, poses: &BodyPoses, world: &World) -> Vec<SoftContact> {
        self.contacts(poses, world).into_iter().map(|(c, _)| c).collect()
    }

    /// Adds a cone for each contact at `poses` in `world`, moving at `qd`, for its physics step.
    pub fn cones<const N: usize>(&self, dynamics: &ArmDynamics<N>, poses: &BodyPoses, qd: &Coords<N>, world: &World, cones: &mut Vec<Cone<N>>) {
        if self.pairs.is_empty() {
            return;
        }
        let dt = world.params().dt;
        for (c, pair) in self.contacts(poses, world) {
            let moves = |b: Option<usize>| b.map_or(Jacobian::<N>::zeros(), |b| dynamics.point_jacobian(poses, b, &c.pos));
            let relative = moves(c.bodies[1]) - moves(c.bodies[0]);
            let along = |d: &Vec3, rows: usize| -> Coords<N> { (d.transpose() * relative.fixed_rows::<3>(rows)).transpose() };
            let [t1, t2] = tangents(&c.normal);
            let spin = if pair.friction.spin.is_some() { along(&c.normal, 3) } else { Coords::<N>::zeros() };
            let weight: f64 = c.bodies.iter().flatten().map(|&b| self.invweight0[b]).sum();
            cones.push(pair.softness.cone(along(&c.normal, 0), [along(&t1, 0), along(&t2, 0)], spin, c.dist, qd, weight, pair.friction, IMPRATIO, dt));
        }
    }
}

/// MuJoCo's tangent frame for a contact normal (`mju_makeFrame`): the first tangent from +y, or
/// +z where the normal is close to y.
fn tangents(normal: &Vec3) -> [Vec3; 2] {
    let seed = if normal.y.abs() < 0.5 { Vec3::y() } else { Vec3::z() };
    let t1 = (seed - normal * normal.dot(&seed)).normalize();
    [t1, normal.cross(&t1)]
}

/// MuJoCo's `body_invweight0[0]`: a third of the trace of `Jp M⁻¹ Jpᵀ` at the body's centre of
/// mass, at `q = 0`; zero for bodies welded to the world.
fn translational_invweight0<const N: usize>(dynamics: &ArmDynamics<N>) -> Vec<f64> {
    let poses = dynamics.forward(&Pose::IDENTITY, &Coords::<N>::zeros());
    let inverse = dynamics.mass_matrix(&poses).cholesky().expect("an arm's mass matrix is positive definite").inverse();
    (0..dynamics.model().bodies.len())
        .map(|b| {
            let com = poses.poses[b].transform_point(&dynamics.model().bodies[b].inertial.com);
            let jp = dynamics.point_jacobian(&poses, b, &com).fixed_rows::<3>(0).into_owned();
            (jp * inverse * jp.transpose()).trace() / 3.0
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panda::{self, Mount};

    fn panda() -> (ArmDynamics<9>, SoftContacts) {
        let dynamics = ArmDynamics::<9>::new(panda::model(Mount::Pedestal), [0.0, 0.0, -9.81]);
        let contacts = SoftContacts::new(&dynamics);
        (dynamics, contacts)
    }

    /// MuJoCo 2.3.7's `body_invweight0[0]` of robosuite's Panda in a LIBERO scene.
    #[test]
    fn invweight0_matches_mujoco() {
        let (dynamics, contacts) = panda();
        let golden = [
            ("link0", 0.0),
            ("link1", 0.0),
            ("link2", 0.000679260),
            ("link3", 0.005179869),
            ("link4", 0.008725314),
            ("link5", 0.019499194),
            ("link6", 0.036972590),
            ("right_gripper", 0.039045809),
            ("leftfinger", 0.331239769),
            ("finger1_tip", 0.332143782),
        ];
        for (name, g) in golden {
            let b = dynamics.model().body_index(name).unwrap();
            assert!((contacts.invweight0()[b] - g).abs() < 2e-6, "{name}: {} against MuJoCo's {g}", contacts.invweight0()[b]);
        }
    }

    /// MuJoCo pairs link 0 with link 1 (link 0 is welded to the world, so the parent filter does
    /// not apply), link 2 with the fingers, the hand with link 5, the mount with the links; never
    /// a link with its parent or the two finger shells.
    #[test]
    fn the_pairs_are_mujocos() {
        let (dynamics, contacts) = panda();
        let pairs = contacts.pair_bodies(&dynamics);
        let has = |a: &str, b: &str| pairs.iter().any(|p| (p[0] == a && p[1] == b) || (p[0] == b && p[1] == a));
        for (a, b) in [("link0", "link1"), ("link2", "leftfinger"), ("link2", "finger2_tip"), ("right_gripper", "link5"), ("base", "link1"), ("base", "rightfinger")] {
            assert!(has(a, b), "{a}-{b} missing");
        }
        for (a, b) in [("link1", "link2"), ("link5", "link6"), ("link6", "right_gripper"), ("leftfinger", "rightfinger"), ("base", "link0"), ("finger1_tip", "finger2_tip")] {
            assert!(!has(a, b), "{a}-{b} paired");
        }
    }
}
