//! The scene classes agree with the compiled MuJoCo models of LIBERO (`model_facts.json`).

use serde_json::Value;
use vifo_scenes::scene_class::scene_class;
use vifo_scenes::task::ProblemClass;

fn vec_of(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// World-frame axis-aligned half-size and centre of a box geom (`size` = half-extents).
fn world_box(geom: &Value) -> ([f64; 3], [f64; 3]) {
    let size = vec_of(&geom["size"]);
    let m = vec_of(&geom["world_xmat"]);
    let half = [0, 1, 2].map(|r| (0..3).map(|c| m[3 * r + c].abs() * size[c]).sum());
    let pos = vec_of(&geom["world_pos"]);
    (half, [pos[0], pos[1], pos[2]])
}

fn assert_close(what: &str, ours: &[f64], theirs: &[f64], tol: f64) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    for (a, b) in ours.iter().zip(theirs) {
        assert!((a - b).abs() <= tol, "{what}: ours {ours:?}, MuJoCo {theirs:?}");
    }
}

#[test]
fn scene_classes_match_the_compiled_models() {
    let test = "scene_classes_match_the_compiled_models";
    let Some(path) = vifo_tests::shared("xval/libero_reference/model_facts.json", test) else {
        return;
    };
    let facts: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let scenes = facts["scenes"].as_object().unwrap();
    assert_eq!(scenes.len(), 5);
    for (name, scene) in scenes {
        let problem = ProblemClass::from_name(name).unwrap();
        let class = scene_class(problem).unwrap();
        assert_eq!(vec_of(&scene["workspace_offset"]), class.workspace_offset, "{name}");
        assert_eq!(vec_of(&scene["robot_base_world_pos"]), class.robot_base.pos, "{name}");
        assert_eq!(vec_of(&scene["robot_base_world_quat_wxyz"]), class.robot_base.quat_wxyz, "{name}");
        let agentview = &scene["cameras"]["agentview"];
        assert_eq!(vec_of(&agentview["world_pos_at_init"]), class.agentview.pose.pos, "{name}");
        assert_eq!(vec_of(&agentview["world_quat_wxyz_at_init"]), class.agentview.pose.quat_wxyz, "{name}");
        assert_eq!(agentview["fovy_deg"].as_f64().unwrap(), class.agentview.fovy_deg, "{name}");
        let bodies = scene["robot_and_table_bodies"].as_object().unwrap();
        assert_eq!(bodies.contains_key("mount0_pedestal"), class.robot_on_mount, "{name}");

        let geoms = scene["scene_geoms"].as_array().unwrap();
        let floor = geoms.iter().find(|g| g["name"] == "floor").unwrap();
        assert_eq!(vec_of(&floor["friction"]), class.floor.friction, "{name}");
        // The table top: the colliding box geoms (floor aside) that reach the highest z.
        let boxes: Vec<([f64; 3], [f64; 3], &Value)> = geoms
            .iter()
            .filter(|g| g["name"] != "floor" && g["contype"].as_i64() != Some(0) && g["type"].as_i64() == Some(6))
            .map(|g| {
                let (half, center) = world_box(g);
                (half, center, g)
            })
            .collect();
        let highest = boxes.iter().map(|(h, c, _)| c[2] + h[2]).fold(f64::NEG_INFINITY, f64::max);
        let top: Vec<_> = boxes.iter().filter(|(h, c, _)| (c[2] + h[2] - highest).abs() < 1e-9).collect();
        match class.table {
            None => assert!(top.is_empty(), "{name}: MuJoCo has a table"),
            Some(table) => {
                assert_eq!(top.len(), table.top.len(), "{name}: number of top slabs");
                for (slab, (half, center, geom)) in table.top.iter().zip(&top) {
                    assert_close(&format!("{name} slab half-size"), &slab.half_size, half, 1e-12);
                    assert_close(&format!("{name} slab centre"), &slab.center, center, 1e-9);
                    assert_eq!(vec_of(&geom["friction"]), table.friction, "{name}");
                }
            }
        }
    }
}
