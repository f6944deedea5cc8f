//! The one error type of the BDDL parser: where, what was expected, what was found.

use serde::Serialize;
use std::fmt;

/// A malformed BDDL file: `foo.bddl:12:5: expected ')' closing (:objects, found end of file`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct BddlError {
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    pub expected: String,
    pub found: String,
}

impl fmt::Display for BddlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: expected {}, found {}",
            self.file,
            self.line,
            self.column,
            self.expected,
            shown(&self.found)
        )
    }
}

/// What was found, as printed: a long token (a file of one huge word, or of NUL bytes) is cut
/// and control characters are escaped, so the message stays one readable line.
fn shown(found: &str) -> String {
    const MAX: usize = 80;
    let mut out: String =
        found.chars().take(MAX).flat_map(|c| if c.is_control() { c.escape_default().collect() } else { vec![c] }).collect();
    let n = found.chars().count();
    if n > MAX {
        out.push_str(&format!("… ({n} characters)"));
    }
    out
}

impl std::error::Error for BddlError {}
