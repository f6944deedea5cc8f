//! [`SceneView`]: a task's render scene, built once per [`SceneModel`] and posed per frame.

use vifo_render::glam::{Mat3, Vec3};
use std::sync::Arc;

use vifo_render::{Frame, Instance, Material, Mesh, RenderError, Renderer, Scene, Transform};
use vifo_render::{Background, Camera, Headlight, Light, Mirror};
use vifo_robots::model::Shape;
use vifo_robots::spatial::Pose;

use super::arena::{ArenaPiece, ArenaTextures, arena};
use super::cameras::ImageOrder;
use super::material::textured;
use super::meshes::MeshCache;
use crate::catalog::{Recipe, SiteShape};
use crate::look::{Lods, Look, lod_step};
use crate::scene_class::SceneClass;
use crate::sim::{SceneModel, Sim};
use crate::task::{Atom, Predicate, ProblemClass};

/// What a segmentation id stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegmentKind {
    /// A movable object of the task.
    Object,
    /// A fixture of the task (cabinet, stove, ...).
    Fixture,
    /// One body of the robot (link, hand, finger); the pedestal belongs to the base.
    RobotLink,
    /// Floor, table or walls.
    Arena,
}

/// One entry of the segmentation legend.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Segment {
    /// The id written into [`Frame::segmentation`] (0 is the background).
    pub id: u32,
    /// Entity name as the task names it (`akita_black_bowl_1`), `robot0_<body>` for robot bodies,
    /// or `floor`, the workspace name (`main_table`) and `walls` for the arena.
    pub name: String,
    pub kind: SegmentKind,
}

/// Where an instance's transform comes from each frame.
#[derive(Clone, Debug)]
enum Anchor {
    /// Fixed in the world.
    Static,
    /// Body `body` of entity `entity`, at `local` in that body's frame (scaled by `scale`).
    Entity { entity: usize, body: usize, local: Pose, scale: [f64; 3] },
    /// Body `body` of the robot.
    Robot { body: usize, local: Pose, scale: [f64; 3] },
}

/// An instance shown only while an atom holds: the stove's red burner while it is turned on.
#[derive(Clone, Debug)]
struct Indicator {
    when: Atom,
    instance: Instance,
    anchor: Anchor,
}

/// A task's scene for the renderer: meshes built once (shared by `Arc`), transforms updated from
/// a [`Sim`] each frame.
#[derive(Clone, Debug)]
pub struct SceneView {
    scene: Scene,
    /// Anchor of each always-shown instance (`scene.instances[..anchors.len()]`).
    anchors: Vec<Anchor>,
    /// Coarser meshes of each always-shown instance; empty when no instance has any (the
    /// built-in look), so those scenes are drawn as they are.
    lods: Vec<Lods>,
    indicators: Vec<Indicator>,
    legend: Vec<Segment>,
    class: &'static SceneClass,
    /// What results record as the look ([`Look::label`], or `built-in`).
    look: String,
}

/// A coarser mesh is drawn where its own simplification step ([`lod_step`]) is at most this
/// many of the camera's pixels at the instance's depth.
const LOD_STEP_PIXELS: f32 = 0.5;

/// Objects and fixtures: LIBERO's assets are textured with MuJoCo's default material.
fn object_material(rgba: [f32; 4]) -> Material {
    let default = Material::default();
    textured(rgba, default.specular, default.shininess)
}

/// Surface finish of the robot (robosuite's Panda materials are glossy).
fn robot_material(rgba: [f32; 4]) -> Material {
    Material { rgba, specular: 0.5, shininess: 0.3, ..Material::default() }
}

fn recipe_of(shape: &Shape) -> Recipe {
    match *shape {
        Shape::Box { half } => Recipe::Box { half },
        Shape::Capsule { radius, half_height } => Recipe::Capsule { radius, half_height },
        Shape::Cylinder { radius, half_height } => Recipe::Cylinder { radius, half_height },
        Shape::Sphere { radius } => Recipe::Sphere { radius },
    }
}

