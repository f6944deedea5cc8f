//! Building a task into a physics world: the immutable [`SceneModel`].
//!
//! A scene model owns a *template* world (arena, robot (the Panda, or the PiPER of the §4.4 study), objects, fixtures) and the handles into
//! it. Every episode starts from a snapshot of the template, so handles stay valid in every
//! episode's world and a reset is a copy, not a rebuild (MuJoCo's mjModel/mjData split).

use std::sync::Arc;

use thiserror::Error;
use vifo_physics::rapier::prelude::*;
use vifo_physics::inert::INERT_CONTACT_HOOKS;
use vifo_physics::{Snapshot, World};
use vifo_robots::contact::{ARENA_GROUPS, FRAME_GROUPS, PART_GROUPS, SCENE_GROUPS};
use vifo_robots::convert::{dmat3, rapier_pose, vector};
use vifo_robots::soft::Softness;
use vifo_robots::soft_contact::FixedShape;
use vifo_robots::joint;
use vifo_robots::model::JointKind as RobotJointKind;
use vifo_robots::spatial::{Mat3, Pose, Vec3};

use crate::catalog::{self, ColliderShape, FREE_JOINT_DAMPING, JointKind, ObjectKind, ObjectModel};
use super::robot::Robot;
use crate::init_file::StateLayout;
use crate::scene_class::{SceneClass, scene_class};
use crate::task::Task;

/// Categories that are the arena itself (the support surface), not catalog objects.
pub const ARENA_CATEGORIES: [&str; 6] = ["table", "floor", "kitchen_table", "living_room_table", "study_table", "coffee_table"];

/// Why a task cannot be built into a scene.
#[derive(Debug, Error, PartialEq)]
pub enum BuildError {
    #[error("task {task}: problem class {problem} has no scene class in LIBERO-VIFO")]
    UnsupportedProblem { task: String, problem: String },
    #[error("task {task}: {entity} has category '{category}', which LIBERO-VIFO does not model (known: {known})")]
    UnknownCategory { task: String, entity: String, category: String, known: String },
    #[error("task {task}: region {region} names site '{site}', which category '{category}' does not have")]
    UnknownSite { task: String, region: String, site: String, category: String },
    #[error("task {task}: region {region} has no ranges and its target {target} is the arena")]
    RegionWithoutRange { task: String, region: String, target: String },
}

/// An object or fixture of the scene and where it lives in the world.
#[derive(Clone, Debug)]
pub struct SceneEntity {
    pub name: String,
    pub category: String,
    pub model: &'static ObjectModel,
    /// rapier body of each catalog body (`bodies[0]` is the root).
    pub bodies: Vec<RigidBodyHandle>,
    /// The multibody joint of each catalog body (`None` for the root).
    pub joints: Vec<Option<MultibodyJointHandle>>,
    /// A fixture with moving parts: the collider-less fixed body their multibody hangs from,
    /// kept at the root's pose (see [`FRAME_GROUPS`] for why the root itself is not in it).
    pub anchor: Option<RigidBodyHandle>,
    pub colliders: Vec<ColliderHandle>,
}

impl SceneEntity {
    pub fn movable(&self) -> bool {
        self.model.kind == ObjectKind::Movable
    }

    /// Catalog body index and multibody joint of the articulation joint called `name`.
    pub fn joint(&self, name: &str) -> Option<(usize, MultibodyJointHandle)> {
        self.model
            .bodies
            .iter()
            .enumerate()
            .find(|(_, b)| b.joint.as_ref().is_some_and(|j| j.name == name))
            .and_then(|(i, _)| self.joints[i].map(|h| (i, h)))
    }
}

/// Where a region's box lives.
#[derive(Clone, Debug, PartialEq)]
pub enum RegionPlace {
    /// A workspace rectangle: a fixed box in the world.
    Workspace { center: [f64; 3], half_size: [f64; 3] },
    /// A site of an entity's asset, moving with one of its bodies.
    Site { entity: usize, site: usize },
}

/// A region key resolved against the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRegion {
    pub key: String,
    pub place: RegionPlace,
}

