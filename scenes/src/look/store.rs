//! [`Look`]: LIBERO's meshes and textures, loaded once per process and shared by `Arc`.
//!
//! A category is drawn from its asset files only when every one of its visual parts loads;
//! otherwise it keeps the built-in procedural look and the problem is reported once, naming the
//! file. One bad file never affects another category.

use std::collections::BTreeMap;
use std::convert::Infallible;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

use serde::Serialize;
use sha1::{Digest, Sha1};
use vifo_render::assets::parse_mesh;
use vifo_render::pack::{PackError, Packer, Unpacker};
use vifo_render::imageio::decode_png_rgba;
use vifo_render::glam::Vec2;
use vifo_render::{Material, Mesh, Texture};

use super::cache::{CACHE_VAR, CacheReport, DiskCache};
use super::discover::Roots;
use super::{ARM, MOUNT};
use super::facts::{CATEGORIES, PANDA, SCENES};
use super::parallel::{self, Once};
use super::parts::{MaterialFact, PartFact, Shape};
use super::tree::{AssetTree, Located, blob_sha1};
use crate::catalog::{self, ObjectKind, Recipe};
use crate::scene_class::scene_class;
use crate::task::ProblemClass;
use crate::view::MeshCache;

/// One visual part ready to draw: where it sits on its body, its mesh and its material.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedPart {
    /// The body it moves with: a catalog body name (`main`, `cabinet_top`) or a robot body name
    /// (`link3`, `leftfinger`).
    pub body: &'static str,
    pub pos: [f64; 3],
    pub quat_wxyz: [f64; 4],
    /// The `<mesh scale>` (1 for primitives).
    pub scale: [f64; 3],
    pub mesh: Arc<Mesh>,
    /// Coarser copies of `mesh` for far views: (world size of the pixel it is made for, mesh), finest
    /// first; empty for primitives and meshes that are already coarse.
    pub lods: Lods,
    pub material: Material,
    /// The reflectance of a box MuJoCo draws as a mirror (its +z face), with the face's height
    /// in the part's frame.
    pub mirror: Option<MirrorFace>,
}

/// A box's +z face that MuJoCo draws as a mirror.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MirrorFace {
    pub reflectance: f32,
    /// Height of the face above the part's origin (the box's half height).
    pub height: f32,
}

/// Coarser copies of a mesh, each with the world size (metres) of the pixel it is made for.
pub type Lods = Arc<[(f32, Arc<Mesh>)]>;

/// World sizes of the pixels the coarser copies are made for, in two chains that each start
/// from the full mesh, with the fraction of its pixel by which each copy may move from the one
/// before it. At 256² a table-top object seen from agentview (about 1 m) is 3-4 mm per pixel:
/// half-pixel steps keep those copies within a pixel of the full mesh (a half + a quarter + ...).
/// The wrist camera near a grasp sees 0.3-2 mm per pixel, where the Gouraud shading of scanned
/// meshes' noisy normals shows more than their outline: quarter-pixel steps keep the close-up
/// copies within half a pixel of the full mesh at their own pixel (half-pixel steps there took
/// the wrist's median SSIM against MuJoCo from 0.943 to 0.936; these leave it at 0.942).
/// Each copy is drawn where its own step is at most half of the camera's pixel ([`lod_step`]):
/// a close-up copy from twice its pixel on, where all its steps stay within three quarters of a
/// pixel; MuJoCo's frames of the wrist over the expert's grasps moved by −0.003 to +0.002 SSIM
/// with that (2026-12-05, `docs/measurements.md`), and the reference frames not at all.
const LOD_CHAINS: [(&[f32], f32); 2] = [(&[0.0005, 0.001], 0.25), (&[0.002, 0.004, 0.008, 0.016], 0.5)];

/// How far the copy made for a `made_for` pixel (one of the LOD chains' pixels) may move a
/// surface from the copy before it in its chain (metres): its step times its pixel. Any other
/// `made_for` gets the pixel itself, which draws the copy only where it is below half a pixel.
pub fn lod_step(made_for: f32) -> f32 {
    LOD_CHAINS.iter().find(|(pixels, _)| pixels.contains(&made_for)).map_or(made_for, |&(_, step)| step * made_for)
}