/// `pose` with the part's stretch along its local axes, in the renderer's `f32`.
fn transform(pose: &Pose, scale: [f64; 3]) -> Transform {
    let r = &pose.rot;
    let col = |c: usize| Vec3::new((r[(0, c)] * scale[c]) as f32, (r[(1, c)] * scale[c]) as f32, (r[(2, c)] * scale[c]) as f32);
    Transform::from_pos_mat3(Vec3::new(pose.pos.x as f32, pose.pos.y as f32, pose.pos.z as f32), Mat3::from_cols(col(0), col(1), col(2)))
}

fn light(l: &crate::scene_class::Light) -> Light {
    let v = |a: [f64; 3]| Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    let base = if l.directional { Light::mujoco_directional(v(l.dir)) } else { Light::mujoco_spot(v(l.pos), v(l.dir)) };
    let f = |a: [f64; 3]| a.map(|x| x as f32);
    Light { diffuse: f(l.diffuse), specular: f(l.specular), cast_shadow: false, ..base }
}

/// Builds the legend and instance list in a fixed order: entities, robot bodies, arena.
struct Builder {
    meshes: MeshCache,
    instances: Vec<Instance>,
    anchors: Vec<Anchor>,
    lods: Vec<Lods>,
    legend: Vec<Segment>,
}

impl Builder {
    fn segment(&mut self, name: String, kind: SegmentKind) -> u32 {
        let id = self.legend.len() as u32 + 1;
        self.legend.push(Segment { id, name, kind });
        id
    }

    fn push(&mut self, recipe: &Recipe, material: Material, segment: u32, anchor: Anchor) {
        let mesh = self.meshes.get(recipe);
        self.push_mesh(mesh, Lods::from([]), material, segment, anchor);
    }

    fn push_mesh(&mut self, mesh: Arc<Mesh>, lods: Lods, material: Material, segment: u32, anchor: Anchor) {
        self.instances.push(Instance { mesh, material, transform: Transform::IDENTITY, segment });
        self.anchors.push(anchor);
        self.lods.push(lods);
    }
}

impl SceneView {
    /// The render scene of `model`: every object's and fixture's procedural look, the robot's
    /// body shapes, the arena, the scene class's lights and MuJoCo's headlight. Transforms are
    /// placeholders until [`SceneView::update`].
    pub fn new(model: &SceneModel) -> SceneView {
        SceneView::with_look(model, None)
    }

