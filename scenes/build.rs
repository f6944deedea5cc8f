//! Names the code that makes the look's cached entries (`src/look/cache.rs`): a hash of the
//! look's and the renderer's sources, of the workspace's lock file (the simplifier's and
//! decoders' versions) and of the target (a home folder shared by machines of two kinds keeps
//! each one's own entries), so that a change to any of them starts a new cache folder instead of
//! reading what other code made.

use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::{Path, PathBuf};

fn main() {
    let mut files = Vec::new();
    for dir in ["src/look", "../render/src"] {
        println!("cargo:rerun-if-changed={dir}");
        collect(Path::new(dir), &mut files);
    }
    let lock = PathBuf::from("../Cargo.lock");
    if lock.is_file() {
        println!("cargo:rerun-if-changed=../Cargo.lock");
        files.push(lock);
    }
    files.sort();
    // SipHash with fixed keys: the same sources give the same name in every build.
    let mut h = DefaultHasher::new();
    std::env::var("TARGET").unwrap_or_default().hash(&mut h);
    for f in &files {
        f.hash(&mut h);
        std::fs::read(f).unwrap_or_default().hash(&mut h);
    }
    println!("cargo:rustc-env=VIFO_LOOK_CODE={:016x}", h.finish());
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.filter_map(Result::ok) {
        let path = e.path();
        if path.is_dir() {
            collect(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            out.push(path);
        }
    }
}