/// How the files are turned into drawings, hashed into the look: a change that alters the asset
/// look's pixels gets a new name here, so results drawn before and after never share a look.
const DRAWING: &str = "quadric LODs within a pixel\ntriangle clusters\nclose-up LODs within half a pixel\nuntextured LODs across UV seams\ntextured walls and box-table faces\nLODs drawn where their step is within half a pixel\n";

/// A coarser copy is kept only if it has at most this fraction of the previous one's triangles.
const LOD_KEEP: f32 = 0.75;

/// The coarser copies of `mesh` drawn at `scale`, finest first. Without a texture the UVs are
/// never drawn, so they are dropped first: the simplifier keeps every UV seam, and robosuite's
/// Panda meshes carry UVs split at nearly every vertex (link 7's 5,374 triangles stopped at
/// 2,305, where without them they reach 263 for a 4 mm pixel).
fn lods_of(mesh: &Mesh, scale: [f64; 3], textured: bool) -> Lods {
    let plain;
    let mesh = match mesh.uvs() {
        Some(_) if !textured => {
            plain = mesh.without_uvs();
            &plain
        }
        _ => mesh,
    };
    let s = scale.iter().fold(0.0f64, |m, &x| m.max(x.abs())) as f32;
    let chain = |&(pixels, step): &(&[f32], f32)| {
        let mut out: Vec<(f32, Arc<Mesh>)> = Vec::new();
        let mut finer: Option<Arc<Mesh>> = None;
        for &pixel in pixels {
            let from = finer.as_deref().unwrap_or(mesh);
            if let Some(coarse) = from.simplified(step * pixel / s).filter(|m| (m.triangle_count() as f32) <= LOD_KEEP * from.triangle_count() as f32) {
                let coarse = Arc::new(coarse.clustered());
                finer = Some(coarse.clone());
                out.push((pixel, coarse));
            }
        }
        out
    };
    // The simplifier is about two thirds of loading all 40 tasks' assets, and the chains do not
    // depend on each other: where the machine has threads they run side by side (the same copies).
    parallel::map(&LOD_CHAINS, parallel::threads(), chain).concat().into()
}

/// Whether a category is drawn from LIBERO's files.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Assets,
    BuiltIn,
}

/// A file a category needs and where it was found (`None`: not found).
#[derive(Clone, Debug, Serialize)]
pub struct FileReport {
    pub file: &'static str,
    pub found: Option<Located>,
}

/// What a report line is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartKind {
    Object,
    Fixture,
    /// One body of the robot.
    Robot,
    /// Floor, walls, table of a scene class.
    Arena,
}

/// What `vifo assets` prints per category or robot body.
#[derive(Clone, Debug, Serialize)]
pub struct CategoryReport {
    /// Catalog category, or `robot0_<body>`.
    pub category: String,
    pub kind: PartKind,
    pub status: Status,
    pub files: Vec<FileReport>,
    /// Why the category falls back (the first file that failed and how).
    pub problem: Option<String>,
}

/// LIBERO's look as found on this machine.
pub struct Look {
    roots: Roots,
    hash: String,
    parts: BTreeMap<&'static str, Vec<LoadedPart>>,
    robot: BTreeMap<&'static str, Vec<LoadedPart>>,
    /// Floor, table and wall textures by upstream path.
    arena_textures: BTreeMap<&'static str, Arc<Texture>>,
    /// The scene XMLs' decor meshes (body `main` = the world) by scene XML name.
    decor: BTreeMap<&'static str, Vec<LoadedPart>>,
    report: Vec<CategoryReport>,
    cache: CacheReport,
}