    /// Like [`SceneView::new`], drawing each object and fixture whose category `look` has from
    /// LIBERO's meshes and materials (the others keep the built-in look).
    pub fn with_look(model: &SceneModel, look: Option<&Look>) -> SceneView {
        let mut b = Builder { meshes: MeshCache::default(), instances: Vec::new(), anchors: Vec::new(), lods: Vec::new(), legend: Vec::new() };
        let mut indicators = Vec::new();
        // MuJoCo draws only the first reflective geom as a mirror.
        let mut mirror = None;
        for (entity, e) in model.entities.iter().enumerate() {
            let kind = if e.movable() { SegmentKind::Object } else { SegmentKind::Fixture };
            let segment = b.segment(e.name.clone(), kind);
            if let Some(parts) = look.and_then(|l| l.parts(&e.model.category)) {
                for part in parts {
                    // Fact bodies are catalog bodies (tested); a part on an unknown body is skipped.
                    let Some(body) = e.model.bodies.iter().position(|b| b.name == part.body) else { continue };
                    let anchor = Anchor::Entity { entity, body, local: Pose::from_wxyz(part.pos, part.quat_wxyz), scale: part.scale };
                    if let (None, Some(face)) = (&mirror, part.mirror) {
                        mirror = Some(Mirror { instance: b.instances.len(), face_z: face.height, reflectance: face.reflectance });
                    }
                    b.push_mesh(part.mesh.clone(), part.lods.clone(), part.material.clone(), segment, anchor);
                }
            } else {
                for part in &e.model.visuals {
                    let local = Pose::from_wxyz(part.pos, part.quat_wxyz);
                    let anchor = Anchor::Entity { entity, body: part.body, local, scale: part.scale };
                    b.push(&part.recipe, object_material(part.rgba), segment, anchor);
                }
            }
            // Sites LIBERO draws only in a state: the stove's burner glows red while it is on.
            for site in e.model.sites.iter().filter(|s| s.name == "burner" && s.rgba[3] > 0.0) {
                let [r, _, h] = site.half_size;
                let recipe = match site.shape {
                    SiteShape::Cylinder => Recipe::Cylinder { radius: r, half_height: h },
                    SiteShape::Box => Recipe::Box { half: site.half_size },
                };
                let instance = Instance { mesh: b.meshes.get(&recipe), material: object_material(site.rgba), transform: Transform::IDENTITY, segment };
                let anchor = Anchor::Entity { entity, body: site.body, local: Pose::from_wxyz(site.pos, site.quat_wxyz), scale: [1.0; 3] };
                let when = Atom { predicate: Predicate::TurnOn, args: vec![e.name.clone()] };
                indicators.push(Indicator { when, instance, anchor });
            }
        }
        let arm = model.robot.model().name;
        for (body, spec) in model.robot.model().bodies.iter().enumerate() {
            // A base with shapes of its own stands on a pedestal; an unmounted one draws nothing.
            let parts = look.and_then(|l| l.robot_parts(arm, spec.name, !spec.visuals.is_empty()));
            if spec.visuals.is_empty() && parts.is_none() {
                continue;
            }
            let segment = b.segment(format!("robot0_{}", spec.name), SegmentKind::RobotLink);
            if let Some(parts) = parts {
                for part in parts {
                    let anchor = Anchor::Robot { body, local: Pose::from_wxyz(part.pos, part.quat_wxyz), scale: part.scale };
                    b.push_mesh(part.mesh.clone(), part.lods.clone(), part.material.clone(), segment, anchor);
                }
                continue;
            }
            for v in &spec.visuals {
                b.push(&recipe_of(&v.shape), robot_material(v.rgba), segment, Anchor::Robot { body, local: v.local, scale: [1.0; 3] });
            }
        }
        let class = model.class;
        let mut arena_segments: Vec<(ArenaPiece, u32)> = Vec::new();
        let texture = |file: Option<&str>| look.and_then(|l| l.arena_texture(file?)).cloned();
        let textures = ArenaTextures {
            floor: texture(Some(class.floor.texture)),
            table: texture(class.table.and_then(|t| t.texture)),
            walls: texture(Some(class.wall_texture)),
        };
        let mut parts = arena(class, &mut b.meshes, &textures);
        let decor = look.and_then(|l| l.decor(class.problem));
        if decor.is_some() && matches!(class.problem, ProblemClass::LivingRoomTabletop | ProblemClass::StudyTabletop) {
            // The decor holds these tables' own meshes; the boxes standing in for them would
            // cover their textured tops.
            parts.retain(|p| p.piece != ArenaPiece::Table);
        }
        for part in parts {
            let segment = match arena_segments.iter().find(|(p, _)| *p == part.piece) {
                Some(&(_, id)) => id,
                None => {
                    let name = match part.piece {
                        ArenaPiece::Floor => "floor",
                        ArenaPiece::Table => class.workspace,
                        ArenaPiece::Walls => "walls",
                        ArenaPiece::Riser => "riser",
                    };
                    let id = b.segment(name.to_string(), SegmentKind::Arena);
                    arena_segments.push((part.piece, id));
                    id
                }
            };
            b.instances.push(Instance { mesh: part.mesh, material: part.material, transform: part.transform, segment });
            b.anchors.push(Anchor::Static);
            b.lods.push(Lods::from([]));
        }
        if let Some(decor) = decor {
            let segment = b.segment("decor".to_string(), SegmentKind::Arena);
            for part in decor {
                let pose = Pose::from_wxyz(part.pos, part.quat_wxyz);
                b.instances.push(Instance { mesh: part.mesh.clone(), material: part.material.clone(), transform: transform(&pose, part.scale), segment });
                b.anchors.push(Anchor::Static);
                b.lods.push(part.lods.clone());
            }
        }
        let scene = Scene {
            instances: b.instances,
            lights: class.lights.iter().map(light).collect(),
            headlight: Headlight::default(),
            // LIBERO's gradient skybox (rgb1 0.9 0.9 1, rgb2 0.2 0.3 0.4); walls hide most of it.
            background: Background::Gradient { up: [0.9, 0.9, 1.0], down: [0.2, 0.3, 0.4] },
            mirror,
        };
        let lods = if b.lods.iter().any(|l| !l.is_empty()) { b.lods } else { Vec::new() };
        let look = look.map_or_else(|| crate::look::BUILT_IN.to_string(), Look::label);
        SceneView { scene, anchors: b.anchors, lods, indicators, legend: b.legend, class, look }
    }

