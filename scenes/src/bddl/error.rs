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
            self.file, self.line, self.column, self.expected, self.found
        )
    }
}

impl std::error::Error for BddlError {}
