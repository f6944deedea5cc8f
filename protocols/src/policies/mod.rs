//! Built-in reference policies. Their metrics have known patterns, which the end-to-end tests
//! check:
//!
//! | policy | follows | expected |
//! |---|---|---|
//! | `expert-cue` | the task the cue shows (privileged), ignores language | high AVF, UVF, UVI; Orig. SR 0 |
//! | `expert-language` | the task the instruction names ([`ground`]) | high Orig. SR, LFR; AVF = UVF = UVI = 0 |
//! | `expert-authorized` | the cue under the authorisation sentence, else the language | high Orig. SR, AVF, LFR; UVF = UVI = 0 |
//! | `random` | uniform actions seeded from the episode | about 0 everywhere |
//! | `zero` | all-zero actions | 0 everywhere |
//!
//! "High" is as high as the scripted expert is reliable on the task (it does not yet solve
//! every task). The experts are privileged: they read the simulator through
//! [`EpisodeState`](crate::policy::EpisodeState), never the images.

mod expert;
pub mod ground;
mod simple;

pub use expert::{ExpertPolicy, Follow};
pub use simple::{Random, Zero};

use crate::policy::Policy;

/// The names `builtin` knows, in the order reports list them.
pub const NAMES: [&str; 5] = ["expert-cue", "expert-language", "expert-authorized", "random", "zero"];

/// Checks a name given to a policy that is not built in (`vifo run --policy-name`, a Python
/// policy's `name=`): printable, 1 to 100 characters, and not a built-in's, whose records it
/// would pass for.
pub fn check_name(name: &str) -> Result<(), String> {
    if name.trim().is_empty() || name.chars().count() > 100 || name.chars().any(char::is_control) {
        return Err(format!("{name:?}: give 1 to 100 printable characters"));
    }
    if NAMES.contains(&name) {
        return Err(format!("{name:?}: give the model a name of its own, not a built-in policy's name"));
    }
    Ok(())
}

/// A fresh built-in policy by name.
pub fn builtin(name: &str) -> Option<Box<dyn Policy>> {
    Some(match name {
        "expert-cue" => Box::new(ExpertPolicy::new(Follow::Cue)),
        "expert-language" => Box::new(ExpertPolicy::new(Follow::Language)),
        "expert-authorized" => Box::new(ExpertPolicy::new(Follow::Authorized)),
        "random" => Box::new(Random::default()),
        "zero" => Box::new(Zero),
        _ => return None,
    })
}