    /// Adds a mesh drawn on body `body` of entity `entity` at `local` (in that body's frame),
    /// with the entity's segmentation id: the picture on a cue object's face.
    pub fn attach(&mut self, entity: usize, body: usize, local: Pose, mesh: Arc<Mesh>, material: Material, segment: u32) {
        let at = self.anchors.len();
        self.scene.instances.insert(at, Instance { mesh, material, transform: Transform::IDENTITY, segment });
        self.anchors.push(Anchor::Entity { entity, body, local, scale: [1.0; 3] });
        if !self.lods.is_empty() {
            self.lods.push(Lods::from([]));
        }
    }

    /// Poses every instance as `sim` has its bodies, and shows the indicators whose condition
    /// holds.
    pub fn update(&mut self, sim: &Sim) {
        let robot = sim.model().robot.body_poses(sim.world());
        let place = |anchor: &Anchor| -> Option<Transform> {
            match anchor {
                Anchor::Static => None,
                Anchor::Entity { entity, body, local, scale } => Some(transform(&sim.body_pose(*entity, *body).mul(local), *scale)),
                Anchor::Robot { body, local, scale } => Some(transform(&robot.poses[*body].mul(local), *scale)),
            }
        };
        let shown = self.anchors.len();
        for (instance, anchor) in self.scene.instances[..shown].iter_mut().zip(&self.anchors) {
            if let Some(t) = place(anchor) {
                instance.transform = t;
            }
        }
        self.scene.instances.truncate(shown);
        for ind in &self.indicators {
            if sim.holds(&ind.when) == Ok(true) {
                let mut instance = ind.instance.clone();
                instance.transform = place(&ind.anchor).unwrap_or(instance.transform);
                self.scene.instances.push(instance);
            }
        }
    }

    /// One entity alone, as if its root body stood at `root` (its other bodies keep their pose
    /// relative to the root in `sim`), lit like the scene, on an empty background (segment 0):
    /// for drawing an object where it is not, e.g. the future poses of a ghost trajectory.
    pub fn entity_scene(&self, sim: &Sim, entity: usize, root: &Pose) -> Scene {
        let to_root = sim.entity_pose(entity).inverse();
        let instances = self
            .scene
            .instances
            .iter()
            .zip(&self.anchors)
            .filter_map(|(instance, anchor)| match anchor {
                Anchor::Entity { entity: e, body, local, scale } if *e == entity => {
                    let relative = to_root.mul(&sim.body_pose(entity, *body));
                    Some(Instance { transform: transform(&root.mul(&relative).mul(local), *scale), ..instance.clone() })
                }
                _ => None,
            })
            .collect();
        Scene { instances, lights: self.scene.lights.clone(), headlight: self.scene.headlight, background: Background::Solid([0.0; 3]), mirror: None }
    }

    /// The scene as of the last [`SceneView::update`].
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene class the view was built for.
    /// The look it draws: [`Look::label`] of the look it was made with, or `built-in`.
    pub fn look(&self) -> &str {
        &self.look
    }