/// Meshes and textures by file, so that a file shared by several parts (or asked for by several
/// threads at once) is read once.
#[derive(Default)]
struct Loaded {
    meshes: Once<PathBuf, FromFile<Arc<Mesh>>>,
    /// Coarser copies by file, scale bits, whether the mesh was given constant UVs (see
    /// `load_part`) and whether it is textured (see `lods_of`).
    lods: Once<(PathBuf, [u64; 3], bool, bool), Lods>,
    /// Copies of UV-less meshes with every UV at the origin, by file (see `constant_uv_mesh`).
    constant_uv_meshes: Once<PathBuf, Result<Arc<Mesh>, String>>,
    textures: Once<PathBuf, FromFile<LoadedTexture>>,
    /// (upstream path, blob hash) of every file read.
    hashes: Mutex<BTreeMap<&'static str, String>>,
    /// The primitives' procedural meshes.
    shapes: Mutex<MeshCache>,
    /// What earlier processes made of the same files.
    cache: DiskCache,
}

/// What was made of a file, and the file's blob hash where it could be read.
type FromFile<T> = (Option<String>, Result<T, String>);

impl Loaded {
    fn mesh(&self, rel: &'static str, at: &Located) -> Result<Arc<Mesh>, String> {
        let made = self.meshes.get_or_make(&at.path, || {
            read(at, |name, bytes, blob| {
                let make = || parse_mesh(bytes, name).map(|m| Arc::new(m.clustered())).map_err(|e| e.to_string());
                // The format is chosen by the name's extension, so it is part of the key.
                let format = at.path.extension().map(|x| x.to_string_lossy().to_lowercase()).unwrap_or_default();
                self.cache.get_or_make(&format!("mesh {format} {blob}"), make, |m, p| p.mesh(m), |u| u.mesh().map(Arc::new))
            })
        });
        self.hashed(rel, made)
    }

    /// `rel`'s mesh with every UV at the origin, made once per file. A textured mesh without UVs
    /// is drawn with one texel (see `material`), which needs UVs to be sampled at all.
    fn constant_uv_mesh(&self, rel: &'static str, at: &Located) -> Result<Arc<Mesh>, String> {
        self.constant_uv_meshes.get_or_make(&at.path, || Ok(Arc::new(self.mesh(rel, at)?.with_zero_uvs())))
    }

    fn texture(&self, rel: &'static str, at: &Located) -> Result<LoadedTexture, String> {
        let made = self.textures.get_or_make(&at.path, || {
            read(at, |name, bytes, blob| self.cache.get_or_make(&format!("texture {blob}"), || {
                let (mut w, mut h, mut rgba) = decode_png_rgba(bytes, name).map_err(|e| e.to_string())?;
                let texel = mean_rgb(&rgba).map(|c| (c * 255.0).round().clamp(0.0, 255.0) as u8);
                let mean = Texture::from_rgba8(1, 1, &[texel[0], texel[1], texel[2], 255]).expect("a 1 x 1 RGBA image is a valid texture");
                while w.max(h) > MAX_TEXTURE_SIDE && w % 2 == 0 && h % 2 == 0 {
                    (w, h, rgba) = halve(w, h, &rgba);
                }
                let texture = Texture::from_rgba8(w, h, &rgba).map_err(|e| format!("{name}: {e}"))?;
                Ok(LoadedTexture { full: Arc::new(texture), mean: Arc::new(mean) })
            }, |t, p| {
                p.texture(&t.full);
                p.texture(&t.mean);
            }, |u| Ok(LoadedTexture { full: Arc::new(u.texture()?), mean: Arc::new(u.texture()?) })))
        });
        self.hashed(rel, made)
    }