/// Everything about a task's scene that does not change during an episode.
pub struct SceneModel {
    pub task: Task,
    pub class: &'static SceneClass,
    pub robot: Robot,
    /// Movable objects in `:objects` order, then the non-arena fixtures in `:fixtures` order,
    /// then the props the task does not name ([`SceneModel::build_with`]: a cue object).
    pub entities: Vec<SceneEntity>,
    pub regions: Vec<SceneRegion>,
    /// Colliders of the arena (table top slabs or floor).
    pub arena: Vec<ColliderHandle>,
    pub layout: StateLayout,
    pub(crate) template: Snapshot,
}

impl std::fmt::Debug for SceneModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SceneModel").field("task", &self.task.label()).field("entities", &self.entities.len()).finish()
    }
}

impl SceneModel {
    /// The entity called `name`.
    pub fn entity(&self, name: &str) -> Option<(usize, &SceneEntity)> {
        self.entities.iter().enumerate().find(|(_, e)| e.name == name)
    }

    pub fn region(&self, key: &str) -> Option<&SceneRegion> {
        self.regions.iter().find(|r| r.key == key)
    }

    /// Whether `name` is the arena (the table or floor the task calls `main_table`, `floor`, ...).
    pub fn is_arena(&self, name: &str) -> bool {
        self.task.fixture(name).is_some_and(|f| ARENA_CATEGORIES.contains(&f.category.as_str()))
    }

    /// Builds the scene of `task`. Fixtures stand at their region centres and objects at the
    /// origin until an episode places them.
    pub fn build(task: &Task) -> Result<Arc<SceneModel>, BuildError> {
        SceneModel::build_with(task, &[])
    }

