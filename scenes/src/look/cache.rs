//! The look's disk cache: what loading made of each asset file (a clustered mesh, its coarser
//! copies, a downsized texture), kept so that the next process reads it instead of making it
//! again. Loading all 40 tasks' assets takes about 10 s on two cores, most of it
//! meshoptimizer's simplifier and PNG decoding; each process, Python interpreter and Ray worker
//! paid it.
//!
//! - An entry is found by the file's blob hash (its content, not its path or time) and what was
//!   made of it, in a folder named for the code that makes it: a hash of the look's and the
//!   renderer's sources and of the workspace's lock file, computed by `build.rs`. A change to
//!   any of them starts a new folder; the newest [`KEEP`] folders are kept.
//! - Each entry carries a SHA-1 of its bytes: one that is short, corrupt or unreadable is made
//!   again and rewritten. Entries are written to a temporary file and renamed into place, so
//!   processes loading side by side never read a half-written one.
//! - A process making an entry holds the entry's lock file (`<name>.lock`) until it is written,
//!   so that processes starting together on a cold cache (Ray workers) make each entry once: the
//!   others wait for it and read it. A lock held for longer than [`LOCK_WAIT`] (a stuck process)
//!   is given up on and the entry made anyway; where locks are not supported, nobody waits.
//! - Where: `VIFO_LOOK_CACHE` (a folder, or `off`), else `$XDG_CACHE_HOME/libero-vifo/look`, else
//!   `~/.cache/libero-vifo/look`. A folder that cannot be written costs speed only, and is said.

use std::fs::{File, TryLockError};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use sha1::{Digest, Sha1};
use vifo_render::pack::{PackError, Packer, Unpacker};

/// The environment variable naming the cache folder (`off`: no cache).
pub const CACHE_VAR: &str = "VIFO_LOOK_CACHE";

/// Names the code that makes the entries (see `build.rs`).
const CODE: &str = env!("VIFO_LOOK_CODE");

/// Code folders kept: builds used side by side (a Python package and a command-line build of
/// another commit) keep their own entries.
const KEEP: usize = 3;

/// How long a process waits for another to make an entry. The slowest entry (a scene's decor)
/// takes about 2 s to make on one core.
const LOCK_WAIT: Duration = Duration::from_secs(120);

/// An entry's first bytes.
const MAGIC: &[u8; 8] = b"VIFOLOOK";

/// Where entries are read and written, and how many of each this process saw.
pub(super) struct DiskCache {
    /// The code's folder; `None` when the cache is off or no folder is known.
    dir: Option<PathBuf>,
    read: AtomicUsize,
    made: AtomicUsize,
    /// The first entry that could not be written, and why.
    problem: OnceLock<String>,
    /// Made once, when the first entry is written: the folder, and old code folders removed.
    prepared: OnceLock<Result<(), String>>,
}

/// What the cache did while the look loaded, for `vifo assets`.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct CacheReport {
    /// The code's folder (`None`: no cache).
    pub dir: Option<PathBuf>,
    /// Entries read from it.
    pub read: usize,
    /// Entries made from the asset files (and written, unless `problem` says otherwise).
    pub made: usize,
    /// Why entries could not be written.
    pub problem: Option<String>,
}

/// No cache.
impl Default for DiskCache {
    fn default() -> DiskCache {
        DiskCache::at(None)
    }
}

impl DiskCache {
    /// The cache the environment asks for (see the module doc).
    pub(super) fn from_env() -> DiskCache {
        let var = std::env::var_os(CACHE_VAR).filter(|v| !v.is_empty());
        let base = match var {
            Some(v) if v == "off" => None,
            Some(v) => Some(PathBuf::from(v)),
            None => std::env::var_os("XDG_CACHE_HOME")
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
                .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
                .map(|c| c.join("libero-vifo").join("look")),
        };
        DiskCache::at(base)
    }

    /// A cache under `base` (`None`: none).
    pub(super) fn at(base: Option<PathBuf>) -> DiskCache {
        DiskCache { dir: base.map(|b| b.join(CODE)), read: AtomicUsize::new(0), made: AtomicUsize::new(0), problem: OnceLock::new(), prepared: OnceLock::new() }
    }

