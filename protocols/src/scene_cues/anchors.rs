//! Where a cue's source and target are in the scene, and their world anchors at any state.
//!
//! A step names its source and target by goal-atom arguments (`akita_black_bowl_1`,
//! `wooden_cabinet_1_top_region`); [`resolve`] turns them into [`ScenePoint`]s once per
//! episode, and [`ScenePoint::world`] reads the current state every frame:
//!
//! * an object or fixture: the centre of its visual box (root body), with that box's extent, so
//!   rings and glows fit the object as seen;
//! * a region (`plate_right_region`, a stove's `cook_region`, a drawer's `top_region`): the
//!   centre and extent of its box at the current state (sites move with their body);
//! * the thing acted on by open/close/turn on/turn off: its moving part — a drawer's handle
//!   (so the cue sits where the drawer is pulled), a door, the stove's knob.

use vifo_cues::{CueSpec, Relation, Step, WorldAnchor};
use vifo_robots::spatial::{Mat3, Pose, Vec3};
use vifo_scenes::catalog::{Aabb, JointKind};
use vifo_scenes::sim::{RegionPlace, Sim};

use super::SceneCueError;

/// A scene thing a cue anchors on.
#[derive(Clone, Debug, PartialEq)]
pub enum ScenePoint {
    /// An object or fixture as a whole (its root body's visual box).
    Entity { entity: usize },
    /// A moving part of a fixture: a drawer (its handle), a door, a knob.
    Part { entity: usize, body: usize },
    /// A region key of the task.
    Region { key: String },
}

/// The source and target of the step a cue shows.
#[derive(Clone, Debug, PartialEq)]
pub struct CuePoints {
    pub source: ScenePoint,
    pub target: Option<ScenePoint>,
}

/// Finds the spec's step in the scene: by the step's goal-atom names when it has them (steps
/// are grounded to the goal), else by word overlap with the scene's objects, fixtures and
/// regions — for a state change only those with a moving part ("open the top drawer" when the
/// goal only says where the bowl ends up).
pub fn resolve(sim: &Sim, spec: &CueSpec) -> Result<CuePoints, SceneCueError> {
    let step: &Step = spec
        .steps
        .get(spec.step)
        .ok_or_else(|| SceneCueError::Unsupported { cue: spec.id(), why: format!("the spec has no step {}", spec.step) })?;
    let acted_on = step.relation.is_state_change();
    let source_id = match &step.source_id {
        Some(id) => id.clone(),
        None => ground(sim, spec, "source", &step.source, acted_on)?,
    };
    let source = point(sim, spec, "source", &source_id, acted_on)?;
    let target = match (&step.target, &step.target_id) {
        (None, _) => None,
        (Some(_), Some(id)) => Some(point(sim, spec, "target", id, false)?),
        (Some(phrase), None) => Some(point(sim, spec, "target", &ground(sim, spec, "target", phrase, false)?, false)?),
    };
    Ok(CuePoints { source, target })
}

/// The scene name sharing most words with `phrase`; `moving` keeps only things with a moving
/// part (jointed fixtures and the regions on their moving bodies).
fn ground(sim: &Sim, spec: &CueSpec, role: &'static str, phrase: &str, moving: bool) -> Result<String, SceneCueError> {
    let model = sim.model();
    let jointed = |entity: usize, body: usize| model.entities[entity].model.bodies[body].joint.is_some();
    let entities = model
        .entities
        .iter()
        .enumerate()
        .filter(|(i, e)| !moving || (0..e.model.bodies.len()).any(|b| jointed(*i, b)))
        .map(|(_, e)| e.name.as_str());
    let regions = model
        .regions
        .iter()
        .filter(|r| {
            !moving
                || matches!(r.place, RegionPlace::Site { entity, site } if jointed(entity, model.entities[entity].model.sites[site].body))
        })
        .map(|r| r.key.as_str());
    let names: Vec<&str> = entities.chain(regions).collect();
    let mut probe = Step { source: phrase.to_string(), source_qualifier: None, relation: Relation::PickUp, target: None, source_id: None, target_id: None };
    vifo_cues::parse::ground_to_names(std::slice::from_mut(&mut probe), &names);
    probe.source_id.ok_or_else(|| SceneCueError::Ungrounded { cue: spec.id(), role, phrase: phrase.to_string(), known: names.join(", ") })
}