    /// Like [`SceneModel::build`], with extra movable props the task does not name (a cue as a
    /// scene object, paper §4.2), each `(entity name, model)`, after the task's entities. They
    /// are not part of the task's state vectors; episodes place them.
    pub fn build_with(task: &Task, props: &[(&str, &'static ObjectModel)]) -> Result<Arc<SceneModel>, BuildError> {
        let class = scene_class(task.problem).ok_or_else(|| BuildError::UnsupportedProblem {
            task: task.label(),
            problem: task.problem.to_string(),
        })?;
        let mut world = World::new(Robot::sim_params(class.arm));
        let arena = build_arena(&mut world, class);
        let robot = Robot::insert(&mut world, class);

        let mut entities = Vec::new();
        let non_arena = task.fixtures.iter().filter(|f| !ARENA_CATEGORIES.contains(&f.category.as_str()));
        for entity in task.objects.iter().chain(non_arena) {
            let model = catalog::object(&entity.category).map_err(|_| BuildError::UnknownCategory {
                task: task.label(),
                entity: entity.name.clone(),
                category: entity.category.clone(),
                known: catalog::CATEGORIES.join(", "),
            })?;
            entities.push(insert_entity(&mut world, &entity.name, model));
        }
        for (name, model) in props {
            entities.push(insert_entity(&mut world, name, model));
        }
        let robot = robot.with_fixed(&world, &fixed_shapes(&arena, &entities));
        let regions = resolve_regions(task, class, &entities)?;
        let model = SceneModel {
            task: task.clone(),
            class,
            robot,
            entities,
            regions,
            arena,
            layout: StateLayout::for_task(task),
            template: world.snapshot(),
        };
        Ok(Arc::new(model))
    }
}

fn collider(shape: &ColliderShape) -> SharedShape {
    match *shape {
        ColliderShape::Box { half_size: h } => SharedShape::cuboid(h[0], h[1], h[2]),
        ColliderShape::Capsule { radius, half_length } => SharedShape::capsule_z(half_length, radius),
    }
}

fn scene_collider(shape: SharedShape, local: &Pose, friction: f64, groups: InteractionGroups) -> ColliderBuilder {
    ColliderBuilder::new(shape)
        .position(rapier_pose(local))
        .density(0.0)
        .friction(friction)
        .friction_combine_rule(CoefficientCombineRule::Max)
        .collision_groups(groups)
        .solver_groups(groups)
        .active_hooks(INERT_CONTACT_HOOKS)
}

/// The fixed colliders the arm's links touch with MuJoCo's soft contact: the arena (floor and table
/// keep MuJoCo's default `solref`/`solimp`) and the still bodies of fixtures with moving parts,
/// with their catalog parameters. Fixtures without moving parts share the objects' layer and stay
/// rapier's.
fn fixed_shapes(arena: &[ColliderHandle], entities: &[SceneEntity]) -> Vec<FixedShape> {
    let mut fixed: Vec<FixedShape> = arena.iter().map(|&collider| FixedShape { collider, softness: Softness::MUJOCO_DEFAULT }).collect();
    for e in entities.iter().filter(|e| e.anchor.is_some()) {
        for (&collider, c) in e.colliders.iter().zip(&e.model.bodies[0].colliders) {
            fixed.push(FixedShape { collider, softness: Softness { solref: c.solref, solimp: c.solimp, margin: c.margin } });
        }
    }
    fixed
}

/// The table top slabs (or the floor) as fixed colliders.
fn build_arena(world: &mut World, class: &SceneClass) -> Vec<ColliderHandle> {
    let r = world.rapier_mut();
    let ground = r.bodies.insert(RigidBodyBuilder::fixed());
    let mut handles = Vec::new();
    // The floor: a thick slab whose top is z = 0, wide enough for every scene.
    let floor = scene_collider(SharedShape::cuboid(4.0, 4.0, 0.1), &Pose::from_wxyz([0.0, 0.0, -0.1], [1.0, 0.0, 0.0, 0.0]), class.floor.friction[0], ARENA_GROUPS);
    handles.push(r.colliders.insert_with_parent(floor, ground, &mut r.bodies));
    if let Some(table) = &class.table {
        for slab in table.top {
            let c = scene_collider(
                SharedShape::cuboid(slab.half_size[0], slab.half_size[1], slab.half_size[2]),
                &Pose::from_wxyz(slab.center, [1.0, 0.0, 0.0, 0.0]),
                table.friction[0],
                ARENA_GROUPS,
            );
            handles.push(r.colliders.insert_with_parent(c, ground, &mut r.bodies));
        }
    }
    if let Some(riser) = &class.robot_riser {
        let [x, y, z] = riser.half_size;
        let c = scene_collider(SharedShape::cuboid(x, y, z), &Pose::from_wxyz(riser.center, [1.0, 0.0, 0.0, 0.0]), class.floor.friction[0], ARENA_GROUPS);
        handles.push(r.colliders.insert_with_parent(c, ground, &mut r.bodies));
    }
    handles
}

fn mass_properties(inertial: &catalog::Inertial) -> MassProperties {
    let r = Pose::from_wxyz([0.0; 3], inertial.quat_wxyz).rot;
    let inertia: Mat3 = r * Mat3::from_diagonal(&Vec3::from(inertial.inertia)) * r.transpose();
    MassProperties::with_inertia_matrix(vector(&Vec3::from(inertial.com)), inertial.mass, dmat3(&inertia))
}

fn insert_entity(world: &mut World, name: &str, model: &'static ObjectModel) -> SceneEntity {
    let sleep_after = world.params().sleep_after;
    let r = world.rapier_mut();
    let mut bodies: Vec<RigidBodyHandle> = Vec::with_capacity(model.bodies.len());
    let mut joints = vec![None; model.bodies.len()];
    let mut colliders = Vec::new();
    let articulated = model.kind == ObjectKind::Fixture && model.bodies.iter().any(|b| b.joint.is_some());
    let anchor = articulated.then(|| r.bodies.insert(RigidBodyBuilder::fixed()));
    for (i, body) in model.bodies.iter().enumerate() {
        let local = Pose::from_wxyz(body.pos, body.quat_wxyz);
        let builder = match (i, model.kind) {
            (0, ObjectKind::Movable) => {
                // LIBERO's free joint damping, as rapier's per-mass damping.
                let m = body.inertial.mass.max(1e-9);
                RigidBodyBuilder::dynamic().linear_damping(FREE_JOINT_DAMPING / m).angular_damping(FREE_JOINT_DAMPING / m)
            }
            (0, ObjectKind::Fixture) => RigidBodyBuilder::fixed(),
            // Articulated parts (drawers, doors, knobs) may sleep like anything else still (a
            // multibody sleeps and wakes as a whole); joint writes wake them (`Sim::set_joint`).
            _ => RigidBodyBuilder::dynamic(),
        };
        let handle = r.bodies.insert(builder.additional_mass_properties(mass_properties(&body.inertial)));
        if i == 0 && model.kind == ObjectKind::Movable {
            r.bodies[handle].activation_mut().time_until_sleep = sleep_after;
        }
        let groups = match (body.parent, anchor) {
            (Some(_), _) => PART_GROUPS,
            (None, Some(_)) => FRAME_GROUPS,
            (None, None) => SCENE_GROUPS,
        };
        for c in &body.colliders {
            let shape_pose = Pose::from_wxyz(c.pos, c.quat_wxyz);
            let builder = scene_collider(collider(&c.shape), &shape_pose, c.friction[0], groups);
            colliders.push(r.colliders.insert_with_parent(builder, handle, &mut r.bodies));
        }
        if let (Some(parent), Some(j)) = (body.parent, &body.joint) {
            let kind = match j.kind {
                JointKind::Hinge => RobotJointKind::Hinge,
                JointKind::Slide => RobotJointKind::Slide,
            };
            // The joint anchor may sit off the body origin (the microwave door hinge).
            let generic = joint::one_dof(kind, &local, &Vec3::from(j.pos), &Vec3::from(j.axis), Some(j.range));
            let parent_body = match (parent, anchor) {
                (0, Some(a)) => a,
                _ => bodies[parent],
            };
            let jh = r.multibody_joints.insert(parent_body, handle, generic, true).expect("fixtures are trees");
            let (mb, link) = r.multibody_joints.get_mut(jh).expect("fixture joint");
            let dof = mb.link(link).expect("link").assembly_id();
            mb.damping_mut()[dof] = j.damping;
            mb.armature_mut()[dof] = j.armature;
            mb.frictions_mut()[dof] = j.frictionloss;
            joints[i] = Some(jh);
        }
        bodies.push(handle);
    }
    // Settle the multibody root type so dof indices are final (see vifo_robots::arm). Parts of
    // one fixture never touch each other: MuJoCo's parent-child filter covers a drawer and its
    // cabinet, and sibling drawers stacked flush would otherwise keep dozens of resting contacts
    // alive every substep (a sixfold slowdown of every cabinet scene).
    if let Some(jh) = joints.iter().flatten().next() {
        let (mb, _) = r.multibody_joints.get_mut(*jh).expect("fixture joint");
        mb.set_self_contacts_enabled(false);
        mb.forward_kinematics(&r.bodies, true);
    }
    SceneEntity { name: name.to_string(), category: model.category.clone(), model, bodies, joints, anchor, colliders }
}

fn resolve_regions(task: &Task, class: &SceneClass, entities: &[SceneEntity]) -> Result<Vec<SceneRegion>, BuildError> {
    let mut out = Vec::new();
    for region in &task.regions {
        let place = if let Some(range) = region.ranges.first() {
            let site = class.region_site(*range);
            RegionPlace::Workspace { center: site.center, half_size: site.half_size }
        } else if let Some(e) = entities.iter().position(|e| e.name == region.target) {
            let entity = &entities[e];
            let site = entity.model.sites.iter().position(|s| s.name == region.name).ok_or_else(|| BuildError::UnknownSite {
                task: task.label(),
                region: region.key.clone(),
                site: region.name.clone(),
                category: entity.category.clone(),
            })?;
            RegionPlace::Site { entity: e, site }
        } else {
            return Err(BuildError::RegionWithoutRange { task: task.label(), region: region.key.clone(), target: region.target.clone() });
        };
        out.push(SceneRegion { key: region.key.clone(), place });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    /// The ketchup's inertia is one where glibc's `cos` and the `libm` crate's (which std uses in
    /// wasm32) round differently inside parry's eigen-solve (glamx `SymmetricEigen3`, through
    /// `MassProperties::with_inertia_matrix`): natively the two larger principal moments came out
    /// one ulp off the page's, and libero_object/4 and libero_10/7 ended with other state hashes
    /// in the browser. `vendor/glamx` routes that solve through `libm` on every target; these are
    /// the bits both give.
    #[test]
    fn ketchup_principal_inertia_is_the_same_bits_natively_and_in_wasm() {
        let model = crate::catalog::object("ketchup").unwrap();
        let inertia = super::mass_properties(&model.bodies[0].inertial).principal_inertia();
        let bits = [inertia.x.to_bits(), inertia.y.to_bits(), inertia.z.to_bits()];
        assert_eq!(bits, [4529867985220160615, 4540722888855062284, 4541076310258918697], "{inertia:?}");
    }
}