    /// The coarser copies of `mesh` (the file `rel`, drawn at `scale`), made once per process
    /// and kept in the disk cache.
    fn lods(&self, rel: &'static str, at: &Located, mesh: &Mesh, scale: [f64; 3], constant_uvs: bool, textured: bool) -> Lods {
        let key = (at.path.clone(), scale.map(f64::to_bits), constant_uvs, textured);
        self.lods.get_or_make(&key, || {
            let make = || lods_of(mesh, scale, textured);
            // The mesh was read, so its blob hash is known; without it there is no key to keep them by.
            let Some(blob) = self.hashes.lock().unwrap_or_else(PoisonError::into_inner).get(rel).cloned() else { return make() };
            let pack = |lods: &Lods, p: &mut Packer| {
                p.u32(lods.len() as u32);
                for (pixel, m) in lods.iter() {
                    p.f32(*pixel);
                    p.mesh(m);
                }
            };
            let unpack = |u: &mut Unpacker| (0..u.u32()?).map(|_| Ok((u.f32()?, Arc::new(u.mesh()?)))).collect::<Result<Vec<_>, PackError>>().map(Lods::from);
            let Ok(lods) = self.cache.get_or_make(&format!("lods {blob} {:?} {constant_uvs} {textured}", key.1), || Ok::<_, Infallible>(make()), pack, unpack);
            lods
        })
    }

    /// Notes `rel`'s blob hash for the look's hash (each path asked for, whichever thread read
    /// the file), and passes on what was made.
    fn hashed<T>(&self, rel: &'static str, (blob, made): FromFile<T>) -> Result<T, String> {
        if let Some(blob) = blob {
            self.hashes.lock().unwrap_or_else(PoisonError::into_inner).insert(rel, blob);
        }
        made
    }
}

/// Reads the file at `at` and makes something of its bytes (`make` gets the file's name and blob
/// hash too).
fn read<T>(at: &Located, make: impl FnOnce(&str, &[u8], &str) -> Result<T, String>) -> FromFile<T> {
    let name = at.path.display().to_string();
    match std::fs::read(&at.path) {
        Ok(bytes) => {
            let blob = blob_sha1(&bytes);
            let made = make(&name, &bytes, &blob);
            (Some(blob), made)
        }
        Err(e) => (None, Err(format!("{name}: cannot read: {e}"))),
    }
}

/// A texture file as drawn: the image, and one texel of its mean colour (for cube textures and
/// meshes without UVs, see `material`), both made once per file.
#[derive(Clone)]
struct LoadedTexture {
    full: Arc<Texture>,
    mean: Arc<Texture>,
}

/// Textures are kept at most this many texels on a side: at 256² no surface shows more texels
/// than that, and LIBERO's 4096² scanned-object atlases would otherwise take 85 MB each.
const MAX_TEXTURE_SIDE: u32 = 1024;

/// The image at half size, each texel the mean of a 2 × 2 block (rounded to nearest).
fn halve(w: u32, h: u32, rgba: &[u8]) -> (u32, u32, Vec<u8>) {
    let (w2, h2) = (w / 2, h / 2);
    let mut out = vec![0u8; (w2 * h2 * 4) as usize];
    for y in 0..h2 as usize {
        for x in 0..w2 as usize {
            for c in 0..4 {
                let at = |dx: usize, dy: usize| u32::from(rgba[((2 * y + dy) * w as usize + 2 * x + dx) * 4 + c]);
                out[(y * w2 as usize + x) * 4 + c] = ((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2) / 4) as u8;
            }
        }
    }
    (w2, h2, out)
}

/// Mean colour of RGBA8 pixels, in `[0, 1]`.
fn mean_rgb(rgba: &[u8]) -> [f32; 3] {
    let n = (rgba.len() / 4).max(1) as f64;
    let mut sum = [0f64; 3];
    for px in rgba.chunks_exact(4) {
        for c in 0..3 {
            sum[c] += f64::from(px[c]);
        }
    }
    sum.map(|s| (s / n / 255.0) as f32)
}

