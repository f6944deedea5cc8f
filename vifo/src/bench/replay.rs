//! `vifo bench replay <dir>`: control steps per second while replaying recorded LIBERO episodes
//! (`*_init0.json`, the format of `vifo xval`) in the full task scene, without cameras and with
//! both 256² cameras rendered after every step, as a LIBERO evaluation does.
//!
//! This is our half of the side-by-side bench against the original stack
//! (`bench/libero_side_by_side.sh`), which times the same steps there. Both sides use the
//! wall clock over whole episodes, because the original renderer works in threads of its own.
//! The cameras draw the look given (LIBERO's assets, as the original draws them, or the
//! built-in one).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use vifo_render::{Frame, Renderer};
use vifo_robots::action::Action;
use vifo_scenes::look::Look;
use vifo_scenes::view::{CameraName, Cameras, ImageOrder, SceneView};

use crate::look::label;
use crate::xval::{Recording, recordings_in, start};

const SIZE: u32 = 256;

/// Steps per second of one recording, the median over the repeats.
#[derive(Debug, Serialize)]
pub struct ReplayBench {
    pub file: String,
    pub suite: String,
    pub task_id: usize,
    pub control_steps: usize,
    pub repeats: usize,
    pub steps_per_second_physics: f64,
    pub steps_per_second_two_cameras_256: f64,
    /// The look the cameras drew (`built-in`, or LIBERO's assets with their hash).
    pub look: String,
}

/// One timed episode: the recorded actions from the recorded start, rendering both cameras
/// after each step when `render` is set. Returns steps per second.
fn episode(rec: &Recording, actions: &[Action], render: bool, look: Option<&Look>) -> Result<f64> {
    let mut sim = start(rec)?;
    let mut view = SceneView::with_look(sim.model(), look);
    let cameras = Cameras::new(SIZE, SIZE);
    let mut renderer = Renderer::default();
    let mut frame = Frame::default();
    let clock = Instant::now();
    for action in actions {
        sim.step(action);
        if render {
            view.update(&sim);
            for name in CameraName::ALL {
                view.render_into(&mut renderer, &cameras.get(name, &sim), ImageOrder::Upright, &mut frame)?;
            }
        }
    }
    Ok(actions.len() as f64 / clock.elapsed().as_secs_f64())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) }
}

/// Times every recording in `dir`, `repeats` episodes per configuration (scene building and
/// state loading are outside the timed span, as `reset()` is on the original's side), the
/// cameras drawing `look` (`None`: built-in).
pub fn run(dir: &Path, repeats: usize, look: Option<Arc<Look>>) -> Result<Vec<ReplayBench>> {
    let repeats = repeats.max(1);
    let mut out = Vec::new();
    for path in recordings_in(dir)? {
        let rec = Recording::load(&path)?;
        let actions = rec.steps[1..].iter().map(|r| r.action()).collect::<Result<Vec<_>>>()?;
        let physics = (0..repeats).map(|_| episode(&rec, &actions, false, None)).collect::<Result<Vec<_>>>()?;
        let rendered = (0..repeats).map(|_| episode(&rec, &actions, true, look.as_deref())).collect::<Result<Vec<_>>>()?;
        out.push(ReplayBench {
            file: path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
            suite: rec.meta.suite.clone(),
            task_id: rec.meta.task_id,
            control_steps: actions.len(),
            repeats,
            steps_per_second_physics: median(physics),
            steps_per_second_two_cameras_256: median(rendered),
            look: label(look.as_deref()),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_or_empty_directory_is_an_error_naming_it() {
        let missing = Path::new("no/such/recordings");
        let err = run(missing, 1, None).unwrap_err().to_string();
        assert!(err.contains("no/such/recordings"), "{err}");
        let empty = std::env::temp_dir().join(format!("vifo-bench-replay-empty-{}", std::process::id()));
        std::fs::create_dir_all(&empty).unwrap();
        let err = format!("{:#}", run(&empty, 1, None).unwrap_err());
        std::fs::remove_dir_all(&empty).unwrap();
        assert!(err.contains("no *_init0.json recordings"), "{err}");
    }
}
