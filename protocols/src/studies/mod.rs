//! The paper's extended studies (§4.2–§4.4), run with the benchmark's own machinery (episode
//! specs, the runner, results files) and reported in tables laid out as the paper lays each
//! study out. Study suites are not part of `--suite all` (the 40 LIBERO tasks).
//!
//! - [`piper`]: §4.4, the PiPER cup-stacking setting (suite `vifo_piper`).

pub mod piper;

/// A study `vifo run --study` runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Study {
    Piper,
}

impl Study {
    pub const ALL: [Study; 1] = [Study::Piper];

    pub fn name(self) -> &'static str {
        match self {
            Study::Piper => "piper",
        }
    }

    /// The study whose suite `suite` is, if any.
    pub fn of_suite(suite: &str) -> Option<Study> {
        (suite == piper::SUITE).then_some(Study::Piper)
    }
}

impl std::str::FromStr for Study {
    type Err = String;

    fn from_str(s: &str) -> Result<Study, String> {
        Study::ALL.into_iter().find(|st| st.name() == s).ok_or_else(|| format!("unknown study {s:?}: expected piper"))
    }
}
