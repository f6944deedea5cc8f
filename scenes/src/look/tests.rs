//! A generated asset tree: real categories drawn from small valid files, broken files falling
//! back for their category only.

use std::path::Path;

use super::facts::CATEGORIES;
use super::cache::DiskCache;
use super::parts::Shape;
use super::*;

/// Writes a valid one-triangle `.msh` with UVs at `path`.
fn msh(path: &Path) {
    msh_of(path, &[[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], &[], &[[0., 0.], [1., 0.], [0., 1.]], &[[0, 1, 2]]);
}

/// Writes a `.msh` (MuJoCo's binary mesh: counts, positions, normals, UVs, faces) at `path`.
fn msh_of(path: &Path, positions: &[[f32; 3]], normals: &[[f32; 3]], uvs: &[[f32; 2]], faces: &[[u32; 3]]) {
    let mut b = Vec::new();
    for c in [positions.len(), normals.len(), uvs.len(), faces.len()] {
        b.extend_from_slice(&(c as i32).to_le_bytes());
    }
    for f in positions.iter().flatten().chain(normals.iter().flatten()).chain(uvs.iter().flatten()) {
        b.extend_from_slice(&f.to_le_bytes());
    }
    for i in faces.iter().flatten() {
        b.extend_from_slice(&(*i as i32).to_le_bytes());
    }
    write(path, &b);
}

fn png(path: &Path, rgb: [u8; 3]) {
    let img = vifo_render::RgbImage::filled(2, 2, rgb);
    write(path, &vifo_render::imageio::encode_png(&img).unwrap());
}

fn write(path: &Path, bytes: &[u8]) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// Every file of `category`, written valid.
fn category_files(root: &Path, category: &str) {
    let (_, _, facts) = CATEGORIES.iter().find(|(c, _, _)| *c == category).unwrap();
    for f in facts.iter() {
        if let Shape::Mesh { file, .. } = f.shape {
            msh(&root.join(file));
        }
        if let Some(t) = &f.material.texture {
            png(&root.join(t.file), [200, 100, 50]);
        }
    }
}

/// The look of `root`, loaded without the disk cache (tests never write to the user's).
fn look_of(root: &Path) -> Look {
    Look::load_on(roots_of(root), 2, DiskCache::default())
}

fn roots_of(root: &Path) -> Roots {
    Roots { libero: vec![Root { path: root.to_path_buf(), origin: Origin::Flag }], robot: None, notes: vec![] }
}

#[test]
fn every_fact_category_and_body_is_in_the_catalog() {
    for (category, _, facts) in CATEGORIES.iter() {
        let model = crate::catalog::object(category).unwrap();
        assert!(!facts.is_empty(), "{category}");
        for f in facts.iter() {
            assert!(model.bodies.iter().any(|b| b.name == f.body), "{category}: {}", f.body);
        }
    }
}

#[test]
fn categories_with_all_files_use_them_broken_ones_fall_back_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let root = tmp.path();
    for c in ["plate", "akita_black_bowl", "ketchup"] {
        category_files(root, c);
    }
    // The bowl's mesh is truncated, the ketchup's texture is not a PNG.
    let bowl = root.join("stable_scanned_objects/akita_black_bowl/visual/akita_black_bowl_vis.msh");
    let bytes = std::fs::read(&bowl).unwrap();
    std::fs::write(&bowl, &bytes[..bytes.len() - 3]).unwrap();
    let ketchup = root.join("stable_hope_objects/ketchup/texture_map.png");
    std::fs::write(&ketchup, b"not a png").unwrap();
    let look = look_of(root);
    let status = |c: &str| look.report().iter().find(|r| r.category == c).unwrap();
    assert_eq!(status("plate").status, Status::Assets);
    assert!(look.parts("plate").is_some_and(|p| p[0].material.texture.is_some()));
    for (c, file) in [("akita_black_bowl", bowl), ("ketchup", ketchup)] {
        let r = status(c);
        assert_eq!(r.status, Status::BuiltIn, "{c}");
        let problem = r.problem.as_deref().unwrap();
        assert!(problem.contains(&file.display().to_string()), "{c}: {problem}");
        assert!(look.parts(c).is_none());
    }
    let missing = status("milk");
    assert_eq!(missing.status, Status::BuiltIn);
    assert!(missing.problem.as_deref().unwrap().contains("not found in any asset folder"));
    assert!(look.is_used());
    assert!(look.label().starts_with("libero-assets:") && look.hash().len() == 16);
}