    /// The entry `key` read back, or made by `make` and written. A failure to make is passed on
    /// and not kept.
    pub(super) fn get_or_make<T, E>(
        &self,
        key: &str,
        make: impl FnOnce() -> Result<T, E>,
        pack: impl FnOnce(&T, &mut Packer),
        unpack: impl Fn(&mut Unpacker) -> Result<T, PackError>,
    ) -> Result<T, E> {
        let Some(dir) = &self.dir else { return make() };
        let path = dir.join(entry_name(key));
        if let Some(found) = read_entry(&path, &unpack) {
            self.read.fetch_add(1, Ordering::Relaxed);
            return Ok(found);
        }
        // Another process may be making it: wait for its lock, then read what it wrote.
        let prepared = self.prepare(dir);
        let lock = prepared.as_ref().ok().and_then(|()| lock_entry(&path));
        if lock.is_some() && let Some(found) = read_entry(&path, &unpack) {
            self.read.fetch_add(1, Ordering::Relaxed);
            return Ok(found);
        }
        let made = make()?;
        self.made.fetch_add(1, Ordering::Relaxed);
        let mut packer = Packer::new();
        pack(&made, &mut packer);
        if let Err(e) = prepared.and_then(|()| write_entry(&path, &packer.finish())) {
            let _ = self.problem.set(e);
        }
        drop(lock);
        Ok(made)
    }

    pub(super) fn report(&self) -> CacheReport {
        CacheReport {
            dir: self.dir.clone(),
            read: self.read.load(Ordering::Relaxed),
            made: self.made.load(Ordering::Relaxed),
            problem: self.problem.get().cloned(),
        }
    }

    /// Creates the code's folder and removes all but the newest [`KEEP`] code folders beside it.
    fn prepare(&self, dir: &Path) -> Result<(), String> {
        self.prepared
            .get_or_init(|| {
                std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
                if let Some(base) = dir.parent() {
                    prune(base, dir);
                }
                Ok(())
            })
            .clone()
    }
}

/// An entry's file name: the SHA-1 of its key.
fn entry_name(key: &str) -> String {
    Sha1::digest(key.as_bytes()).iter().map(|b| format!("{b:02x}")).collect::<String>() + ".bin"
}

/// The entry's lock file, held (the lock goes with the file when it is dropped). `None` where it
/// cannot be had: locks unsupported, the folder unwritable, or held past [`LOCK_WAIT`].
fn lock_entry(path: &Path) -> Option<File> {
    let file = File::options().write(true).create(true).truncate(false).open(path.with_extension("lock")).ok()?;
    let deadline = Instant::now() + LOCK_WAIT;
    loop {
        match file.try_lock() {
            Ok(()) => return Some(file),
            Err(TryLockError::WouldBlock) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(10)),
            Err(_) => return None,
        }
    }
}

/// The entry at `path`, when it is whole and reads back.
fn read_entry<T>(path: &Path, unpack: impl Fn(&mut Unpacker) -> Result<T, PackError>) -> Option<T> {
    let bytes = std::fs::read(path).ok()?;
    let rest = bytes.strip_prefix(MAGIC)?;
    let (sum, payload) = rest.split_at_checked(20)?;
    if Sha1::digest(payload).as_slice() != sum {
        return None;
    }
    let mut u = Unpacker::new(payload);
    let value = unpack(&mut u).ok()?;
    u.finish().ok()?;
    Some(value)
}

/// Writes an entry beside its place and renames it there.
fn write_entry(path: &Path, payload: &[u8]) -> Result<(), String> {
    let mut bytes = Vec::with_capacity(MAGIC.len() + 20 + payload.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&Sha1::digest(payload));
    bytes.extend_from_slice(payload);
    // Unique per process and thread, so that writers side by side never share a temporary file.
    let tmp = path.with_extension(format!("tmp{}.{:?}", std::process::id(), std::thread::current().id()).replace(['(', ')'], ""));
    std::fs::write(&tmp, &bytes).and_then(|()| std::fs::rename(&tmp, path)).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        format!("cannot write {}: {e}", path.display())
    })
}

