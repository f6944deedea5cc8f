//! The cue's own picture, printed on a physical card, sign or tag (paper §4.2: cues as scene
//! objects). It is exactly what the overlay form draws, cut out of the frame, so the two forms
//! show the same content and differ only in how they reach the camera.

use crate::draw;
use crate::error::CueError;
use crate::image::RgbImage;
use crate::insert::{FrameInputs, Inserter};
use crate::signage::{SignSpec, compose_pixmap};
use crate::spec::{CueSpec, Family};
use crate::variants::{Form, Marks};

/// The families that exist as scene objects (paper §4.2): text cards, signs and code tags.
pub const OBJECT_FAMILIES: [Family; 3] = [Family::F1, Family::F6, Family::F8];

/// Paper colour the picture is printed on.
pub const PAPER: [u8; 3] = [250, 250, 246];

/// The picture of `spec` as printed on its object, about `side` pixels on its longer side,
/// on [`PAPER`]. Fixed-region cues (F1, F8) are drawn as the overlay draws them into a
/// `side`² frame and cut to what they cover; signs (F6) are the composed sign without the
/// post the overlay adds. Other families have no object form.
pub fn object_picture(spec: &CueSpec, side: u32) -> Result<RgbImage, CueError> {
    let variant = spec.check()?;
    if !OBJECT_FAMILIES.contains(&spec.family) {
        return Err(CueError::BadSpec(format!(
            "{}: family {} has no scene-object form (only F1 text, F6 signs and F8 codes do)",
            spec.id(),
            spec.family.name()
        )));
    }
    let side = side.clamp(32, 2048);
    if let Form::Sign(category) = variant.form {
        let step = spec.steps.get(spec.step).ok_or_else(|| CueError::BadSpec(format!("spec has no step {}", spec.step)))?;
        // As the overlay: a target sign stands at the source when the step has no target.
        let on_source = match variant.marks {
            Marks::Target => spec.target.is_none(),
            _ => true,
        };
        let sign = compose_pixmap(&SignSpec::for_step(category, step, on_source), side);
        let mut out = RgbImage::filled(sign.width(), sign.height(), PAPER)?;
        draw::composite(&mut out, &sign, 0, 0);
        return Ok(out);
    }
    // What the overlay covers: pixels that differ between a black and a white frame.
    let mut inserter = Inserter::new();
    let draw_on = |inserter: &mut Inserter, rgb: [u8; 3]| -> Result<RgbImage, CueError> {
        let mut frame = RgbImage::filled(side, side, rgb)?;
        inserter.insert(&mut frame, spec, &FrameInputs::default())?;
        Ok(frame)
    };
    let black = draw_on(&mut inserter, [0, 0, 0])?;
    let paper = draw_on(&mut inserter, PAPER)?;
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for y in 0..side {
        for x in 0..side {
            if black.pixel(x, y) != Some([0, 0, 0]) || paper.pixel(x, y) != Some(PAPER) {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
            }
        }
    }
    if x0 > x1 {
        return Err(CueError::BadSpec(format!("{}: the overlay draws nothing", spec.id())));
    }
    let (w, h) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut data = Vec::with_capacity(w as usize * h as usize * 3);
    for y in y0..=y1 {
        let row = (y * side + x0) as usize * 3;
        data.extend_from_slice(&paper.data[row..row + w as usize * 3]);
    }
    Ok(RgbImage::from_raw(w, h, data)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{parse, variants};

    fn spec(variant: &str) -> CueSpec {
        let task = parse("put the black bowl on the plate").unwrap();
        CueSpec::new("t/0", &task, 0, variants::find(variant).unwrap()).unwrap()
    }

    #[test]
    fn fixed_region_pictures_are_the_overlay_cut_to_its_box() {
        let caption = object_picture(&spec("caption_bar"), 512).unwrap();
        // The caption bar spans the frame and is about a fifth of it high.
        assert_eq!(caption.width, 512);
        assert!((90..130).contains(&caption.height), "{}", caption.height);
        let qr = object_picture(&spec("qr_instruction"), 512).unwrap();
        assert!(qr.width < 300 && (qr.width as f32 / qr.height as f32 - 1.0).abs() < 0.5, "{}x{}", qr.width, qr.height);
    }

    #[test]
    fn signs_are_composed_without_the_post_and_other_families_have_no_object() {
        let sign = object_picture(&spec("sign_mandatory_source"), 200).unwrap();
        assert_eq!(sign.width, 200);
        assert!(sign.height >= 200);
        let err = object_picture(&spec("straight_arrow_red"), 200).unwrap_err();
        assert!(err.to_string().contains("F2"), "{err}");
    }
}