/// The mesh file of a part, or the procedural recipe of a primitive.
enum Source {
    File(&'static str, [f64; 3]),
    Primitive(Recipe),
}

fn source(shape: &Shape) -> Source {
    match *shape {
        Shape::Mesh { file, scale } => Source::File(file, scale),
        Shape::Box { half } => Source::Primitive(Recipe::Box { half }),
        Shape::Capsule { radius, half_height } => Source::Primitive(Recipe::Capsule { radius, half_height }),
    }
}

/// MuJoCo's material for a part. A 2D texture is sampled with the mesh's own UVs (`has_uvs`;
/// `texrepeat` as the UV scale); a cube texture, or one on a mesh without UVs, is one texel of
/// the texture's mean colour (MuJoCo maps those by direction or by object-plane texture
/// generation, which the renderer does not do). Being a texture, it multiplies the lit colour
/// after clamping, as MuJoCo's does: baked into `rgba` it would let bright lights push a
/// grey metal past its texture's colour.
fn material(fact: &MaterialFact, texture: Option<LoadedTexture>, has_uvs: bool) -> Material {
    let rgba = fact.rgba.map(|x| x as f32);
    let (specular, shininess, emission) = (fact.specular as f32, fact.shininess as f32, fact.emission as f32);
    let plain = Material { rgba, specular, shininess, emission, ..Material::default() };
    match (texture, &fact.texture) {
        (Some(tex), Some(t)) if !t.cube && has_uvs => {
            Material { texture: Some(tex.full), uv_scale: Vec2::new(t.repeat[0] as f32, t.repeat[1] as f32), ..plain }
        }
        (Some(tex), Some(_)) => Material { texture: Some(tex.mean), ..plain },
        _ => plain,
    }
}

impl Look {
    /// Loads every category's and robot body's parts found under `roots`, on a few threads
    /// where the machine has them.
    ///
    /// What loading makes of each file is kept in the disk cache (`cache.rs`), which the next
    /// process reads instead.
    pub fn load(roots: Roots) -> Look {
        Look::load_on(roots, parallel::threads(), DiskCache::from_env())
    }

    /// [`Look::load`] with the disk cache in `cache` (`None`: none) whatever the environment
    /// says: for programs that choose the folder themselves.
    pub fn load_with_cache(roots: Roots, cache: Option<&Path>) -> Look {
        Look::load_on(roots, parallel::threads(), DiskCache::at(cache.map(Path::to_path_buf)))
    }

    /// [`Look::load`] on up to `threads` threads with `cache`: the same look whatever the count
    /// and whatever the cache holds.
    pub(super) fn load_on(roots: Roots, threads: usize, cache: DiskCache) -> Look {
        let tree = AssetTree::new(&roots.libero);
        let robot_tree = AssetTree::with_known(roots.robot.as_slice(), &[]);
        let loaded = Loaded { cache, ..Loaded::default() };
        let jobs = jobs();
        let done = parallel::map(&jobs, threads, |job| match *job {
            Job::Parts { group, kind, ref facts } => {
                let tree = if matches!(group, Group::Robot(_)) { &robot_tree } else { &tree };
                let (line, ok) = load_group(group.name(), kind, facts.iter().copied(), tree, &loaded);
                (line, Done::Parts(ok))
            }
            Job::Arena { piece, file } => {
                let found = tree.find(file);
                let texture = found.clone().ok_or_else(|| format!("{file}: not found in any asset folder")).and_then(|at| loaded.texture(file, &at));
                let (status, problem, texture) = match texture {
                    Ok(texture) => (Status::Assets, None, Some(texture.full)),
                    Err(e) => (Status::BuiltIn, Some(e), None),
                };
                let line = CategoryReport { category: format!("{piece} {file}"), kind: PartKind::Arena, status, files: vec![FileReport { file, found }], problem };
                (line, Done::Arena(texture))
            }
        });
        let (mut parts, mut robot, mut decor, mut arena_textures) = (BTreeMap::new(), BTreeMap::new(), BTreeMap::new(), BTreeMap::new());
        let mut report = Vec::new();
        for (job, (line, done)) in jobs.iter().zip(done) {
            report.push(line);
            match (job, done) {
                (Job::Parts { group, .. }, Done::Parts(Some(ok))) => {
                    let _ = match *group {
                        Group::Category(name) => parts.insert(name, ok),
                        Group::Robot(name) => robot.insert(name, ok),
                        Group::Decor(name) => decor.insert(name, ok),
                    };
                }
                (&Job::Arena { file, .. }, Done::Arena(Some(texture))) => {
                    arena_textures.insert(file, texture);
                }
                _ => {}
            }
        }
        let mut h = Sha1::new();
        h.update(DRAWING.as_bytes());
        let hashes = loaded.hashes.into_inner().unwrap_or_else(PoisonError::into_inner);
        for (rel, blob) in &hashes {
            h.update(format!("{rel} {blob}\n").as_bytes());
        }
        let hash = if hashes.is_empty() { String::new() } else { h.finalize().iter().take(8).map(|b| format!("{b:02x}")).collect() };
        let cache = loaded.cache.report();
        Look { roots, hash, parts, robot, arena_textures, decor, report, cache }
    }

