//! The render crate's loaders on LIBERO's own asset files (skipped when `../shared` is absent).

use std::path::{Path, PathBuf};

use vifo_render::assets::{load_mesh, load_texture_png, parse_msh};
use vifo_tests::shared;

const ASSETS: &str = "libero/libero/libero/assets";

/// Files under `dir` (recursively) with extension `ext`, sorted.
fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let p = entry.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().and_then(|e| e.to_str()) == Some(ext) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn every_libero_mesh_loads() {
    let Some(root) = shared(ASSETS, "every_libero_mesh_loads") else { return };
    let mut counts = Vec::new();
    for ext in ["msh", "stl", "obj"] {
        let paths = files(&root, ext);
        for path in &paths {
            let mesh = load_mesh(path).unwrap_or_else(|e| panic!("{e}"));
            assert!(mesh.triangle_count() > 0, "{}", path.display());
            let b = mesh.bounds();
            // LIBERO meshes are object-sized before their XML scale (at most a few metres,
            // the kitchen backdrop excepted, which is in centimetres).
            assert!(b.radius.is_finite() && b.radius > 0.0 && b.radius < 1000.0, "{}: {b:?}", path.display());
        }
        counts.push((ext, paths.len()));
    }
    println!("loaded {counts:?}");
    assert!(counts[0].1 >= 40 && counts[1].1 >= 7 && counts[2].1 >= 2, "{counts:?}");
}

#[test]
fn textured_msh_keeps_its_uvs() {
    let Some(path) = shared(&format!("{ASSETS}/turbosquid_objects/wine_bottle/visual/wine_bottle_red_logo_vis.msh"), "textured_msh_keeps_its_uvs") else {
        return;
    };
    let mesh = load_mesh(&path).unwrap();
    let uvs = mesh.uvs().expect("this .msh stores texture coordinates");
    assert!(uvs.iter().all(|t| t.is_finite()));
    assert_eq!(uvs.len(), mesh.vertex_count());
}

#[test]
fn truncated_libero_msh_is_an_error_naming_the_file() {
    let Some(path) = shared(&format!("{ASSETS}/articulated_objects/flat_stove/stove_knob_base/visual/stove_knob_base_vis.msh"), "truncated_libero_msh") else {
        return;
    };
    let bytes = std::fs::read(&path).unwrap();
    let e = parse_msh(&bytes[..bytes.len() - 7], "stove_knob_base_vis.msh").unwrap_err();
    assert_eq!(e.file, "stove_knob_base_vis.msh");
    assert!(e.problem.contains(&format!("file has {}", bytes.len() - 7)), "{e}");
    assert!(parse_msh(&bytes, "ok").is_ok());
}

#[test]
fn libero_textures_load_with_mipmaps() {
    let Some(dir) = shared(&format!("{ASSETS}/textures"), "libero_textures_load_with_mipmaps") else { return };
    for path in files(&dir, "png") {
        let t = load_texture_png(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(t.width() >= 64 && t.height() >= 64, "{}", path.display());
        assert!(t.level_count() > 5);
    }
    let bad = load_texture_png(dir.join("no_such_texture.png")).unwrap_err();
    assert!(bad.to_string().contains("no_such_texture.png"));
}
