//! Finding one upstream file in the asset roots: by its upstream path first, then (for files
//! whose upstream blob hash is known) by content, since LIBERO-PRO's wheels keep some files only
//! under a variant's folder (`red_akita_black_bowl/`, `red_basket/`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::Serialize;
use sha1::{Digest, Sha1};

use super::discover::Root;

/// Upstream git blob SHA-1s of the files the reference snapshot lacked (paths under LIBERO's
/// `assets/`), so a copy under another name can be recognised.
pub const KNOWN_BLOBS: [(&str, &str); 14] = [
    ("stable_scanned_objects/akita_black_bowl/visual/akita_black_bowl_vis.msh", "4068575d0038c63ebd19b59ad415fd2a2809d436"),
    ("stable_scanned_objects/akita_black_bowl/texture.png", "480c0fc69019bc601abdf5fa66f0c171fe4e498b"),
    ("stable_scanned_objects/basket/visual/basket_vis.msh", "aa5ce1b4738b3121024e6d33356625c89705899e"),
    ("stable_scanned_objects/basket/texture.png", "a7b6d1f8a5dd393d603dd8db1283b529eef5141f"),
    ("stable_scanned_objects/plate/texture.png", "af4001e756abd872b0aacfbfb517ec7bac549bea"),
    ("turbosquid_objects/porcelain_mug/porcelain_mug_texture.png", "4fbb8b96df475b02a297a2466e6f953d5aa5214b"),
    ("turbosquid_objects/red_coffee_mug/red_coffee_mug_texture.png", "aa45ec8403646aebef687395d7ddbfb24b5856b7"),
    ("turbosquid_objects/white_yellow_mug/white_yellow_mug_texture.png", "945fc11f107a38c6282735f77177816e45c2bda9"),
    ("turbosquid_objects/desk_caddy/desk_caddy_texture.png", "15f16f8185d4f09b3f4e5531c939dccb28269a9c"),
    ("scenes/kitchen_background/visual/kitchen_background_vis.msh", "7c684365cb40e736ac58099812879baf7f67aec9"),
    ("scenes/kitchen_background_pot/visual/kitchen_background_pot_vis.msh", "19ba167aec6bfbbcf2651c9fdca1a2e7cbde0847"),
    ("scenes/kitchen_background_stove/visual/kitchen_background_stove_vis.msh", "2e46da8c774c0ccb1e337f60d5ad38cc4d054ea6"),
    ("scenes/living_room/visual/living_room_vis.msh", "f096ef4960166a5894f62ed498b3a8afc0647112"),
    ("scenes/wall_decoration/wall_decoration_texture.png", "4c0fea35546af14253504e64b12471cbb3a5fbbc"),
];

/// Git's blob hash of `bytes` (`sha1("blob <len>\0" + bytes)`), hex.
pub fn blob_sha1(bytes: &[u8]) -> String {
    let mut h = Sha1::new();
    h.update(format!("blob {}\0", bytes.len()).as_bytes());
    h.update(bytes);
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// How a file was found.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FoundBy {
    Path,
    /// Under another name, with the upstream file's blob hash.
    BlobHash,
}

/// A file found in one of the roots.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Located {
    pub path: PathBuf,
    pub by: FoundBy,
}

/// The roots, searched in order; the content index for [`KNOWN_BLOBS`] is built on first need.
pub struct AssetTree {
    roots: Vec<PathBuf>,
    known: &'static [(&'static str, &'static str)],
    by_blob: Mutex<Option<BTreeMap<String, PathBuf>>>,
}

impl AssetTree {
    pub fn new(roots: &[Root]) -> AssetTree {
        AssetTree::with_known(roots, &KNOWN_BLOBS)
    }

    /// A tree that recognises the files of `known` (upstream path, blob hash) by content.
    pub fn with_known(roots: &[Root], known: &'static [(&'static str, &'static str)]) -> AssetTree {
        AssetTree { roots: roots.iter().map(|r| r.path.clone()).collect(), known, by_blob: Mutex::new(None) }
    }

    /// Where upstream file `rel` (relative to LIBERO's `assets/`) is, if anywhere.
    pub fn find(&self, rel: &str) -> Option<Located> {
        if let Some(path) = self.roots.iter().map(|r| r.join(rel)).find(|p| p.is_file()) {
            return Some(Located { path, by: FoundBy::Path });
        }
        let (_, blob) = self.known.iter().find(|(p, _)| *p == rel)?;
        let mut index = self.by_blob.lock().unwrap_or_else(|e| e.into_inner());
        let index = index.get_or_insert_with(|| self.index_known_blobs());
        index.get(*blob).map(|path| Located { path: path.clone(), by: FoundBy::BlobHash })
    }

    /// Blob hash -> first file (roots in order, names sorted) whose content has one of the
    /// known hashes; only files with a known file's extension are read.
    fn index_known_blobs(&self) -> BTreeMap<String, PathBuf> {
        let wanted: Vec<&str> = self.known.iter().map(|(_, h)| *h).collect();
        let exts: Vec<&str> = self.known.iter().filter_map(|(p, _)| Path::new(p).extension()?.to_str()).collect();
        let mut out = BTreeMap::new();
        for root in &self.roots {
            let mut files = Vec::new();
            walk(root, &mut files);
            files.sort();
            for f in files {
                let ext = f.extension().and_then(|e| e.to_str()).unwrap_or("");
                if !exts.contains(&ext) {
                    continue;
                }
                if let Ok(bytes) = std::fs::read(&f) {
                    let h = blob_sha1(&bytes);
                    if wanted.contains(&h.as_str()) {
                        out.entry(h).or_insert(f);
                    }
                }
            }
        }
        out
    }
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, out);
        } else {
            out.push(p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::look::discover::Origin;

    #[test]
    fn git_blob_hash_of_known_content() {
        // `printf 'hello\n' | git hash-object --stdin`
        assert_eq!(blob_sha1(b"hello\n"), "ce013625030ba8dba906f756967f9e9ca394464a");
    }

    #[test]
    fn path_first_in_root_order_then_blob_hash() {
        let tmp = tempfile::tempdir().unwrap();
        let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
        let write = |p: PathBuf, bytes: &[u8]| {
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, bytes).unwrap();
        };
        write(a.join("textures/x.png"), b"first");
        write(b.join("textures/x.png"), b"second");
        write(b.join("textures/y.png"), b"only b");
        let roots = [Root { path: a.clone(), origin: Origin::Flag }, Root { path: b.clone(), origin: Origin::Env }];
        let tree = AssetTree::new(&roots);
        assert_eq!(tree.find("textures/x.png"), Some(Located { path: a.join("textures/x.png"), by: FoundBy::Path }));
        assert_eq!(tree.find("textures/y.png").unwrap().path, b.join("textures/y.png"));
        assert_eq!(tree.find("textures/z.png"), None);
        // A known upstream file present only under another name is found by content.
        write(b.join("stable_scanned_objects/red_basket/texture.png"), b"not the basket");
        assert_eq!(tree.find("stable_scanned_objects/basket/texture.png"), None);
        static KNOWN: [(&str, &str); 1] = [("basket/texture.png", "ce013625030ba8dba906f756967f9e9ca394464a")];
        write(b.join("red_basket/texture.png"), b"hello\n");
        let tree = AssetTree::with_known(&roots, &KNOWN);
        assert_eq!(tree.find("basket/texture.png"), Some(Located { path: b.join("red_basket/texture.png"), by: FoundBy::BlobHash }));
    }
}
