//! Catalog-wide checks: lookup, the goal-region facts the predicates depend on (numbers as
//! documented for LIBERO's predicates), joints, spawn offsets, and that every look sits where the
//! physics is.

use super::*;

fn model(category: &str) -> &'static ObjectModel {
    object(category).unwrap_or_else(|e| panic!("{e}"))
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

fn assert_site(category: &str, site: &str, body: &str, pos: [f64; 3], half: [f64; 3]) {
    let m = model(category);
    let s = m
        .site(site)
        .unwrap_or_else(|| panic!("{category} has no site {site}"));
    assert_eq!(m.bodies[s.body].name, body, "{category}/{site} body");
    assert!(
        close(&s.pos, &pos, 1e-12),
        "{category}/{site} pos {:?}",
        s.pos
    );
    assert!(
        close(&s.half_size, &half, 1e-12),
        "{category}/{site} half-size {:?}",
        s.half_size
    );
}

#[test]
fn every_category_builds_once_with_a_unique_name() {
    assert_eq!(all().len(), CATEGORIES.len());
    for (i, name) in CATEGORIES.iter().enumerate() {
        assert!(!CATEGORIES[..i].contains(name), "{name} listed twice");
        let m = model(name);
        assert_eq!(m.category, *name);
        assert_eq!(m.bodies[0].name, "main");
        assert!(m.bodies[0].parent.is_none() && m.bodies[0].joint.is_none());
        for (b, body) in m.bodies.iter().enumerate().skip(1) {
            assert!(
                body.parent.is_some_and(|p| p < b),
                "{name}/{}: parent must come first",
                body.name
            );
            assert!(
                body.joint.is_some(),
                "{name}/{}: non-root bodies are jointed",
                body.name
            );
        }
        assert!(m.total_mass() > 0.0, "{name} has no mass");
        assert!(m.sites.iter().all(|s| s.body < m.bodies.len()));
    }
    // Same address both times: built once, then shared.
    assert!(std::ptr::eq(model("plate"), model("plate")));
}

#[test]
fn unknown_category_names_itself_and_the_known_ones() {
    let err = object("toaster").unwrap_err();
    assert_eq!(err.category, "toaster");
    let text = err.to_string();
    assert!(
        text.contains("`toaster`")
            && text.contains("akita_black_bowl")
            && text.contains("desk_caddy"),
        "{text}"
    );
}

