//! Reading a text input file (a BDDL task, a JSON task list, a questions file) without the
//! ways `read_to_string` fails a user: a device or pipe named by mistake is read forever
//! (`/dev/zero` fills the memory), and invalid UTF-8 is reported without saying where.

use std::io;
use std::path::Path;

/// Input text files larger than this are refused (LIBERO's largest BDDL file is a few kB, a
/// questions file of the full set a few MB).
pub const MAX_BYTES: u64 = 1 << 30;

/// The text of the plain file `path`; the error says what is wrong (not a plain file, too
/// large, or the line and column of the first byte that is not UTF-8). It does not name the
/// file: callers do.
pub fn read(path: &Path) -> io::Result<String> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(io::Error::other("not a plain file"));
    }
    if meta.len() > MAX_BYTES {
        return Err(io::Error::other(format!("{} bytes, more than the {MAX_BYTES} an input file may have", meta.len())));
    }
    let bytes = std::fs::read(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
        let line_start = valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let column = String::from_utf8_lossy(&valid[line_start..]).chars().count() + 1;
        io::Error::new(io::ErrorKind::InvalidData, format!("line {line}, column {column}: not UTF-8 text"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_invalid_text_are_named() {
        assert_eq!(read(Path::new("/dev/zero")).unwrap_err().to_string(), "not a plain file");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.bddl");
        std::fs::write(&path, b"(define\n  (probl\xffem x))").unwrap();
        assert_eq!(read(&path).unwrap_err().to_string(), "line 2, column 9: not UTF-8 text");
        std::fs::write(&path, "(define (problem é))\n").unwrap();
        assert_eq!(read(&path).unwrap(), "(define (problem é))\n");
        assert_eq!(read(&dir.path().join("missing")).unwrap_err().kind(), io::ErrorKind::NotFound);
    }
}