    pub fn class(&self) -> &'static SceneClass {
        self.class
    }

    /// Every segmentation id and what it stands for, in id order (ids start at 1).
    pub fn legend(&self) -> &[Segment] {
        &self.legend
    }

    /// The segmentation id of an entity, robot body (`robot0_<body>`) or arena piece.
    pub fn segment_of(&self, name: &str) -> Option<u32> {
        self.legend.iter().find(|s| s.name == name).map(|s| s.id)
    }

    /// Triangles of every instance currently in the scene (in view or not).
    pub fn triangle_count(&self) -> usize {
        self.scene.instances.iter().map(|i| i.mesh.triangle_count()).sum()
    }

    /// Renders the current scene with `camera`, rows in `order`.
    pub fn render(&self, renderer: &mut Renderer, camera: &Camera, order: ImageOrder) -> Result<Frame, RenderError> {
        let mut frame = Frame::default();
        self.render_into(renderer, camera, order, &mut frame)?;
        Ok(frame)
    }

    /// Like [`SceneView::render`], reusing `frame`'s memory.
    pub fn render_into(&self, renderer: &mut Renderer, camera: &Camera, order: ImageOrder, frame: &mut Frame) -> Result<(), RenderError> {
        match self.for_camera(camera) {
            Some(scene) => renderer.render_into(&scene, camera, frame)?,
            None => renderer.render_into(&self.scene, camera, frame)?,
        }
        order.apply(frame);
        Ok(())
    }

    /// The scene with each instance's coarsest mesh whose step is within [`LOD_STEP_PIXELS`]
    /// pixels at the instance's depth in `camera`; `None` when no instance has coarser meshes.
    fn for_camera(&self, camera: &Camera) -> Option<Scene> {
        if self.lods.is_empty() {
            return None;
        }
        let metres_per_pixel_at_1m = 2.0 * libm::tanf(camera.fovy_deg.to_radians() / 2.0) / camera.height as f32;
        let mut scene = self.scene.clone();
        for (instance, lods) in scene.instances.iter_mut().zip(&self.lods) {
            let centre = instance.transform.transform_point(instance.mesh.bounds().center);
            let pixel = (centre - camera.position).dot(camera.forward()) * metres_per_pixel_at_1m;
            if let Some(mesh) = coarsest(lods, pixel) {
                instance.mesh = mesh.clone();
            }
        }
        Some(scene)
    }
}