#[test]
fn goal_sites_match_libero() {
    assert_site(
        "flat_stove",
        "cook_region",
        "main",
        [0.15, 0.0, 0.0],
        [0.075, 0.075, 0.0025],
    );
    assert_site(
        "wooden_cabinet",
        "top_side",
        "main",
        [0.00354, 0.01567, 0.22152],
        [0.12534, 0.09438, 0.00147],
    );
    assert_site(
        "wine_rack",
        "top_region",
        "main",
        [0.0, -0.08003, 0.21745],
        [0.10087, 0.022, 0.00251],
    );
    assert_site(
        "basket",
        "contain_region",
        "main",
        [0.0, 0.0, 0.07185],
        [0.06108, 0.06108, 0.06949],
    );
    for (cabinet, (site, body, z)) in
        ["wooden_cabinet", "white_cabinet"]
            .into_iter()
            .flat_map(|c| {
                [
                    ("top_region", "cabinet_top", 0.18563),
                    ("middle_region", "cabinet_middle", 0.11690),
                    ("bottom_region", "cabinet_bottom", 0.04701),
                ]
                .map(|s| (c, s))
            })
    {
        assert_site(
            cabinet,
            site,
            body,
            [0.00328, 0.01128, z],
            [0.02993, 0.07561, 0.10224],
        );
        // Turned 90° about y, so its world-axis half-extent is (0.10224, 0.07561, 0.02993).
        let q = model(cabinet)
            .site(site)
            .map(|s| s.quat_wxyz)
            .unwrap_or_default();
        assert!(
            close(&q, &[0.5_f64.sqrt(), 0.0, 0.5_f64.sqrt(), 0.0], 1e-9),
            "{cabinet}/{site} quat {q:?}"
        );
    }
    assert_site(
        "desk_caddy",
        "back_contain_region",
        "main",
        [0.03364, -0.00064, 0.08558],
        [0.02775, 0.06216, 0.06046],
    );
    assert_site(
        "desk_caddy",
        "right_contain_region",
        "main",
        [0.00631, -0.14339, 0.06558],
        [0.06196, 0.06216, 0.06046],
    );
    assert_site(
        "desk_caddy",
        "left_contain_region",
        "main",
        [0.00631, 0.14551, 0.06558],
        [0.06196, 0.06216, 0.06046],
    );
    assert_site(
        "desk_caddy",
        "front_contain_region",
        "main",
        [-0.03102, -0.00064, 0.04054],
        [0.02775, 0.03595, 0.06216],
    );
    assert_site(
        "microwave",
        "heating_region",
        "main",
        [0.0, 0.01, 0.096],
        [0.12, 0.0835, 0.08],
    );
    assert_site(
        "microwave",
        "top_side",
        "main",
        [0.0, 0.01, 0.20],
        [0.12, 0.0835, 0.005],
    );
    let burner = model("flat_stove")
        .site("burner")
        .expect("burner indicator");
    assert_eq!(burner.shape, SiteShape::Cylinder);
    assert!(
        close(&burner.pos, &[0.15, 0.0, 0.022], 1e-12)
            && close(&burner.half_size, &[0.0625, 0.0625, 0.0005], 1e-12)
    );
    assert_eq!(burner.rgba, [0.9, 0.05, 0.05, 1.0]);
}

#[test]
fn articulations_match_libero() {
    for cabinet in ["wooden_cabinet", "white_cabinet"] {
        let m = model(cabinet);
        for (body, joint) in [
            ("cabinet_top", "top_level"),
            ("cabinet_middle", "middle_level"),
            ("cabinet_bottom", "bottom_level"),
        ] {
            let b = &m.bodies[m.body_index(body).expect("drawer")];
            let j = b.joint.as_ref().expect("slide");
            assert_eq!((j.kind, j.name.as_str()), (JointKind::Slide, joint));
            assert_eq!(
                (j.axis, j.range, j.damping),
                ([0.0, 1.0, 0.0], [-0.16, 0.01], 50.0)
            );
            assert_eq!((b.inertial.mass, b.inertial.inertia), (3.0, [1.0; 3]));
            assert_eq!(b.colliders.len(), 9);
        }
    }
    let stove = model("flat_stove");
    let knob = stove.bodies[stove.body_index("button").expect("knob")]
        .joint
        .as_ref()
        .expect("hinge");
    assert_eq!(
        (knob.kind, knob.axis, knob.range, knob.damping),
        (JointKind::Hinge, [0.0, 0.0, 1.0], [-0.005, 2.1], 1.0)
    );
    let micro = model("microwave");
    let door = &micro.bodies[micro.body_index("microdoorroot").expect("door")];
    assert_eq!(door.pos, [-0.1725, -0.088, 0.096]);
    let hinge = door.joint.as_ref().expect("hinge");
    assert_eq!(
        (hinge.name.as_str(), hinge.axis, hinge.range, hinge.damping),
        ("microjoint", [0.0, 0.0, 1.0], [-2.094, 0.0], 0.5)
    );
    // Door: three capsules of 20 g and a 200 g panel; shell: six 0.5 kg boxes with a 1 mm margin.
    assert!(
        (door.inertial.mass - 0.26).abs() < 1e-12
            && (micro.bodies[0].inertial.mass - 3.0).abs() < 1e-12
    );
    assert_eq!(
        door.colliders
            .iter()
            .filter(|c| matches!(c.shape, ColliderShape::Capsule { .. }))
            .count(),
        3
    );
    assert!(
        micro
            .bodies
            .iter()
            .flat_map(|b| &b.colliders)
            .all(|c| c.margin == 0.001 && c.contype == 0)
    );
}

