//! The object catalog against LIBERO's own data: the categories the 40 BDDL files use, MuJoCo's
//! compiled masses (`meta.object_inertials` of the reference runs) and where the reference
//! objects come to rest (which checks the object frames and collision geometry together).

use serde_json::Value;
use vifo_scenes::catalog::{self, ColliderShape, ObjectKind, ObjectModel};

const REFERENCE_RUNS: [&str; 4] = [
    "libero_spatial",
    "libero_object",
    "libero_goal",
    "libero_10",
];

fn reference_run(suite: &str, test: &str) -> Option<Value> {
    let path = vifo_tests::shared(
        &format!("xval/libero_reference/{suite}_task0_init0.json"),
        test,
    )?;
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Some(serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
}

/// `akita_black_bowl_2` → `akita_black_bowl`.
fn category_of(instance: &str) -> &str {
    instance.rsplit_once('_').map_or(instance, |(head, _)| head)
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

fn rotate(q: &[f64], v: [f64; 3]) -> [f64; 3] {
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let m = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// `R · diag(d) · Rᵀ` for the rotation `q`.
fn tensor(q: &[f64], d: &[f64]) -> [[f64; 3]; 3] {
    let cols = [
        rotate(q, [1.0, 0.0, 0.0]),
        rotate(q, [0.0, 1.0, 0.0]),
        rotate(q, [0.0, 0.0, 1.0]),
    ];
    let mut t = [[0.0; 3]; 3];
    for (i, row) in t.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| cols[k][i] * d[k] * cols[k][j]).sum();
        }
    }
    t
}

#[test]
fn catalog_covers_exactly_the_categories_of_the_40_tasks() {
    let Some(root) = vifo_tests::shared(
        "libero/libero/libero/bddl_files",
        "catalog_covers_exactly_the_categories_of_the_40_tasks",
    ) else {
        return;
    };
    // Tables and floors are scene classes, not catalog entries.
    let arenas = [
        "table",
        "floor",
        "kitchen_table",
        "living_room_table",
        "study_table",
    ];
    let mut used = std::collections::BTreeSet::new();
    let mut files = 0;
    for suite in [
        "libero_spatial",
        "libero_object",
        "libero_goal",
        "libero_10",
    ] {
        let dir = root.join(suite);
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("directory entry").path();
            if path.extension().is_none_or(|e| e != "bddl") {
                continue;
            }
            let text = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            files += 1;
            for section in ["(:fixtures", "(:objects"] {
                let start = text
                    .find(section)
                    .unwrap_or_else(|| panic!("{}: no {section}", path.display()))
                    + section.len();
                let body =
                    &text[start..start + text[start..].find(')').expect("closing parenthesis")];
                let tokens: Vec<&str> = body.split_whitespace().collect();
                used.extend(
                    tokens
                        .windows(2)
                        .filter(|w| w[0] == "-")
                        .map(|w| w[1].to_string()),
                );
            }
        }
    }
    assert_eq!(files, 40);
    used.retain(|c| !arenas.contains(&c.as_str()));
    // The study scenes' own objects (hazards, the PiPER setting's cups and note) are ours, in
    // no BDDL file.
    let known: std::collections::BTreeSet<String> = catalog::CATEGORIES
        .iter()
        .filter(|c| !catalog::STUDY_CATEGORIES.contains(*c))
        .map(|c| c.to_string())
        .collect();
    assert_eq!(used, known, "BDDL categories vs catalog");
}

