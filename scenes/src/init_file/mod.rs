//! LIBERO's fixed initial states: reading the original `.pruned_init` files, and naming the parts
//! of a state row for a task.
//!
//! A `.pruned_init` file is a `torch.save` zip archive whose `*/data.pkl` pickles one numpy
//! float64 array of shape (50, 1 + nq + nv). [`read`] unpacks it in pure Rust: the zip entry,
//! then a pickle reader that understands only numpy's array reconstruction (see `pickle`).
//! [`StateLayout`] says which numbers are the arm, the gripper, each object's pose and each
//! drawer, door or knob.

mod archive;
mod layout;
pub mod pickle;

pub use layout::{InitState, JointState, LayoutError, ObjectState, StateLayout, articulation_joints};

use std::path::Path;

/// A table of state rows (LIBERO's 50 initial states of one task).
#[derive(Clone, Debug, PartialEq)]
pub struct InitStates {
    cols: usize,
    /// Row-major.
    data: Vec<f64>,
}

impl InitStates {
    pub fn rows(&self) -> usize {
        self.data.len() / self.cols
    }

    /// Numbers per row (1 + nq + nv).
    pub fn cols(&self) -> usize {
        self.cols
    }

    pub fn row(&self, index: usize) -> Option<&[f64]> {
        self.data.chunks_exact(self.cols).nth(index)
    }

    pub fn iter(&self) -> impl Iterator<Item = &[f64]> {
        self.data.chunks_exact(self.cols)
    }
}

/// A file that is not a readable LIBERO init-state file.
#[derive(Debug, thiserror::Error)]
#[error("{file}: {problem}")]
pub struct InitFileError {
    pub file: String,
    pub problem: String,
}

/// Reads the bytes of a `.pruned_init` (or `.init`) file; `file` names it in errors.
pub fn read(bytes: &[u8], file: &str) -> Result<InitStates, InitFileError> {
    let fail = |problem: String| InitFileError { file: file.to_string(), problem };
    let pickle = archive::data_pickle(bytes).map_err(fail)?;
    let array = pickle::load_array(&pickle).map_err(fail)?;
    match array.shape[..] {
        [rows, cols] if rows > 0 && cols > 0 => Ok(InitStates { cols, data: array.values }),
        _ => Err(fail(format!("expected a non-empty 2-D array of states, found shape {:?}", array.shape))),
    }
}

/// Reads a `.pruned_init` file from disk.
pub fn load(path: &Path) -> Result<InitStates, InitFileError> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|e| InitFileError { file: file.clone(), problem: e.to_string() })?;
    read(&bytes, &file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use zip::write::SimpleFileOptions;

    fn archive(entries: &[(&str, &[u8])], method: zip::CompressionMethod) -> Vec<u8> {
        let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        for (name, bytes) in entries {
            zip.start_file(*name, SimpleFileOptions::default().compression_method(method)).unwrap();
            zip.write_all(bytes).unwrap();
        }
        zip.finish().unwrap().into_inner()
    }

    const VALUES: [f64; 6] = [0.0, 0.5, -1.25, 0.0, 2.0, 1e-300];

    #[test]
    fn reads_a_torch_style_archive() {
        for method in [zip::CompressionMethod::Stored, zip::CompressionMethod::Deflated] {
            let pickle = pickle::tests::pickle_array(2, 3, &VALUES, 2);
            let bytes = archive(&[("archive/data.pkl", &pickle), ("archive/version", b"3\n")], method);
            let states = read(&bytes, "t.pruned_init").unwrap();
            assert_eq!((states.rows(), states.cols()), (2, 3));
            assert_eq!(states.row(1).unwrap(), &VALUES[3..]);
            assert_eq!(states.row(2), None);
            assert_eq!(states.iter().count(), 2);
        }
    }

    #[test]
    fn explains_what_is_wrong_with_other_files() {
        let err = read(b"hello", "x.pruned_init").unwrap_err();
        assert!(err.to_string().starts_with("x.pruned_init: not a torch zip archive"), "{err}");
        let err = read(&pickle::tests::pickle_array(2, 3, &VALUES, 2), "old.pt").unwrap_err();
        assert!(err.problem.contains("legacy"), "{err}");
        let bytes = archive(&[("archive/version", b"3\n")], zip::CompressionMethod::Stored);
        let err = read(&bytes, "y").unwrap_err();
        assert_eq!(err.problem, "the archive has no data.pkl entry (entries: archive/version)");
        let no_rows = archive(&[("a/data.pkl", &pickle::tests::pickle_array(0, 3, &[], 2))], zip::CompressionMethod::Stored);
        assert!(read(&no_rows, "z").unwrap_err().problem.contains("non-empty 2-D"));
        let err = load(Path::new("/nonexistent/t.pruned_init")).unwrap_err();
        assert!(err.to_string().starts_with("/nonexistent/t.pruned_init: "), "{err}");
    }

    #[test]
    fn never_panics_on_damaged_archives() {
        let pickle = pickle::tests::pickle_array(2, 3, &VALUES, 4);
        let good = archive(&[("archive/data.pkl", &pickle)], zip::CompressionMethod::Stored);
        for cut in 0..good.len() {
            assert!(read(&good[..cut], "cut").is_err());
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..5000 {
            let mut bad = good.clone();
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let at = (state % bad.len() as u64) as usize;
            bad[at] ^= 1 << (state >> 61);
            let _ = read(&bad, "flip");
        }
    }
}