#[test]
fn loading_on_several_threads_gives_the_same_look() {
    let tmp = tempfile::tempdir().unwrap();
    for (category, _, _) in CATEGORIES.iter().take(14) {
        category_files(tmp.path(), category);
    }
    let ketchup = tmp.path().join("stable_hope_objects/ketchup/texture_map.png");
    std::fs::write(&ketchup, b"not a png").unwrap();
    let one = Look::load_on(roots_of(tmp.path()), 1, DiskCache::default());
    let report = |look: &Look| serde_json::to_string(look.report()).unwrap();
    for threads in [2, 4] {
        let many = Look::load_on(roots_of(tmp.path()), threads, DiskCache::default());
        assert_eq!(report(&many), report(&one), "{threads} threads");
        assert_eq!(many.hash(), one.hash());
        for (category, _, _) in CATEGORIES.iter() {
            assert_eq!(many.parts(category), one.parts(category), "{category}, {threads} threads");
        }
    }
    assert!(one.report().iter().filter(|r| r.status == Status::Assets).count() >= 10, "{}", report(&one));
    assert!(one.report().iter().any(|r| r.problem.as_deref().is_some_and(|p| p.contains("texture_map.png"))));
}

#[test]
fn a_look_read_from_the_cache_is_the_look_made_from_the_files() {
    let tmp = tempfile::tempdir().unwrap();
    for (category, _, _) in CATEGORIES.iter().take(14) {
        category_files(tmp.path(), category);
    }
    // The plate's mesh dense enough for coarser copies: a 3 cm sphere with UVs.
    let (_, _, plate) = CATEGORIES.iter().find(|(c, _, _)| *c == "plate").unwrap();
    let file = plate.iter().find_map(|f| if let Shape::Mesh { file, .. } = f.shape { Some(file) } else { None }).expect("the plate has a mesh");
    let sphere = vifo_render::Mesh::sphere(0.03, 96);
    let uvs: Vec<[f32; 2]> = sphere.positions().iter().map(|p| [p.x * 10.0 + 0.5, p.y * 10.0 + 0.5]).collect();
    let vec3s = |v: &[vifo_render::glam::Vec3]| v.iter().map(|p| p.to_array()).collect::<Vec<_>>();
    msh_of(&tmp.path().join(file), &vec3s(sphere.positions()), &vec3s(sphere.normals()), &uvs, sphere.triangles());
    std::fs::write(tmp.path().join("stable_hope_objects/ketchup/texture_map.png"), b"not a png").unwrap();
    let cache = tempfile::tempdir().unwrap();
    let fresh = look_of(tmp.path());
    let first = Look::load_on(roots_of(tmp.path()), 2, DiskCache::at(Some(cache.path().to_path_buf())));
    let second = Look::load_on(roots_of(tmp.path()), 2, DiskCache::at(Some(cache.path().to_path_buf())));
    let report = |look: &Look| serde_json::to_string(look.report()).unwrap();
    // Files of equal content share entries, so the first load already reads some.
    let asked = first.cache().made + first.cache().read;
    assert!(first.cache().made >= 4 && first.cache().problem.is_none(), "{:?}", first.cache());
    assert_eq!((second.cache().read, second.cache().made), (asked, 0), "everything made the first time is read the second");
    for look in [&first, &second] {
        assert_eq!(report(look), report(&fresh));
        assert_eq!(look.hash(), fresh.hash());
        for (category, _, _) in CATEGORIES.iter() {
            assert_eq!(look.parts(category), fresh.parts(category), "{category}");
        }
        assert!(look.announcement("x").iter().all(|l| !l.contains("cache")));
    }
    assert!(second.parts("plate").unwrap().iter().any(|p| p.lods.len() >= 2), "the plate has coarser copies, read from the cache");
    assert!(report(&second).contains("texture_map.png"), "a broken file is still reported when the rest comes from the cache");
}

#[test]
fn the_hash_follows_the_content() {
    let tmp = tempfile::tempdir().unwrap();
    category_files(tmp.path(), "plate");
    let a = look_of(tmp.path()).hash().to_string();
    assert_eq!(look_of(tmp.path()).hash(), a);
    png(&tmp.path().join("stable_scanned_objects/plate/texture.png"), [1, 2, 3]);
    assert_ne!(look_of(tmp.path()).hash(), a);
    let empty = tempfile::tempdir().unwrap();
    let none = look_of(empty.path());
    assert!(!none.is_used());
    assert_eq!(none.label(), BUILT_IN);
}

#[test]
fn every_panda_fact_body_is_a_robot_body() {
    let model = vifo_robots::panda::model(vifo_robots::panda::Mount::Pedestal);
    // The pedestal's parts (`mount`) are drawn on the base of a mounted arm.
    for f in super::facts::PANDA {
        let body = if f.body == super::MOUNT { "base" } else { f.body };
        assert!(model.bodies.iter().any(|b| b.name == body), "{}", f.body);
    }
    assert!(super::facts::PANDA.iter().any(|f| f.body == super::MOUNT), "the pedestal's parts are in the facts");
}
