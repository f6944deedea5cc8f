//! Subcommands of `vifo`, one module each, and the command-line values several of them take.

pub mod assets;
pub mod xval;
pub mod report;
pub mod vqa;
pub mod bddl;
pub mod bench;
pub mod cues;
pub mod expert;
pub mod render;
pub mod run;
pub mod init_states;
pub mod web;

use std::path::PathBuf;

use anyhow::Context;
use vifo_cues::{Family, SetName};
use vifo_protocols::CueForm;
use vifo_protocols::env::CueFacing;
use vifo_protocols::serving::Profile;

/// "1 episode", "8 episodes".
pub fn episodes_text(n: usize) -> String {
    format!("{n} episode{}", if n == 1 { "" } else { "s" })
}

/// A count that must be 1 or more (`--episodes`, `--steps`, ...): 0 would run nothing and
/// report it as a result.
pub fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("expected 1 or more: 0 would run nothing".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

/// An image side in pixels (`--size`), checked before anything is loaded or allocated: below
/// 16 a camera shows nothing a policy could use, above 4096 one frame alone is 48 MB.
pub fn image_side(s: &str) -> Result<u32, String> {
    match s.parse::<u32>() {
        Ok(n) if (16..=4096).contains(&n) => Ok(n),
        Ok(n) => Err(format!("{n} pixels: expected 16 to 4096")),
        Err(e) => Err(e.to_string()),
    }
}

/// A file `vifo` writes as PNG: a name ending otherwise (`x.jpg`) would hold PNG bytes under
/// another format's name.
pub fn png_file(s: &str) -> Result<PathBuf, String> {
    file_ending(s, "png")
}

/// A file `vifo` writes as a binary PPM image.
pub fn ppm_file(s: &str) -> Result<PathBuf, String> {
    file_ending(s, "ppm")
}

/// A file `vifo` writes as an animated GIF.
pub fn gif_file(s: &str) -> Result<PathBuf, String> {
    file_ending(s, "gif")
}

fn file_ending(s: &str, ending: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(s);
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case(ending) => Ok(path),
        _ => Err(format!("vifo writes this file as {}: give a name ending in .{ending}", ending.to_uppercase())),
    }
}

use vifo_protocols::benchmark::specs::MAX_EPISODES;

/// `--episodes`: 1 to [`MAX_EPISODES`].
pub fn episode_count(s: &str) -> Result<usize, String> {
    up_to(s, MAX_EPISODES, "episodes per instance (initial states repeat every 50)")
}

/// `init-states generate --states`: 1 to 10,000 per task (LIBERO ships 50; every slot is
/// allocated before the first state is drawn).
pub fn state_count(s: &str) -> Result<usize, String> {
    up_to(s, 10_000, "states per task (LIBERO ships 50)")
}

/// `render --steps`: 1 to 5,000 (ten times the longest suite's budget of 520 steps).
pub fn step_count(s: &str) -> Result<usize, String> {
    up_to(s, 5_000, "control steps (ten times libero_10's budget)")
}

/// A thread count or requests in flight: 1 to 1,024.
pub fn thread_count(s: &str) -> Result<usize, String> {
    up_to(s, 1_024, "threads")
}

/// A count from 1 to `max`: a mistyped huge count would otherwise run for ever or fill the
/// memory before it is noticed.
fn up_to(s: &str, max: usize, what: &str) -> Result<usize, String> {
    match at_least_one(s)? {
        n if n > max => Err(format!("at most {max} {what}")),
        n => Ok(n),
    }
}

/// `--set paper|full`.
pub fn parse_set(name: &str) -> Result<SetName, String> {
    name.parse()
}

/// A cue family, `F1` to `F8` (any case).
pub fn parse_family(name: &str) -> anyhow::Result<Family> {
    Family::ALL
        .into_iter()
        .find(|f| f.to_string().eq_ignore_ascii_case(name))
        .with_context(|| format!("unknown cue family {name:?}: expected F1 to F8"))
}

/// `--form overlay|object`: a cue drawn over the image or standing in the scene.
pub fn parse_form(name: &str) -> Result<CueForm, String> {
    CueForm::ALL.into_iter().find(|f| f.name() == name).ok_or_else(|| format!("unknown form {name:?}: expected overlay or object"))
}

/// `--cue-facing upright|model`: which way cues drawn over the frames face.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Facing {
    Upright,
    Model,
}

impl From<Facing> for CueFacing {
    fn from(f: Facing) -> CueFacing {
        match f {
            Facing::Upright => CueFacing::Upright,
            Facing::Model => CueFacing::Model,
        }
    }
}

/// `--model-profile NAME`.
pub fn profile(name: &str) -> anyhow::Result<&'static Profile> {
    Profile::named(name).with_context(|| format!("unknown --model-profile {name:?}: expected one of {}", Profile::names().join(", ")))
}
