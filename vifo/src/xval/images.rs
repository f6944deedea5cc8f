//! `vifo xval <dir> --images OUT`: our cameras next to MuJoCo's images of the same states.
//!
//! Each recording's episode is started as the motion check starts it (fixtures where the
//! recording put them, the recorded initial state) and driven by the recorded actions; it is
//! rendered at every record of which MuJoCo's 256² images of both cameras lie next to the
//! recording (upright PNGs): records 0 and 50 in the reference set, every tenth record in
//! recordings of the expert's episodes (`xval/record_complete.py --actions`). The reference used surrogate meshes for some
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

/// The records of the recording `path` (of `records` records) that have MuJoCo's images of both
/// cameras: [`IMAGE_STEPS`] in the reference set, more in recordings of other episodes.
pub fn image_steps(path: &Path, records: usize) -> Vec<usize> {
    (0..records).filter(|&t| CameraName::ALL.iter().all(|&c| reference_image(path, c, t).is_file())).collect()
}

/// Renders the recording at its [`image_steps`] with both cameras in `look` (`None`: built-in),
/// writes `MuJoCo | ours | difference` PNGs into `out` and returns PSNR and SSIM per image.
pub fn compare(path: &Path, rec: &Recording, out: &Path, look: Option<&Look>) -> Result<Vec<ImageReport>> {
    let steps = image_steps(path, rec.steps.len());
    let Some(&last) = steps.last() else {
        bail!("no record has MuJoCo's images of both cameras ({})", reference_image(path, CameraName::ALL[0], 0).display());
    };
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
        if !steps.contains(&t) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_steps_are_the_records_with_both_cameras_images() {
        let dir = std::env::temp_dir().join(format!("vifo-image-steps-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("libero_goal_task0_init0.json");
        let touch = |camera: CameraName, t: usize| std::fs::write(reference_image(&path, camera, t), b"").unwrap();
        for t in [0, 10, 120] {
            for camera in CameraName::ALL {
                touch(camera, t);
            }
        }
        // One camera alone does not make a compared record; records past the recording are not.
        touch(CameraName::ALL[0], 20);
        assert_eq!(image_steps(&path, 121), [0, 10, 120]);
        assert_eq!(image_steps(&path, 100), [0, 10]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
