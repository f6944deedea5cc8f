//! A cue as a scene object (paper §4.2): which physical kind an F1/F6/F8 variant becomes, where
//! it stands in an episode, and its picture on the face for the cameras.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use vifo_cues::{CueSpec, OBJECT_FAMILIES, object_picture};
use vifo_render::{Material, Mesh, Texture};
use vifo_scenes::cue_object::{self, CueObjectKind, ENTITY_NAME};
use vifo_scenes::sim::Sim;
use vifo_scenes::view::SceneView;
use vifo_robots::spatial::Pose;

use super::EnvError;
use crate::runner::stable_hash;

/// Side of the frame the picture is drawn for: text and codes at 512 (legible on a 20 cm card
/// close up), signs (drawn graphics) at 256.
fn picture_side(spec: &CueSpec) -> u32 {
    if spec.family == vifo_cues::Family::F6 { 256 } else { 512 }
}

/// Pictures kept per process before the cache starts over (bounded memory).
const KEPT: usize = 64;

/// The physical kind of a cue: text cards for F1 (a long strip for bars and banners, a note
/// card for the sticky note), a sign on a post for F6, tags for F8 (wide for the barcode).
pub fn kind_of(spec: &CueSpec) -> Result<CueObjectKind, EnvError> {
    use vifo_cues::Family;
    match (spec.family, spec.variant.as_str()) {
        (Family::F1, "sticky_note") => Ok(CueObjectKind::Note),
        (Family::F1, _) => Ok(CueObjectKind::TextStrip),
        (Family::F6, _) => Ok(CueObjectKind::Sign),
        (Family::F8, "barcode_code128") => Ok(CueObjectKind::BarcodeTag),
        (Family::F8, _) => Ok(CueObjectKind::CodeTag),
        (family, _) => Err(EnvError::Cue(format!(
            "{}: family {} has no scene-object form (only {})",
            spec.id(),
            family.name(),
            OBJECT_FAMILIES.map(|f| f.name()).join(", ")
        ))),
    }
}

/// Seed of the placement: the instance and the initial state, so every protocol of an
/// instance sees the cue at the same place from the same start.
pub fn placement_seed(instance: &str, init: usize) -> u64 {
    stable_hash(&format!("{instance}|{init}|cue-object"))
}

/// Stands the cue object of `spec` in `sim` (built with it) by the placement rule of
/// [`cue_object::place`].
pub fn stand(sim: &mut Sim, spec: &CueSpec, init: usize) -> Result<(), EnvError> {
    let kind = kind_of(spec)?;
    let entity = entity(sim)?;
    let pose = cue_object::place(sim, entity, kind, placement_seed(&spec.id(), init)).map_err(|e| EnvError::Scene(e.to_string()))?;
    sim.place_object(entity, &pose);
    Ok(())
}

fn entity(sim: &Sim) -> Result<usize, EnvError> {
    sim.model().entity(ENTITY_NAME).map(|(i, _)| i).ok_or_else(|| EnvError::Scene(format!("the scene has no {ENTITY_NAME}")))
}

/// Puts the cue's picture on the object's face in `view`: as large as fits with its aspect,
/// centred, the rest of the face the card's paper; lit like any object, slightly matte.
pub fn paint(view: &mut SceneView, sim: &Sim, spec: &CueSpec) -> Result<(), EnvError> {
    let kind = kind_of(spec)?;
    paint_on(view, sim, ENTITY_NAME, kind.face(), spec)
}

/// Puts `spec`'s picture on a face of the scene entity `name` (a rectangle in its body frame,
/// with half width and height, as [`CueObjectKind::face`] gives): the §4.2 cue objects, and
/// the PiPER study's paper note, whose text is drawn as the sticky-note cue draws it.
pub fn paint_on(view: &mut SceneView, sim: &Sim, name: &str, face: (Pose, [f64; 2]), spec: &CueSpec) -> Result<(), EnvError> {
    let entity = sim.model().entity(name).map(|(i, _)| i).ok_or_else(|| EnvError::Scene(format!("the scene has no {name}")))?;
    let segment = view.segment_of(name).ok_or_else(|| EnvError::Scene(format!("the view has no {name}")))?;
    let texture = picture(spec)?;
    let (face, half) = face;
    let (w, h) = (texture.width() as f64, texture.height() as f64);
    let scale = (2.0 * half[0] / w).min(2.0 * half[1] / h);
    let mesh = Arc::new(Mesh::grid((w * scale / 2.0) as f32, (h * scale / 2.0) as f32, 4, 4));
    let material = Material { texture: Some(texture), specular: 0.1, shininess: 0.1, ..Material::default() };
    view.attach(entity, 0, face, mesh, material, segment);
    Ok(())
}

/// The instance's picture as a texture, made once per instance and process.
fn picture(spec: &CueSpec) -> Result<Arc<Texture>, EnvError> {
    static MADE: Mutex<BTreeMap<String, Arc<Texture>>> = Mutex::new(BTreeMap::new());
    // The payload too: the PiPER note's two texts share one spec otherwise.
    let id = format!("{}|{}", spec.id(), spec.payload_text());
    if let Some(t) = MADE.lock().unwrap_or_else(|p| p.into_inner()).get(&id) {
        return Ok(t.clone());
    }
    let image = object_picture(spec, picture_side(spec)).map_err(|e| EnvError::Cue(e.to_string()))?;
    let texture = Texture::from_rgb8(image.width, image.height, &image.data).map_err(|e| EnvError::Cue(format!("{id}: {e}")))?;
    let texture = Arc::new(texture);
    let mut made = MADE.lock().unwrap_or_else(|p| p.into_inner());
    if made.len() >= KEPT {
        made.clear();
    }
    made.insert(id, texture.clone());
    Ok(texture)
}
