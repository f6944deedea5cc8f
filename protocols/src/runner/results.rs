//! The results file: one [`EpisodeRecord`] per JSON line, appended as episodes finish.
//!
//! Each record is written with a single `write_all` of the whole line including its newline,
//! so a crash can only leave an unterminated last line. Reading treats such a tail as
//! "never written" (the episode runs again on resume); any other unreadable line is an error
//! naming the file and line, because it means something else wrote to the file.
//!
//! A write that fails (a full disk) is cut back off the file, and the writer refuses further
//! records, so the file never holds a partial line followed by whole ones. A run holds an
//! exclusive lock on `<results>.lock` while it writes ([`RunLock`]): a second run on the same
//! file stops with an error instead of interleaving lines. The lock file is removed when the
//! run ends; the operating system drops the lock when the process ends, however it ends, so the
//! empty file a killed run leaves blocks nothing (the next run takes it over and removes it).

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
    /// The line of each record (from 1), for messages about it.
    pub lines: Vec<usize>,
    /// Bytes of an unterminated last line (a write cut short), 0 if none. A last line that
    /// holds a whole record but lost only its newline (an editor's save) is a record.
    pub truncated_tail: usize,
    /// Length of the file up to the end of its last complete line or record.
    pub valid_len: u64,
}

/// Reads a results file. A missing file reads as empty.
pub fn read_records(path: &Path) -> Result<Loaded, RunError> {
    // A device or a pipe could be read forever; results files are plain files.
    if let Ok(meta) = std::fs::metadata(path)
        && !meta.is_file()
    {
        return Err(RunError::io(path, std::io::Error::other("not a plain file")));
    }
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Loaded::default()),
        Err(e) => return Err(RunError::io(path, e)),
    };
    parse_records(&bytes, path)
}

/// Reads the bytes of a results file (`path` names it in errors).
pub fn parse_records(bytes: &[u8], path: &Path) -> Result<Loaded, RunError> {
    let mut complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    if complete < bytes.len() && serde_json::from_slice::<EpisodeRecord>(&bytes[complete..]).is_ok() {
        complete = bytes.len();
    }
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
        loaded.lines.push(i + 1);
    }
    Ok(loaded)
}

fn last_byte(path: &Path) -> std::io::Result<u8> {
    use std::io::{Read, Seek, SeekFrom};
    let mut file = std::fs::File::open(path)?;
    file.seek(SeekFrom::End(-1))?;
    let mut byte = [0u8];
    file.read_exact(&mut byte)?;
    Ok(byte[0])
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

/// Prefix and suffix of a policy's results file name in a run's folder.
const FILE_NAME: (&str, &str) = ("results-", ".jsonl");

/// The results file name of the policy labelled `label` (its given name, or the `--policy`
/// string) in a run's folder: `results-<label, file-safe>.jsonl`. `vifo run`, Python's
/// `evaluate` and Ray name files so, and `vifo report FOLDER` reads these back.
pub fn file_name(label: &str) -> String {
    format!("{}{}{}", FILE_NAME.0, file_safe(label), FILE_NAME.1)
}

/// Whether a file name is one that [`file_name`] gives.
pub fn is_file_name(name: &str) -> bool {
    name.starts_with(FILE_NAME.0) && name.ends_with(FILE_NAME.1)
}

/// A policy name, address or model id as part of a file name: every character but ASCII
/// letters, digits, `-`, `_` and `.` becomes `_` (`ws://h:8000` → `ws___h_8000`).
pub fn file_safe(s: &str) -> String {
    s.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

pub(crate) fn is_completed(record: &EpisodeRecord) -> bool {
    matches!(record.outcome, Outcome::Completed { .. })
}

/// Creates the output folder `dir` and those above it. A file standing where one of them should
/// be is named as such (`create_dir_all` says only "File exists" or "Not a directory").
pub fn create_folder(dir: &Path) -> Result<(), RunError> {
    std::fs::create_dir_all(dir).map_err(|e| match blocker(dir) {
        Some(file) => RunError::io(file, std::io::Error::new(std::io::ErrorKind::NotADirectory, "a file, where the output needs a folder")),
        None => RunError::io(dir, e),
    })
}

/// [`create_folder`] for writers of `io` results (reports, charts, clips).
pub fn create_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| match blocker(dir) {
        Some(file) => std::io::Error::new(
            std::io::ErrorKind::NotADirectory,
            format!("{} is a file, where the output needs a folder", file.display()),
        ),
        None => e,
    })
}

/// The file (or device) standing where `dir` or one of its parents must be a folder.
fn blocker(dir: &Path) -> Option<&Path> {
    dir.ancestors().find(|a| a.exists() && !a.is_dir())
}

