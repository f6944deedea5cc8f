//! The look every rendering command uses: LIBERO's assets where discovery finds them, the
//! built-in look otherwise. Loaded once per process and shared by `Arc`; the first command to
//! ask says once, on stderr, which look it uses.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use anyhow::Result;
use clap::Args;
use vifo_scenes::look::{self, Look};

/// `--assets`, `--robot-assets` and `--builtin-look`, shared by every command that renders.
#[derive(Args, Clone, Debug, Default)]
pub struct LookArgs {
    /// LIBERO's asset folder (its `assets/`, a LIBERO checkout, or an asset wheel's package
    /// folder); searched before `VIFO_LIBERO_ASSETS` and the installed Python packages.
    #[arg(long, value_name = "DIR")]
    pub assets: Option<PathBuf>,
    /// robosuite's `models/assets` folder, for the robot's meshes (default: the installed
    /// robosuite).
    #[arg(long, value_name = "DIR")]
    pub robot_assets: Option<PathBuf>,
    /// Ignore any installed assets: draw the built-in procedural look.
    #[arg(long, conflicts_with_all = ["assets", "robot_assets"])]
    pub builtin_look: bool,
}

/// The loaded look of this process, with the arguments it was loaded for.
static LOADED: Mutex<Option<(LookKey, Option<Arc<Look>>)>> = Mutex::new(None);

/// `--assets`, `--robot-assets`, `--builtin-look`.
type LookKey = (Option<PathBuf>, Option<PathBuf>, bool);

impl LookArgs {
    /// The look to draw with (`None`: built-in), discovered and loaded on the first call and
    /// shared afterwards. Says once which look is used and why parts fall back.
    pub fn look(&self) -> Result<Option<Arc<Look>>> {
        let key = (self.assets.clone(), self.robot_assets.clone(), self.builtin_look);
        let mut loaded = LOADED.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, l)) = loaded.as_ref().filter(|(k, _)| *k == key) {
            return Ok(l.clone());
        }
        let result = if self.builtin_look {
            eprintln!("look: built-in (--builtin-look)");
            None
        } else {
            let roots = look::discover(self.assets.as_deref(), self.robot_assets.as_deref())?;
            if !roots.libero.is_empty() {
                // Loading takes seconds (the meshes' coarser copies); say so before the wait.
                eprintln!("look: loading LIBERO's meshes and textures (once per process)...");
            }
            let look = Look::load(roots);
            announce(&look);
            look.is_used().then(|| Arc::new(look))
        };
        *loaded = Some((key, result.clone()));
        Ok(result)
    }

    /// Discovery and loading without the cache or the message (for `vifo assets`).
    pub fn load(&self) -> Result<Look> {
        let roots = look::discover(self.assets.as_deref(), self.robot_assets.as_deref())?;
        Ok(Look::load(roots))
    }
}

/// The label results files record for `look` (`built-in` when `None`).
pub fn label(look: Option<&Look>) -> String {
    look.map_or_else(|| look::BUILT_IN.to_string(), Look::label)
}

fn announce(look: &Look) {
    for line in look.announcement("`vifo assets`") {
        eprintln!("look: {line}");
    }
}
