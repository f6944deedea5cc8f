//! `vifo xval <dir> --images OUT`: our cameras next to MuJoCo's images of the same states.
//!
//! Each recording's episode is started as the motion check starts it (fixtures where the
//! recording put them, the recorded initial state), rendered at record 0, then driven by the
//! recorded actions to record 50 and rendered again. The reference set holds MuJoCo's 256²
//! images of exactly these records (upright PNGs). The reference used surrogate meshes for some
//! assets (black bowls as dark pucks, the basket as a brown block), so the pictures are expected
//! to differ there.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use serde::Serialize;
use vifo_render::imageio::{load_png, save_png_with_text, side_by_side};
use vifo_render::metrics::{psnr, ssim};
use vifo_render::{Renderer, RgbImage};
use vifo_scenes::look::Look;
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

use super::reference::Recording;
use super::replay::start;

/// Records the reference set has images of.
pub const IMAGE_STEPS: [usize; 2] = [0, 50];
/// Side of the reference images.
pub const IMAGE_SIZE: u32 = 256;

/// One compared image.
#[derive(Clone, Debug, Serialize)]
pub struct ImageReport {
    pub file: String,
    pub camera: &'static str,
    pub t: usize,
    pub psnr_db: f64,
    pub ssim: f64,
    /// The side-by-side PNG written (MuJoCo's | ours | difference).
    pub output: PathBuf,
}

/// Min, median and max of one metric over one camera's images.
#[derive(Clone, Debug, Serialize)]
pub struct Spread {
    pub min: f64,
    pub median: f64,
    pub max: f64,
}

/// PSNR and SSIM spread of one camera.
#[derive(Clone, Debug, Serialize)]
pub struct CameraSummary {
    pub camera: &'static str,
    pub images: usize,
    pub psnr_db: Spread,
    pub ssim: Spread,
}

fn spread(mut values: Vec<f64>) -> Option<Spread> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    let median = match n {
        0 => return None,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    };
    Some(Spread { min: values[0], median, max: values[n - 1] })
}

/// Per camera (in [`CameraName::ALL`] order), the spread of PSNR and SSIM over `reports`.
pub fn summarize(reports: &[ImageReport]) -> Vec<CameraSummary> {
    CameraName::ALL
        .iter()
        .filter_map(|c| {
            let mine: Vec<&ImageReport> = reports.iter().filter(|r| r.camera == c.as_str()).collect();
            Some(CameraSummary {
                camera: c.as_str(),
                images: mine.len(),
                psnr_db: spread(mine.iter().map(|r| r.psnr_db).collect())?,
                ssim: spread(mine.iter().map(|r| r.ssim).collect())?,
            })
        })
        .collect()
}

/// Per-pixel absolute difference, times 4 (clamped) so small differences show.
pub fn difference(a: &RgbImage, b: &RgbImage) -> RgbImage {
    let mut out = RgbImage::new(a.width.min(b.width), a.height.min(b.height));
    let w = out.width as usize;
    for y in 0..out.height as usize {
        for x in 0..w {
            for c in 0..3 {
                let pa = a.data[(y * a.width as usize + x) * 3 + c];
                let pb = b.data[(y * b.width as usize + x) * 3 + c];
                out.data[(y * w + x) * 3 + c] = (u32::from(pa.abs_diff(pb)) * 4).min(255) as u8;
            }
        }
    }
    out
}

/// The reference image of `camera` at record `t` next to the recording `path`.
pub fn reference_image(path: &Path, camera: CameraName, t: usize) -> PathBuf {
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!("{stem}_{camera}_step{t:02}.png"))
}

/// Renders the recording at [`IMAGE_STEPS`] with both cameras in `look` (`None`: built-in),
/// writes `MuJoCo | ours | difference` PNGs into `out` and returns PSNR and SSIM per image.
pub fn compare(path: &Path, rec: &Recording, out: &Path, look: Option<&Look>) -> Result<Vec<ImageReport>> {
    let last = IMAGE_STEPS[IMAGE_STEPS.len() - 1];
    if rec.steps.len() <= last {
        bail!("{} records; the image check needs record {last}", rec.steps.len());
    }
    vifo_protocols::runner::create_folder(out)?;
    let file = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut sim = start(rec)?;
    let mut view = SceneView::with_look(sim.model(), look);
    let mut renderer = Renderer::default();
    let cameras = Cameras::new(IMAGE_SIZE, IMAGE_SIZE);
    let mut reports = Vec::new();
    let look_label = crate::look::label(look);
    for t in 0..=last {
        if t > 0 {
            sim.step(&rec.steps[t].action()?);
        }
        if !IMAGE_STEPS.contains(&t) {
            continue;
        }
        view.update(&sim);
        for camera in CameraName::ALL {
            let ours = view.render(&mut renderer, &cameras.get(camera, &sim), ImageOrder::Upright)?.color;
            let theirs = load_png(reference_image(path, camera, t))?;
            let output = out.join(format!("{}_{camera}_step{t:02}.png", file.trim_end_matches(".json")));
            let scene = format!("MuJoCo | ours | difference: {file}, {camera}, record {t}");
            let sheet = side_by_side(&side_by_side(&theirs, &ours, 4), &difference(&ours, &theirs), 4);
            save_png_with_text(&sheet, &output, &[("look", &look_label), ("scene", &scene)])?;
            reports.push(ImageReport { file: file.clone(), camera: camera.as_str(), t, psnr_db: psnr(&ours, &theirs)?, ssim: ssim(&ours, &theirs)?, output });
        }
    }
    Ok(reports)
}