#[test]
fn spawn_offsets_match_robosuite_sites() {
    for (category, radius) in [
        ("cream_cheese", 0.03),
        ("milk", 0.03),
        ("bbq_sauce", 0.015),
        ("butter", 0.02),
        ("plate", 0.025),
        ("flat_stove", 0.045),
        ("microwave", 0.015),
    ] {
        assert_eq!(model(category).horizontal_radius, radius, "{category}");
    }
    assert_eq!(model("akita_black_bowl").bottom_offset, [0.0, 0.0, -0.06]);
    assert_eq!(model("wooden_cabinet").top_offset, [0.0, 0.0, 0.045]);
    assert_eq!(model("butter").bottom_offset, [0.0, 0.0, -0.02]);
}

#[test]
fn surfaces_are_libero_s() {
    let bowl = &model("akita_black_bowl").bodies[0];
    assert_eq!(bowl.colliders.len(), 40);
    let c = &bowl.colliders[0];
    assert_eq!(
        (c.friction, c.solref, c.solimp),
        (
            [0.95, 0.3, 0.1],
            [0.001, 1.0],
            [0.998, 0.998, 0.001, 0.5, 2.0]
        )
    );
    // The stove's burner boxes declare nothing and get MuJoCo's defaults (density 1000 too:
    // 0.19 × 0.19 × 0.041 m of it weigh 1.4801 kg).
    let stove = &model("flat_stove").bodies[0];
    assert_eq!(stove.colliders[0].friction, [1.0, 0.005, 0.0001]);
    assert!((stove.inertial.mass - 1.4801).abs() < 1e-12);
    for m in all() {
        for c in m.bodies.iter().flat_map(|b| &b.colliders) {
            let n = c.quat_wxyz.iter().map(|v| v * v).sum::<f64>();
            assert!(
                (n - 1.0).abs() < 1e-12,
                "{}: quaternions are normalised",
                m.category
            );
        }
    }
}

#[test]
fn every_look_sits_on_its_collision_geometry() {
    // A part may stick out of its body's collision bounds by at most this much (labels, knobs,
    // rounded shapes drawn a little fuller than their boxes).
    const SLACK: f64 = 0.004;
    for m in all() {
        assert!(!m.visuals.is_empty(), "{} has no look", m.category);
        for (i, part) in m.visuals.iter().enumerate() {
            let bounds = m.collision_aabb(part.body).unwrap_or_else(|| {
                panic!(
                    "{} part {i}: body {} has no collision geometry",
                    m.category, part.body
                )
            });
            let aabb = part.aabb();
            assert!(
                aabb.within(&bounds, SLACK),
                "{} part {i} ({:?}) at {aabb:?} leaves {bounds:?}",
                m.category,
                part.recipe
            );
            assert!(part.rgba.iter().all(|c| (0.0..=1.0).contains(c)) && part.rgba[3] == 1.0);
            let n = part.quat_wxyz.iter().map(|v| v * v).sum::<f64>();
            assert!((n - 1.0).abs() < 1e-12 && part.scale.iter().all(|s| *s > 0.0));
        }
        // And the look covers the physics: the union of the parts spans most of each body's bounds.
        for body in 0..m.bodies.len() {
            let (Some(bounds), Some(look)) = (
                m.collision_aabb(body),
                m.visuals
                    .iter()
                    .filter(|p| p.body == body)
                    .map(VisualPart::aabb)
                    .reduce(|a, b| a.union(&b)),
            ) else {
                continue;
            };
            assert!(
                bounds.within(&look, 0.01),
                "{} body {body}: look {look:?} misses part of {bounds:?}",
                m.category
            );
        }
    }
}
