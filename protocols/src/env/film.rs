//! Clips of chosen episodes, so people can see what ran: agentview with the episode's cue as the
//! policy saw it, the wrist camera beside it, as a looping GIF.
//!
//! Small and sparse (128² per camera, every 2nd control step by default) so filming the first
//! episode of each cue family costs a run little. A filmed episode runs in an environment of its
//! own that renders both cameras: at the run's size when the policy looks at images (the frames
//! are then exactly what it saw, scaled down), at the clip's size otherwise (a policy reading
//! the simulator acts the same whatever is drawn). The clip is written next to its final name
//! and renamed when the episode ends, so a results record never points at a half-written clip.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use vifo_render::RgbImage;
use vifo_render::imageio::{GifWriter, ImageIoError, side_by_side};
use vifo_scenes::view::{CameraName, ImageOrder};

use super::EnvConfig;
use crate::policy::Observation;

/// LIBERO's control rate: a clip of every `n`th step plays at `CONTROL_HZ / n` frames per
/// second, in real time.
const CONTROL_HZ: f32 = 20.0;

/// Black columns between the two cameras.
const GAP: u32 = 4;

/// Which episodes to film (by [`crate::EpisodeSpec::key`]) and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Filming {
    /// Episode key to the clip file it makes.
    pub clips: BTreeMap<String, PathBuf>,
    /// Side of each camera's picture in the clip, in pixels.
    pub size: u32,
    /// One frame every this many control steps (the first and the last are always in).
    pub every: usize,
}

impl Filming {
    /// No episode filmed; 128² pictures, every 2nd step.
    pub fn none() -> Filming {
        Filming { clips: BTreeMap::new(), size: 128, every: 2 }
    }

    /// The configuration of the environment a filmed episode runs in, for a run configured
    /// with `run`: both cameras upright, at the run's size when it renders (what the policy
    /// sees must not change), else at the clip's.
    pub fn env_config(&self, run: &EnvConfig) -> EnvConfig {
        let rendering = !run.cameras.is_empty();
        EnvConfig {
            size: if rendering { run.size } else { self.size },
            order: run.order,
            cameras: CameraName::ALL.to_vec(),
            cue_facing: run.cue_facing,
        }
    }
}

/// The clip of one running episode, written frame by frame to `<clip>.part`.
pub struct Clip {
    gif: GifWriter<BufWriter<File>>,
    part: PathBuf,
    path: PathBuf,
    size: u32,
    every: usize,
    /// Step of the last frame added.
    last: Option<usize>,
}

impl Clip {
    /// Starts the clip `path` (its folder is made), with `comment` in the file (what drew it).
    pub fn create(path: &Path, filming: &Filming, comment: &str) -> Result<Clip, ImageIoError> {
        let io = |source| ImageIoError::Io { path: path.display().to_string(), source };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let mut part = path.as_os_str().to_owned();
        part.push(".part");
        let part = PathBuf::from(part);
        let file = File::create(&part).map_err(io)?;
        let every = filming.every.max(1);
        let fps = CONTROL_HZ / every as f32;
        let mut gif = GifWriter::new(BufWriter::new(file), 2 * filming.size + GAP, filming.size, fps)?;
        gif.comment(comment)?;
        Ok(Clip { gif, part, path: path.to_path_buf(), size: filming.size, every, last: None })
    }

    /// Whether the frame of `step` belongs in the clip: every `every`th step, and the `last`.
    pub fn due(&self, step: usize, last: bool) -> bool {
        self.last != Some(step) && (step.is_multiple_of(self.every) || last)
    }

    /// Adds the observation's frame (images in `order`).
    pub fn add(&mut self, obs: &Observation, order: ImageOrder) -> Result<(), ImageIoError> {
        let agentview = self.picture(&obs.agentview, order);
        let wrist = self.picture(&obs.wrist, order);
        self.gif.add_frame(&side_by_side(&agentview, &wrist, GAP))?;
        self.last = Some(obs.step);
        Ok(())
    }

    /// The clip's file name.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Finishes the file and gives it its name; a clip without frames (an episode that failed
    /// to start) is removed instead.
    pub fn finish(self) -> Result<PathBuf, ImageIoError> {
        if self.last.is_none() {
            self.abandon();
            return Err(ImageIoError::Size("the episode drew no frame".into()));
        }
        let io = |source| ImageIoError::Io { path: self.path.display().to_string(), source };
        let mut file = self.gif.finish()?;
        std::io::Write::flush(&mut file).map_err(io)?;
        drop(file);
        std::fs::rename(&self.part, &self.path).map_err(io)?;
        Ok(self.path)
    }

    /// Removes the unfinished file (after an error).
    pub fn abandon(self) {
        let Clip { gif, part, .. } = self;
        drop(gif);
        let _ = std::fs::remove_file(part);
    }

    /// One camera's image upright at the clip's size (black where the camera drew nothing).
    fn picture(&self, camera: &vifo_cues::RgbImage, order: ImageOrder) -> RgbImage {
        let Some(buffer) = image::RgbImage::from_raw(camera.width, camera.height, camera.data.clone())
            .filter(|_| camera.width > 0 && camera.height > 0)
        else {
            return RgbImage::new(self.size, self.size);
        };
        let mut small = if (camera.width, camera.height) == (self.size, self.size) {
            buffer
        } else {
            image::imageops::resize(&buffer, self.size, self.size, image::imageops::FilterType::Triangle)
        };
        if order == ImageOrder::BottomUp {
            image::imageops::flip_vertical_in_place(&mut small);
        }
        RgbImage { width: self.size, height: self.size, data: small.into_raw() }
    }
}