/// Removes the code folders under `base` other than the newest [`KEEP`] (by modification time;
/// `current` counts as the newest). Failures are ignored: another process may be removing them too.
fn prune(base: &Path, current: &Path) {
    let Ok(entries) = std::fs::read_dir(base) else { return };
    let mut others: Vec<(std::time::SystemTime, PathBuf)> = entries
        .filter_map(Result::ok)
        .filter(|e| e.path() != current && e.file_type().is_ok_and(|t| t.is_dir()))
        .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
        .collect();
    others.sort_by_key(|(modified, _)| std::cmp::Reverse(*modified));
    for (_, old) in others.into_iter().skip(KEEP - 1) {
        let _ = std::fs::remove_dir_all(old);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cache_in(dir: &Path) -> DiskCache {
        DiskCache::at(Some(dir.to_path_buf()))
    }

    fn get(cache: &DiskCache, key: &str, value: u32) -> Result<u32, String> {
        cache.get_or_make(key, || Ok(value), |v, p| p.u32(*v), |u| u.u32())
    }

    #[test]
    fn entries_are_read_back_and_bad_ones_made_again() {
        let tmp = tempfile::tempdir().unwrap();
        let cache = cache_in(tmp.path());
        assert_eq!(get(&cache, "a", 7), Ok(7));
        // Read back: `make`'s value is not used.
        assert_eq!(get(&cache, "a", 8), Ok(7));
        assert_eq!(get(&cache, "b", 9), Ok(9));
        assert_eq!(cache.report(), CacheReport { dir: Some(tmp.path().join(CODE)), read: 1, made: 2, problem: None });
        // A failure to make is passed on and not kept.
        assert_eq!(cache.get_or_make("c", || Err::<u32, _>("broken".to_string()), |v, p| p.u32(*v), |u| u.u32()), Err("broken".to_string()));
        assert_eq!(get(&cache, "c", 3), Ok(3));
        // A truncated, a changed and an empty entry are each made again and rewritten.
        let path = tmp.path().join(CODE).join(entry_name("a"));
        let whole = std::fs::read(&path).unwrap();
        for bad in [whole[..whole.len() - 1].to_vec(), { let mut b = whole.clone(); *b.last_mut().unwrap() ^= 1; b }, Vec::new()] {
            std::fs::write(&path, bad).unwrap();
            let fresh = cache_in(tmp.path());
            assert_eq!(get(&fresh, "a", 11), Ok(11));
            assert_eq!(fresh.report().made, 1);
            assert_eq!(get(&cache_in(tmp.path()), "a", 12), Ok(11));
            std::fs::write(&path, &whole).unwrap();
        }
        // No temporary file is left behind.
        let names: Vec<String> = std::fs::read_dir(tmp.path().join(CODE)).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        assert!(names.iter().all(|n| n.ends_with(".bin") || n.ends_with(".lock")), "{names:?}");
    }

    #[test]
    fn a_process_making_an_entry_has_the_others_wait_and_read_it() {
        let tmp = tempfile::tempdir().unwrap();
        // Two caches on one folder stand for two processes: each opens its own lock file, and
        // such locks exclude each other within one process too.
        let (first, second) = (cache_in(tmp.path()), cache_in(tmp.path()));
        let (started, making) = std::sync::mpsc::channel();
        std::thread::scope(|s| {
            s.spawn(|| {
                let slow = || {
                    started.send(()).unwrap();
                    std::thread::sleep(Duration::from_millis(300));
                    Ok::<_, String>(7)
                };
                assert_eq!(first.get_or_make("a", slow, |v, p| p.u32(*v), |u| u.u32()), Ok(7));
            });
            making.recv().unwrap();
            assert_eq!(get(&second, "a", 8), Ok(7));
        });
        assert_eq!((first.report().made, first.report().read), (1, 0));
        assert_eq!((second.report().made, second.report().read), (0, 1));
    }

    #[test]
    fn an_unwritable_folder_costs_speed_only_and_is_said() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("not-a-folder");
        std::fs::write(&file, b"x").unwrap();
        let cache = cache_in(&file);
        assert_eq!(get(&cache, "a", 7), Ok(7));
        assert_eq!(get(&cache, "a", 8), Ok(8));
        let report = cache.report();
        assert_eq!((report.read, report.made), (0, 2));
        assert!(report.problem.as_deref().is_some_and(|p| p.contains("not-a-folder")), "{report:?}");
        let off = DiskCache::at(None);
        assert_eq!(get(&off, "a", 5), Ok(5));
        assert_eq!(off.report(), CacheReport { dir: None, read: 0, made: 0, problem: None });
    }

    #[test]
    fn old_code_folders_beyond_the_newest_are_removed() {
        let tmp = tempfile::tempdir().unwrap();
        for (i, name) in ["old1", "old2", "old3"].iter().enumerate() {
            std::fs::create_dir(tmp.path().join(name)).unwrap();
            let t = std::time::SystemTime::UNIX_EPOCH + std::time::Duration::from_secs(1_000_000 * (i as u64 + 1));
            std::fs::File::open(tmp.path().join(name)).unwrap().set_modified(t).unwrap();
        }
        get(&cache_in(tmp.path()), "a", 1).unwrap();
        let mut left: Vec<String> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        left.sort();
        let mut want = vec![CODE.to_string(), "old2".into(), "old3".into()];
        want.sort();
        assert_eq!(left, want);
    }
}