    /// The parts of `category`, when it is drawn from the asset files.
    pub fn parts(&self, category: &str) -> Option<&[LoadedPart]> {
        self.parts.get(category).map(Vec::as_slice)
    }

    /// What the disk cache did while this look loaded.
    pub fn cache(&self) -> &CacheReport {
        &self.cache
    }

    /// Where files were looked for.
    pub fn roots(&self) -> &Roots {
        &self.roots
    }

    /// Per category: drawn from assets or built in, which files, and why not.
    pub fn report(&self) -> &[CategoryReport] {
        &self.report
    }

    /// Content hash of the files read (16 hex digits over `DRAWING`, the list of drawing
    /// changes that alter pixels, and the upstream path and blob hash of each file), empty when
    /// nothing was read.
    pub fn hash(&self) -> &str {
        &self.hash
    }

    /// The parts of body `body` (`link3`, `leftfinger`) of arm `arm`, when drawn from
    /// robosuite's files. Those are the Panda's: another arm (the PiPER, whose links share
    /// names such as `link1`) has none and keeps its own shapes. The base of a `mounted` Panda
    /// (one whose model stands it on a pedestal) carries robosuite's pedestal. A body on which
    /// robosuite's Panda has no visual geom (`right_hand`, a frame inside the gripper's hand)
    /// has no parts: it draws nothing, as in MuJoCo, once any robot file was loaded.
    pub fn robot_parts(&self, arm: &str, body: &str, mounted: bool) -> Option<&[LoadedPart]> {
        if arm != ARM {
            return None;
        }
        let key = if mounted && body == "base" { MOUNT } else { body };
        match self.robot.get(key) {
            Some(parts) => Some(parts.as_slice()),
            None if !self.robot.is_empty() && !PANDA.iter().any(|p| p.body == key) => Some(&[]),
            None => None,
        }
    }

    /// The decor of `problem`'s scene XML (backdrops, furniture, paintings; posed in the world
    /// frame), when its files were found.
    pub fn decor(&self, problem: ProblemClass) -> Option<&[LoadedPart]> {
        let scene = match problem {
            ProblemClass::Tabletop => "libero_tabletop_base_style",
            ProblemClass::Floor => "libero_floor_base_style",
            ProblemClass::KitchenTabletop => "libero_kitchen_tabletop_base_style",
            ProblemClass::LivingRoomTabletop => "libero_living_room_tabletop_base_style",
            ProblemClass::StudyTabletop => "libero_study_base_style",
            _ => return None,
        };
        self.decor.get(scene).map(Vec::as_slice)
    }

    /// The floor, table or wall texture `file` (a [`crate::scene_class::Floor::texture`],
    /// [`crate::scene_class::Table::texture`] or [`crate::scene_class::SceneClass::wall_texture`]),
    /// when found.
    pub fn arena_texture(&self, file: &str) -> Option<&Arc<Texture>> {
        self.arena_textures.get(file)
    }

    /// True when at least one category, robot body, floor or table is drawn from asset files.
    pub fn is_used(&self) -> bool {
        !self.parts.is_empty() || !self.robot.is_empty() || !self.arena_textures.is_empty()
    }

    /// What results files record as the look: `built-in`, or `libero-assets:<hash>`.
    pub fn label(&self) -> String {
        if self.is_used() { format!("libero-assets:{}", self.hash) } else { BUILT_IN.to_string() }
    }