/// The coarsest of `lods` (finest first) to draw where a pixel is `pixel` metres wide: the last
/// whose step is within [`LOD_STEP_PIXELS`] of it.
fn coarsest(lods: &Lods, pixel: f32) -> Option<&Arc<Mesh>> {
    lods.iter().take_while(|(made_for, _)| lod_step(*made_for) <= LOD_STEP_PIXELS * pixel).last().map(|(_, mesh)| mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn close_up_copies_are_drawn_from_twice_their_pixel_and_the_others_from_their_pixel() {
        // The two chains' copies as the look makes them (close-up 0.5 and 1 mm, then 2 to 16 mm),
        // each a distinct mesh.
        let made_for = [0.0005f32, 0.001, 0.002, 0.004, 0.008, 0.016];
        let lods: Lods = made_for.iter().map(|&p| (p, Arc::new(Mesh::cuboid(Vec3::splat(p))))).collect::<Vec<_>>().into();
        let drawn = |pixel: f32| coarsest(&lods, pixel).map(|m| made_for[lods.iter().position(|(_, l)| Arc::ptr_eq(l, m)).unwrap()]);
        assert_eq!(drawn(0.0002), None);
        assert_eq!(drawn(0.00025), Some(0.0005));
        assert_eq!(drawn(0.0005), Some(0.001));
        assert_eq!(drawn(0.0019), Some(0.001));
        assert_eq!(drawn(0.002), Some(0.002));
        assert_eq!(drawn(0.0039), Some(0.002));
        assert_eq!(drawn(0.004), Some(0.004));
        assert_eq!(drawn(0.05), Some(0.016));
        // A pixel the chains do not list counts as a step of its whole size.
        assert_eq!(lod_step(0.003), 0.003);
    }

    fn view_of(suite: &str, index: usize) -> (Sim, SceneView) {
        let model = SceneModel::build(crate::task(suite, index).unwrap()).unwrap();
        let sim = Sim::new(model.clone());
        let mut view = SceneView::new(&model);
        view.update(&sim);
        (sim, view)
    }

    #[test]
    fn legend_names_every_entity_robot_body_and_arena_piece_once() {
        let (sim, view) = view_of("libero_goal", 0);
        let ids: Vec<u32> = view.legend().iter().map(|s| s.id).collect();
        assert_eq!(ids, (1..=view.legend().len() as u32).collect::<Vec<_>>());
        for e in &sim.model().entities {
            assert!(view.segment_of(&e.name).is_some(), "{}", e.name);
        }
        for name in ["robot0_link3", "robot0_leftfinger", "floor", "main_table", "walls"] {
            assert!(view.segment_of(name).is_some(), "{name}");
        }
        // Every instance carries a legend id.
        let max = view.legend().len() as u32;
        assert!(view.scene().instances.iter().all(|i| (1..=max).contains(&i.segment)));
    }

    #[test]
    fn meshes_are_shared_between_equal_parts() {
        // libero_spatial task 0 has two identical black bowls.
        let (_, view) = view_of("libero_spatial", 0);
        let bowls: Vec<&Instance> =
            view.scene().instances.iter().filter(|i| [view.segment_of("akita_black_bowl_1"), view.segment_of("akita_black_bowl_2")].contains(&Some(i.segment))).collect();
        assert!(bowls.len() >= 2);
        let first = view.segment_of("akita_black_bowl_1").unwrap();
        let a = bowls.iter().find(|i| i.segment == first).unwrap();
        let b = bowls.iter().find(|i| i.segment != first).unwrap();
        assert!(Arc::ptr_eq(&a.mesh, &b.mesh));
    }

    #[test]
    fn instances_follow_their_bodies() {
        let (mut sim, mut view) = view_of("libero_goal", 0);
        let (cabinet, _) = sim.model().entity("wooden_cabinet_1").unwrap();
        let segment = view.segment_of("wooden_cabinet_1").unwrap();
        let before: Vec<Vec3> = view.scene().instances.iter().filter(|i| i.segment == segment).map(|i| i.transform.translation).collect();
        sim.set_joint(cabinet, "middle_level", -0.1);
        view.update(&sim);
        let after: Vec<Vec3> = view.scene().instances.iter().filter(|i| i.segment == segment).map(|i| i.transform.translation).collect();
        let moved = before.iter().zip(&after).filter(|(a, b)| (**a - **b).length() > 0.09).count();
        // The middle drawer's pieces moved by 10 cm; the carcass and other drawers did not.
        assert!(moved > 0 && moved < before.len(), "{moved} of {}", before.len());
    }

    #[test]
    fn an_entity_scene_holds_that_entity_alone_at_the_given_pose() {
        let (sim, view) = view_of("libero_goal", 0);
        let (bowl, _) = sim.model().entity("akita_black_bowl_1").unwrap();
        let segment = view.segment_of("akita_black_bowl_1").unwrap();
        let here = sim.entity_pose(bowl);
        let shift = Vec3::new(0.1, -0.2, 0.3);
        let there = Pose { pos: here.pos + vifo_robots::spatial::Vec3::new(0.1, -0.2, 0.3), ..here };
        let alone = view.entity_scene(&sim, bowl, &there);
        let originals: Vec<&Instance> = view.scene().instances.iter().filter(|i| i.segment == segment).collect();
        assert!(!alone.instances.is_empty());
        assert_eq!(alone.instances.len(), originals.len());
        assert!(alone.instances.iter().all(|i| i.segment == segment));
        for (moved, original) in alone.instances.iter().zip(originals) {
            assert!((moved.transform.translation - original.transform.translation - shift).length() < 1e-5);
        }
        assert_eq!(alone.lights, view.scene().lights);
        // The cabinet's drawers keep their place relative to its root.
        let (cabinet, _) = sim.model().entity("wooden_cabinet_1").unwrap();
        let at_home = view.entity_scene(&sim, cabinet, &sim.entity_pose(cabinet));
        let in_view: Vec<Vec3> = view.scene().instances.iter().filter(|i| i.segment == view.segment_of("wooden_cabinet_1").unwrap()).map(|i| i.transform.translation).collect();
        let alone: Vec<Vec3> = at_home.instances.iter().map(|i| i.transform.translation).collect();
        assert_eq!(in_view.len(), alone.len());
        assert!(in_view.iter().zip(&alone).all(|(a, b)| (*a - *b).length() < 1e-5));
    }

    #[test]
    fn the_burner_shows_only_while_the_stove_is_on() {
        let (mut sim, mut view) = view_of("libero_goal", 7);
        let (stove, _) = sim.model().entity("flat_stove_1").expect("libero_goal task 7 has the stove");
        let base = view.scene().instances.len();
        sim.set_joint(stove, "button", 0.6);
        view.update(&sim);
        assert_eq!(view.scene().instances.len(), base + 1);
        sim.set_joint(stove, "button", 0.4);
        view.update(&sim);
        assert_eq!(view.scene().instances.len(), base);
    }
}