#[test]
fn masses_match_mujoco() {
    let mut rows = Vec::new();
    for suite in REFERENCE_RUNS {
        let Some(run) = reference_run(suite, "masses_match_mujoco") else {
            return;
        };
        let inertials = run["meta"]["object_inertials"]
            .as_object()
            .expect("object_inertials");
        for (instance, reference) in inertials {
            let model = catalog::object(category_of(instance)).unwrap_or_else(|e| panic!("{e}"));
            let subtree = reference["subtree_mass"].as_f64().expect("subtree_mass");
            let mass_err = (model.total_mass() - subtree).abs() / subtree;
            assert!(
                mass_err <= 1e-6,
                "{instance}: total mass {} vs MuJoCo {subtree}",
                model.total_mass()
            );
            // Fixtures whose root MuJoCo leaves empty (geoms on welded sub-bodies we fuse) have
            // only the subtree mass to compare.
            let body_mass = reference["body_mass"].as_f64().expect("body_mass");
            if body_mass == 0.0 {
                rows.push(format!("{instance:32} subtree mass rel err {mass_err:.1e}"));
                continue;
            }
            let ours = &model.bodies[0].inertial;
            let com = numbers(&reference["body_ipos"]);
            let diag = numbers(&reference["body_inertia_diag"]);
            let quat = numbers(&reference["body_iquat_wxyz"]);
            let com_err = (0..3)
                .map(|k| (ours.com[k] - com[k]).abs())
                .fold(0.0, f64::max);
            let diag_err = (0..3)
                .map(|k| (ours.inertia[k] - diag[k]).abs() / diag[k])
                .fold(0.0, f64::max);
            let (a, b) = (tensor(&ours.quat_wxyz, &ours.inertia), tensor(&quat, &diag));
            let tensor_err = (0..9)
                .map(|k| (a[k / 3][k % 3] - b[k / 3][k % 3]).abs())
                .fold(0.0, f64::max)
                / diag[0].max(diag[1]).max(diag[2]);
            rows.push(format!(
                "{instance:32} mass rel {:.1e}  com {com_err:.1e} m  moments rel {diag_err:.1e}  tensor rel {tensor_err:.1e}",
                (ours.mass - body_mass).abs() / body_mass
            ));
            assert!(
                (ours.mass - body_mass).abs() <= 1e-6 * body_mass,
                "{instance}: mass {} vs {body_mass}",
                ours.mass
            );
            assert!(com_err <= 1e-6, "{instance}: com {:?} vs {com:?}", ours.com);
            assert!(
                diag_err <= 1e-4,
                "{instance}: principal moments {:?} vs {diag:?}",
                ours.inertia
            );
            assert!(
                tensor_err <= 1e-4,
                "{instance}: principal axes differ ({tensor_err:.1e})"
            );
        }
    }
    println!("{}", rows.join("\n"));
}

#[test]
fn reference_objects_rest_on_their_support() {
    // Top of the surface the objects stand on in each reference scene (README of the reference runs).
    let supports = [
        ("libero_spatial", 0.90),
        ("libero_object", 0.0),
        ("libero_goal", 0.90),
        ("libero_10", 0.4368),
    ];
    for (suite, support) in supports {
        let Some(run) = reference_run(suite, "reference_objects_rest_on_their_support") else {
            return;
        };
        let last = run["steps"]
            .as_array()
            .and_then(|s| s.last())
            .expect("steps");
        for (instance, pose) in last["objects"].as_object().expect("objects") {
            if pose["kind"] != "object" {
                continue;
            }
            let model: &ObjectModel =
                catalog::object(category_of(instance)).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(model.kind, ObjectKind::Movable, "{instance}");
            let (pos, quat) = (numbers(&pose["pos"]), numbers(&pose["quat_wxyz"]));
            let lowest = lowest_point(model, &pos, &quat);
            println!(
                "{suite:15} {instance:32} lowest collision point {:+.6} m from the support",
                lowest - support
            );
            // MuJoCo's stiff contacts (solref 0.001) let objects sink a few hundredths of a mm.
            assert!(
                (lowest - support).abs() < 0.0005,
                "{suite}/{instance}: lowest point {lowest} vs support {support}"
            );
        }
    }
}

/// Lowest world z of the root body's collision boxes with the object at (`pos`, `quat`).
fn lowest_point(model: &ObjectModel, pos: &[f64], quat: &[f64]) -> f64 {
    let mut lowest = f64::INFINITY;
    for c in &model.bodies[0].colliders {
        let ColliderShape::Box { half_size: h } = c.shape else {
            continue;
        };
        for corner in 0..8 {
            let local = [0, 1, 2].map(|k| if corner >> k & 1 == 1 { h[k] } else { -h[k] });
            let in_object = rotate(&c.quat_wxyz, local);
            let p = [0, 1, 2].map(|k| c.pos[k] + in_object[k]);
            lowest = lowest.min(pos[2] + rotate(quat, p)[2]);
        }
    }
    lowest
}