    /// What a program says once when it starts drawing: which look, and each part that keeps
    /// the built-in look and why. `details` names where to read more (`` `vifo assets` ``).
    pub fn announcement(&self, details: &str) -> Vec<String> {
        if !self.is_used() {
            let searched = if self.roots.libero.is_empty() { "no LIBERO asset folder found" } else { "no usable asset files" };
            return vec![format!("built-in ({searched}; {details} says where it looked)")];
        }
        let real = self.report.iter().filter(|r| r.status == Status::Assets).count();
        let mut lines = vec![format!(
            "{} ({real} of {} categories, robot bodies, floors, walls and table tops from asset files; {details} for details)",
            self.label(),
            self.report.len()
        )];
        for r in self.report.iter().filter(|r| r.status != Status::Assets) {
            lines.push(format!("{} keeps the built-in look: {}", r.category, r.problem.as_deref().unwrap_or("no parts")));
        }
        if let Some(problem) = &self.cache.problem {
            lines.push(format!("the look's cache is not kept ({problem}): the next process loads as slowly; set {CACHE_VAR} to another folder, or to `off`"));
        }
        lines
    }
}

/// One line of `vifo assets`, loaded as a piece of work of its own.
enum Job {
    /// All the visual parts of a category, robot body or scene's decor.
    Parts { group: Group, kind: PartKind, facts: Vec<&'static PartFact> },
    /// A floor, table or wall texture of a scene class.
    Arena { piece: &'static str, file: &'static str },
}

/// Whose parts a [`Job::Parts`] loads.
#[derive(Clone, Copy)]
enum Group {
    Category(&'static str),
    Robot(&'static str),
    /// A scene XML's decor.
    Decor(&'static str),
}

impl Group {
    /// Its line's name in the report.
    fn name(self) -> String {
        match self {
            Group::Category(c) => c.to_string(),
            Group::Robot(body) => format!("robot0_{body}"),
            Group::Decor(scene) => format!("decor {scene}"),
        }
    }
}

/// What a [`Job`] loaded, where every file it needs loaded.
enum Done {
    Parts(Option<Vec<LoadedPart>>),
    Arena(Option<Arc<Texture>>),
}

/// The report's lines in order: the catalog's categories, the Panda's bodies, the scene classes'
/// floor, table and wall textures, the scenes' decor.
fn jobs() -> Vec<Job> {
    let mut jobs = Vec::new();
    for (category, _xml, facts) in CATEGORIES.iter() {
        // Every fact category is in the catalog (tested); skip rather than panic if not.
        let Ok(model) = catalog::object(category) else { continue };
        let kind = if model.kind == ObjectKind::Movable { PartKind::Object } else { PartKind::Fixture };
        jobs.push(Job::Parts { group: Group::Category(category), kind, facts: facts.iter().collect() });
    }
    let mut bodies: Vec<&'static str> = PANDA.iter().map(|p| p.body).collect();
    bodies.dedup();
    for body in bodies {
        let facts = PANDA.iter().filter(|p| p.body == body).collect();
        jobs.push(Job::Parts { group: Group::Robot(body), kind: PartKind::Robot, facts });
    }
    let classes = || ProblemClass::ALL.iter().filter_map(|&p| scene_class(p));
    let mut arena_files: Vec<(&'static str, &'static str)> = classes()
        .map(|c| ("floor", c.floor.texture))
        .chain(classes().filter_map(|c| Some(("table", c.table?.texture?))))
        .chain(classes().map(|c| ("walls", c.wall_texture)))
        .collect();
    arena_files.sort_unstable();
    arena_files.dedup();
    jobs.extend(arena_files.into_iter().map(|(piece, file)| Job::Arena { piece, file }));
    for (scene, facts) in SCENES.iter().filter(|(_, facts)| !facts.is_empty()) {
        jobs.push(Job::Parts { group: Group::Decor(scene), kind: PartKind::Arena, facts: facts.iter().collect() });
    }
    jobs
}

/// The look label of the procedural scenes.
pub const BUILT_IN: &str = "built-in";

/// Loads one category's (or robot body's) parts: all of them, or none and the first problem.
fn load_group<'a>(
    category: String,
    kind: PartKind,
    facts: impl Iterator<Item = &'a PartFact>,
    tree: &AssetTree,
    loaded: &Loaded,
) -> (CategoryReport, Option<Vec<LoadedPart>>) {
    let mut files = Vec::new();
    let mut problem = None;
    let mut out = Vec::new();
    for fact in facts {
        match load_part(fact, tree, loaded, &mut files) {
            Ok(p) => out.push(p),
            Err(e) => {
                problem.get_or_insert(e);
            }
        }
    }
    let ok = problem.is_none() && !out.is_empty();
    let status = if ok { Status::Assets } else { Status::BuiltIn };
    (CategoryReport { category, kind, status, files, problem }, ok.then_some(out))
}

fn load_part(
    fact: &PartFact,
    tree: &AssetTree,
    loaded: &Loaded,
    files: &mut Vec<FileReport>,
) -> Result<LoadedPart, String> {
    let mut find = |rel: &'static str| -> Result<Located, String> {
        let found = tree.find(rel);
        if !files.iter().any(|f| f.file == rel) {
            files.push(FileReport { file: rel, found: found.clone() });
        }
        found.ok_or_else(|| format!("{rel}: not found in any asset folder"))
    };
    let (mesh, scale, lods, own_uvs) = match source(&fact.shape) {
        Source::File(file, scale) => {
            let at = find(file)?;
            let mut mesh = loaded.mesh(file, &at)?;
            let constant_uvs = fact.material.texture.is_some() && mesh.uvs().is_none();
            if constant_uvs {
                mesh = loaded.constant_uv_mesh(file, &at)?;
            }
            let textured = fact.material.texture.is_some();
            let lods = loaded.lods(file, &at, &mesh, scale, constant_uvs, textured);
            (mesh, scale, lods, !constant_uvs)
        }
        Source::Primitive(r) => {
            let mesh = loaded.shapes.lock().unwrap_or_else(PoisonError::into_inner).get(&r);
            let own_uvs = mesh.uvs().is_some();
            (mesh, [1.0; 3], Lods::from([]), own_uvs)
        }
    };
    let texture = match &fact.material.texture {
        Some(t) => {
            let at = find(t.file)?;
            Some(loaded.texture(t.file, &at)?)
        }
        None => None,
    };
    let material = material(&fact.material, texture, own_uvs);
    let mirror = match fact.shape {
        Shape::Box { half } if fact.material.reflectance > 0.0 => Some(MirrorFace { reflectance: fact.material.reflectance as f32, height: half[2] as f32 }),
        _ => None,
    };
    Ok(LoadedPart { body: fact.body, pos: fact.pos, quat_wxyz: fact.quat, scale, mesh, lods, material, mirror })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 cm sphere whose triangles share no vertex, each corner with a UV of its own: a UV
    /// seam at every vertex, as in robosuite's Panda meshes.
    fn seamed_sphere() -> Mesh {
        let s = Mesh::sphere(0.05, 48);
        let corners: Vec<u32> = s.triangles().iter().flatten().copied().collect();
        let pick = |v: &[vifo_render::glam::Vec3]| corners.iter().map(|&i| v[i as usize]).collect();
        let uvs = (0..corners.len()).map(|k| Vec2::new(k as f32 / corners.len() as f32, (k % 3) as f32 / 3.0)).collect();
        let triangles = (0..s.triangle_count() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        Mesh::new(pick(s.positions()), pick(s.normals()), Some(uvs), triangles).unwrap()
    }

    #[test]
    fn untextured_meshes_simplify_across_their_uv_seams() {
        let mesh = seamed_sphere();
        let coarsest = |lods: &Lods| lods.last().map_or(mesh.triangle_count(), |(_, m)| m.triangle_count());
        let textured = lods_of(&mesh, [1.0; 3], true);
        let plain = lods_of(&mesh, [1.0; 3], false);
        assert!(coarsest(&plain) * 4 < coarsest(&textured), "{} vs {} of {}", coarsest(&plain), coarsest(&textured), mesh.triangle_count());
        assert!(plain.iter().all(|(_, m)| m.uvs().is_none()));
    }
}