/// The scene point a name stands for; `acted_on` asks for the moving part of a fixture.
fn point(sim: &Sim, spec: &CueSpec, role: &'static str, name: &str, acted_on: bool) -> Result<ScenePoint, SceneCueError> {
    let model = sim.model();
    if let Some((entity, e)) = model.entity(name) {
        let part = e.model.bodies.iter().position(|b| b.joint.is_some());
        return Ok(match part {
            Some(body) if acted_on => ScenePoint::Part { entity, body },
            _ => ScenePoint::Entity { entity },
        });
    }
    if let Some(region) = model.region(name) {
        if acted_on && let RegionPlace::Site { entity, site } = region.place {
            let body = model.entities[entity].model.sites[site].body;
            if model.entities[entity].model.bodies[body].joint.is_some() {
                return Ok(ScenePoint::Part { entity, body });
            }
        }
        return Ok(ScenePoint::Region { key: name.to_string() });
    }
    let known: Vec<&str> =
        model.entities.iter().map(|e| e.name.as_str()).chain(model.regions.iter().map(|r| r.key.as_str())).collect();
    Err(SceneCueError::UnknownEntity {
        cue: spec.id(),
        role,
        name: name.to_string(),
        task: model.task.label(),
        known: known.join(", "),
    })
}

/// A body-frame box placed in the world: centre and axis-aligned half extents.
fn world_box(pose: &Pose, center: Vec3, half: Vec3) -> WorldAnchor {
    let c = pose.transform_point(&center);
    let r: Mat3 = pose.rot.abs();
    let h = r * half;
    WorldAnchor { center: [c.x, c.y, c.z], half_extents: Some([h.x, h.y, h.z]) }
}

/// Depth (m) of a drawer's front slab: what lies this close to its outermost point along the
/// pull direction — the handle where there is one, else the front panel.
const FRONT_SLAB: f64 = 0.02;

/// The visual box of one body of an entity, in the body's frame. With `pull` (a drawer's
/// outward direction) only the front slab counts, so a ring or glow fits the handle the
/// gripper pulls rather than the whole drawer seen edge-on.
fn visual_box(sim: &Sim, entity: usize, body: usize, pull: Option<Vec3>) -> Option<Aabb> {
    let model = sim.model().entities[entity].model;
    let boxes: Vec<Aabb> = model.visuals.iter().filter(|v| v.body == body).map(|v| v.aabb()).collect();
    let Some(out) = pull else { return boxes.into_iter().reduce(|a, b| a.union(&b)) };
    // The farthest a box reaches along `out` (the maximum of out·x over its corners).
    let reach = |b: &Aabb| (0..3).map(|k| out[k] * if out[k] > 0.0 { b.max[k] } else { b.min[k] }).sum::<f64>();
    let front = boxes.iter().map(reach).fold(f64::NEG_INFINITY, f64::max);
    boxes.into_iter().filter(|b| reach(b) >= front - FRONT_SLAB).reduce(|a, b| a.union(&b))
}

fn center_half(b: &Aabb) -> (Vec3, Vec3) {
    let c = Vec3::from([0, 1, 2].map(|k| (b.min[k] + b.max[k]) / 2.0));
    let h = Vec3::from([0, 1, 2].map(|k| (b.max[k] - b.min[k]) / 2.0));
    (c, h)
}

impl ScenePoint {
    /// The world anchor at the simulation's current state.
    pub fn world(&self, sim: &Sim) -> WorldAnchor {
        match self {
            ScenePoint::Entity { entity } => self.body_anchor(sim, *entity, 0),
            ScenePoint::Part { entity, body } => self.body_anchor(sim, *entity, *body),
            ScenePoint::Region { key } => match sim.region_box(key) {
                Some(b) => world_box(&b.pose, Vec3::zeros(), b.half_size),
                // `resolve` checked the key against this scene's model.
                None => WorldAnchor { center: [f64::NAN; 3], half_extents: None },
            },
        }
    }

    fn body_anchor(&self, sim: &Sim, entity: usize, body: usize) -> WorldAnchor {
        let pose = sim.body_pose(entity, body);
        let model = sim.model().entities[entity].model;
        let joint = model.bodies[body].joint.as_ref();
        let drawer = joint.filter(|j| j.kind == JointKind::Slide && matches!(self, ScenePoint::Part { .. }));
        let pull = drawer.map(|j| {
            let axis = Vec3::from(j.axis).normalize();
            if j.range[0].abs() > j.range[1].abs() { -axis } else { axis }
        });
        let Some(b) = visual_box(sim, entity, body, pull) else {
            let p = pose.pos;
            return WorldAnchor { center: [p.x, p.y, p.z], half_extents: None };
        };
        let (center, half) = center_half(&b);
        world_box(&pose, center, half)
    }
}