/// Creates the folder `path` goes in.
fn create_parent(path: &Path) -> Result<(), RunError> {
    path.parent().filter(|d| !d.as_os_str().is_empty()).map_or(Ok(()), create_folder)
}

/// The lock a run holds on its results file (released when dropped or when the process ends).
/// Dropping it also removes the lock file, so none is left beside the results.
#[derive(Debug)]
pub struct RunLock {
    /// Locked; closing it (after [`Drop::drop`]) releases the lock.
    _file: File,
    path: PathBuf,
    /// The process that took it: a forked child (Python's `multiprocessing`) shares the lock,
    /// and its copy must not remove the file while the parent still writes.
    pid: u32,
}

impl RunLock {
    /// Takes the lock on `<results>.lock`, creating the folder if needed; fails at once if
    /// another run holds it.
    pub fn take(results: &Path) -> Result<RunLock, RunError> {
        create_parent(results)?;
        let mut name = results.as_os_str().to_owned();
        name.push(".lock");
        let path = PathBuf::from(name);
        loop {
            let file = OpenOptions::new().create(true).truncate(false).write(true).open(&path).map_err(|e| RunError::io(&path, e))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(std::fs::TryLockError::WouldBlock) => return Err(RunError::Locked { results: results.to_path_buf(), lock: path }),
                Err(std::fs::TryLockError::Error(e)) => return Err(RunError::io(&path, e)),
            }
            // A run that ended between our open and our lock removed the file we opened: a lock
            // on it excludes nobody, so lock the one at the path now instead.
            if still_at(&file, &path).map_err(|e| RunError::io(&path, e))? {
                return Ok(RunLock { _file: file, path, pid: std::process::id() });
            }
        }
    }
}

impl Drop for RunLock {
    /// Removes the lock file while still holding its lock (the file closes after this), so
    /// no other run can go on holding a lock on it; see [`RunLock::take`]'s check. Best effort:
    /// a file left behind is taken over by the next run.
    fn drop(&mut self) {
        if cfg!(unix) && self.pid == std::process::id() {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Whether `file` is still the file at `path` (same device and inode).
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> std::io::Result<bool> {
    use std::os::unix::fs::MetadataExt;
    let named = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(e),
    };
    let held = file.metadata()?;
    Ok(held.dev() == named.dev() && held.ino() == named.ino())
}

/// Without a stable way in `std` to tell two files apart, the lock file is never removed
/// elsewhere, so the one locked is the one at the path.
#[cfg(not(unix))]
fn still_at(_file: &File, _path: &Path) -> std::io::Result<bool> {
    Ok(true)
}

/// Appends records, one line per `write_all`.
pub struct ResultsWriter {
    path: PathBuf,
    file: File,
    /// File length after the last record written whole.
    len: u64,
    /// Set by a failed write: the file was cut back to `len` and takes no more records.
    failed: bool,
}

impl ResultsWriter {
    /// Opens `path` for appending after cutting an unterminated tail (`valid_len` from
    /// [`read_records`]), so the next record starts on a fresh line.
    pub fn append(path: &Path, valid_len: u64) -> Result<ResultsWriter, RunError> {
        create_parent(path)?;
        let file = OpenOptions::new().create(true).append(true).open(path).map_err(|e| RunError::io(path, e))?;
        let len = file.metadata().map_err(|e| RunError::io(path, e))?.len();
        if len > valid_len {
            file.set_len(valid_len).map_err(|e| RunError::io(path, e))?;
        }
        let mut writer = ResultsWriter { path: path.to_path_buf(), file, len: len.min(valid_len), failed: false };
        // A last record without its newline: the next one starts on a line of its own.
        if writer.len > 0 && last_byte(path).map_err(|e| RunError::io(path, e))? != b'\n' {
            writer.file.write_all(b"\n").map_err(|e| RunError::io(path, e))?;
            writer.len += 1;
        }
        Ok(writer)
    }

    /// Writes one record as one line and hands it to the operating system. After a failure
    /// the part written is cut off again and every later call fails.
    pub fn write(&mut self, record: &EpisodeRecord) -> Result<(), RunError> {
        if self.failed {
            return Err(RunError::io(&self.path, std::io::Error::other("an earlier write failed; no more records are written")));
        }
        let mut line = serde_json::to_vec(record).map_err(|e| RunError::io(&self.path, e.into()))?;
        line.push(b'\n');
        match self.file.write_all(&line).and_then(|()| self.file.flush()) {
            Ok(()) => {
                self.len += line.len() as u64;
                Ok(())
            }
            Err(e) => {
                self.failed = true;
                // Best effort: if even this fails, the reader still treats the unterminated
                // tail as never written.
                let _ = self.file.set_len(self.len);
                Err(RunError::io(&self.path, e))
            }
        }
    }
}
