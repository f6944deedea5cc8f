//! The results file: one [`EpisodeRecord`] per JSON line, appended as episodes finish.
//!
//! Each record is written with a single `write_all` of the whole line including its newline,
//! so a crash can only leave an unterminated last line. Reading treats such a tail as
//! "never written" (the episode runs again on resume); any other unreadable line is an error
//! naming the file and line, because it means something else wrote to the file.

use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::spec::{EpisodeRecord, Outcome};

use super::RunError;

/// What a results file holds.
#[derive(Debug, Default)]
pub struct Loaded {
    /// Every complete record, in file order.
    pub records: Vec<EpisodeRecord>,
    /// Bytes of an unterminated last line (a write cut short), 0 if none.
    pub truncated_tail: usize,
    /// Length of the file up to the end of its last complete line.
    pub valid_len: u64,
}

/// Reads a results file. A missing file reads as empty.
pub fn read_records(path: &Path) -> Result<Loaded, RunError> {
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Loaded::default()),
        Err(e) => return Err(RunError::io(path, e)),
    };
    let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let mut loaded = Loaded { truncated_tail: bytes.len() - complete, valid_len: complete as u64, ..Loaded::default() };
    for (i, line) in bytes[..complete].split(|&b| b == b'\n').enumerate() {
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let record = serde_json::from_slice::<EpisodeRecord>(line).map_err(|e| RunError::BadLine {
            path: path.to_path_buf(),
            line: i + 1,
            message: format!("expected one episode record as JSON: {e}"),
        })?;
        loaded.records.push(record);
    }
    Ok(loaded)
}

/// The record that counts for each episode key: the last completed one, else the last error.
/// Resumed runs append a new record after an error, so a key can appear more than once.
pub fn final_records(records: impl IntoIterator<Item = EpisodeRecord>) -> BTreeMap<String, EpisodeRecord> {
    let mut out: BTreeMap<String, EpisodeRecord> = BTreeMap::new();
    for record in records {
        let key = record.spec.key();
        let keep_old = matches!(out.get(&key), Some(old) if is_completed(old) && !is_completed(&record));
        if !keep_old {
            out.insert(key, record);
        }
    }
    out
}

pub(crate) fn is_completed(record: &EpisodeRecord) -> bool {
    matches!(record.outcome, Outcome::Completed { .. })
}

/// Appends records, one line per `write_all`.
pub struct ResultsWriter {
    path: PathBuf,
    file: File,
}

impl ResultsWriter {
    /// Opens `path` for appending after cutting an unterminated tail (`valid_len` from
    /// [`read_records`]), so the next record starts on a fresh line.
    pub fn append(path: &Path, valid_len: u64) -> Result<ResultsWriter, RunError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| RunError::io(dir, e))?;
        }
        let file = OpenOptions::new().create(true).append(true).open(path).map_err(|e| RunError::io(path, e))?;
        let len = file.metadata().map_err(|e| RunError::io(path, e))?.len();
        if len > valid_len {
            file.set_len(valid_len).map_err(|e| RunError::io(path, e))?;
        }
        Ok(ResultsWriter { path: path.to_path_buf(), file })
    }

    /// Writes one record as one line and hands it to the operating system.
    pub fn write(&mut self, record: &EpisodeRecord) -> Result<(), RunError> {
        let mut line = serde_json::to_vec(record).map_err(|e| RunError::io(&self.path, e.into()))?;
        line.push(b'\n');
        self.file.write_all(&line).and_then(|()| self.file.flush()).map_err(|e| RunError::io(&self.path, e))
    }
}
