//! Behaviour of cue insertion: every variant draws, drawings sit on their anchors, the
//! off-screen rule, determinism, resolution independence, codes that decode, and errors that
//! leave the frame alone.

use vifo_cues::draw::fiducial;
use vifo_cues::families::code::{action_code, fiducial_id};
use vifo_cues::variants::{self, Needs};
use vifo_cues::{
    Anchor, AnchorUse, Anchors, CueError, CueParams, CueSpec, Family, FrameInputs, InsertMode, Inserter, NormBox,
    RgbImage, RgbaImage, VARIANTS, Variant, parse,
};

const W: u32 = 256;
const SRC: (f64, f64) = (70.0, 160.0);
const TGT: (f64, f64) = (185.0, 110.0);

fn base(w: u32, h: u32) -> RgbImage {
    // A mild vertical gradient so "changed" is not confused with "equal to a flat colour".
    let mut img = RgbImage::new(w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            let i = ((y * w + x) * 3) as usize;
            img.data[i..i + 3].copy_from_slice(&[110, (100 + y * 40 / h) as u8, 120]);
        }
    }
    img
}

fn anchors() -> Anchors {
    Anchors {
        source: Some(Anchor::at(SRC.0, SRC.1).with_radius(16.0)),
        target: Some(Anchor::at(TGT.0, TGT.1).with_radius(22.0)),
    }
}

/// A disc layer of the frame size (a "rendered future pose").
fn disc(w: u32, h: u32, cx: f32, cy: f32, r: f32) -> RgbaImage {
    let mut img = RgbaImage::new(w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            if (x as f32 - cx).powi(2) + (y as f32 - cy).powi(2) <= r * r {
                let i = ((y * w + x) * 4) as usize;
                img.data[i..i + 4].copy_from_slice(&[30, 30, 35, 255]);
            }
        }
    }
    img
}

fn ghosts(w: u32, h: u32) -> Vec<RgbaImage> {
    (1..=4)
        .map(|i| {
            let t = i as f32 / 4.0;
            disc(
                w,
                h,
                (SRC.0 as f32 + (TGT.0 - SRC.0) as f32 * t) * w as f32 / 256.0,
                (SRC.1 as f32 + (TGT.1 - SRC.1) as f32 * t) * h as f32 / 256.0,
                12.0,
            )
        })
        .collect()
}

fn pictures() -> Vec<RgbaImage> {
    vec![disc(200, 200, 60.0, 120.0, 20.0), disc(200, 200, 140.0, 80.0, 20.0)]
}

fn spec_for(instruction: &str, v: &Variant) -> CueSpec {
    let parsed = parse(instruction).unwrap();
    let step = parsed.steps.iter().position(|s| s.target.is_some()).unwrap_or(0);
    CueSpec::new("test/0", &parsed, step, v).unwrap()
}

const TASK: &str = "pick up the black bowl next to the plate and place it on the plate";

fn changed(a: &RgbImage, b: &RgbImage) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (i, (p, q)) in a.data.chunks_exact(3).zip(b.data.chunks_exact(3)).enumerate() {
        let d: i32 = p.iter().zip(q).map(|(x, y)| (*x as i32 - *y as i32).abs()).sum();
        if d > 24 {
            out.push((i as u32 % a.width, i as u32 / a.width));
        }
    }
    out
}

fn insert(spec: &CueSpec, frame: &mut RgbImage, inputs: &FrameInputs<'_>) -> Result<vifo_cues::InsertReport, CueError> {
    Inserter::new().insert(frame, spec, inputs)
}

#[test]
fn catalogue_has_enough_distinct_variants() {
    assert!(VARIANTS.len() >= 33, "{} variants", VARIANTS.len());
    for family in Family::ALL {
        assert!(variants::of_family(family).count() >= 3, "{family} has fewer than 3 variants");
    }
    for (i, v) in VARIANTS.iter().enumerate() {
        assert!(v.name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'), "{}", v.name);
        assert!(!v.description.is_empty() && !v.description.contains('\n'));
        assert!(VARIANTS[i + 1..].iter().all(|o| o.name != v.name), "duplicate {}", v.name);
    }
}

#[test]
fn every_variant_draws_something_visible_for_in_view_anchors() {
    let (g, p) = (ghosts(W, W), pictures());
    let inputs = FrameInputs { anchors: anchors(), ghost_layers: &g, pictures: &p };
    let frame0 = base(W, W);
    for v in VARIANTS {
        let spec = spec_for(TASK, v);
        let mut frame = frame0.clone();
        let report = insert(&spec, &mut frame, &inputs).unwrap_or_else(|e| panic!("{}: {e}", v.name));
        let diff = changed(&frame0, &frame);
        assert!(report.drawn, "{}", v.name);
        assert!(diff.len() >= 150, "{} changed only {} pixels", v.name, diff.len());
        assert!(report.source != AnchorUse::Skipped && report.target != AnchorUse::Skipped, "{}: {report:?}", v.name);
    }
}

/// Fraction of changed pixels within `r` of a point.
fn changed_near(diff: &[(u32, u32)], at: (f64, f64), r: f64) -> usize {
    diff.iter().filter(|(x, y)| (*x as f64 - at.0).hypot(*y as f64 - at.1) <= r).count()
}

#[test]
fn scene_anchored_cues_sit_on_their_anchors() {
    let inputs = FrameInputs::anchored(anchors());
    let frame0 = base(W, W);
    for v in VARIANTS.iter().filter(|v| v.family.insert_mode() == InsertMode::SceneAnchored) {
        let spec = spec_for(TASK, v);
        let mut frame = frame0.clone();
        insert(&spec, &mut frame, &inputs).unwrap();
        let diff = changed(&frame0, &frame);
        let near = changed_near(&diff, SRC, 45.0) + changed_near(&diff, TGT, 50.0);
        assert!(near > 0, "{} draws nothing near its anchors", v.name);
        // Most of the drawing is around the objects or between them (signs stand on posts,
        // hands reach in from the side, so allow a generous band).
        let local = diff
            .iter()
            .filter(|(x, y)| {
                let (x, y) = (*x as f64, *y as f64);
                let d_line = segment_distance((x, y), SRC, TGT);
                d_line < 90.0
            })
            .count();
        if v.name != "dim_surround" && v.name != "spotlight_cone" {
            assert!(
                local * 10 >= diff.len() * 8,
                "{}: only {local} of {} changed pixels near the objects",
                v.name,
                diff.len()
            );
        }
    }
}

fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

fn pixel(img: &RgbImage, at: (f64, f64)) -> [u8; 3] {
    img.pixel(at.0 as u32, at.1 as u32).unwrap()
}

#[test]
fn arrows_start_at_the_source_and_end_at_the_target() {
    let inputs = FrameInputs::anchored(anchors());
    let spec = spec_for(TASK, variants::find("straight_arrow_red").unwrap());
    let mut frame = base(W, W);
    insert(&spec, &mut frame, &inputs).unwrap();
    let red = |c: [u8; 3]| c[0] > 180 && c[1] < 90 && c[2] < 90;
    assert!(red(pixel(&frame, SRC)), "tail dot on the source");
    // Just before the tip, on the shaft line, the arrow is red; just past the tip it is not.
    let (dx, dy) = (TGT.0 - SRC.0, TGT.1 - SRC.1);
    let len = dx.hypot(dy);
    let before = (TGT.0 - dx / len * 5.0, TGT.1 - dy / len * 5.0);
    let after = (TGT.0 + dx / len * 6.0, TGT.1 + dy / len * 6.0);
    assert!(red(pixel(&frame, before)), "tip reaches the target");
    assert!(!red(pixel(&frame, after)), "tip stops at the target");
}

#[test]
fn highlights_are_brightest_on_the_anchored_object() {
    let inputs = FrameInputs::anchored(anchors());
    for name in ["glow_halo", "spotlight_cone", "rim_light"] {
        let spec = spec_for(TASK, variants::find(name).unwrap());
        let frame0 = base(W, W);
        let mut frame = frame0.clone();
        insert(&spec, &mut frame, &inputs).unwrap();
        let lum = |img: &RgbImage, at: (f64, f64)| -> i32 { pixel(img, at).iter().map(|&c| c as i32).sum() };
        // Around the source rim the image got brighter; far away (bottom right) it did not.
        let rim = (SRC.0 + 16.0 * 1.2, SRC.1);
        assert!(lum(&frame, rim) > lum(&frame0, rim) + 60, "{name} does not light the source");
        assert_eq!(pixel(&frame, (240.0, 240.0)), pixel(&frame0, (240.0, 240.0)), "{name} spills over the frame");
    }
    let spec = spec_for(TASK, variants::find("dim_surround").unwrap());
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    insert(&spec, &mut frame, &inputs).unwrap();
    assert_eq!(pixel(&frame, SRC), pixel(&frame0, SRC), "the source stays lit");
    assert!(pixel(&frame, (240.0, 20.0))[1] < pixel(&frame0, (240.0, 20.0))[1] / 2, "the surround is dimmed");
}

#[test]
fn same_inputs_give_the_same_bytes() {
    let (g, p) = (ghosts(W, W), pictures());
    let inputs = FrameInputs { anchors: anchors(), ghost_layers: &g, pictures: &p };
    let mut cached = Inserter::new();
    for v in VARIANTS {
        let spec = spec_for(TASK, v);
        let mut a = base(W, W);
        let mut b = base(W, W);
        let mut c = base(W, W);
        Inserter::new().insert(&mut a, &spec, &inputs).unwrap();
        cached.insert(&mut b, &spec, &inputs).unwrap();
        cached.insert(&mut c, &spec, &inputs).unwrap();
        assert!(a == b && b == c, "{} is not deterministic", v.name);
    }
}

/// A kept panel is used again only for the same pictures: a picture changed anywhere (here in
/// every pixel but each ninth, the ones a sampled fingerprint would read) gives a new panel.
#[test]
fn a_changed_picture_is_not_drawn_from_the_kept_panel() {
    let p = pictures();
    let mut q = p.clone();
    let last = q.last_mut().unwrap();
    for (i, px) in last.data.chunks_exact_mut(4).enumerate() {
        if i % 9 != 0 {
            px.copy_from_slice(&[220, 30, 30, 255]);
        }
    }
    let mut kept = Inserter::new();
    for name in ["goal_inset", "goal_polaroid"] {
        let spec = spec_for(TASK, variants::find(name).unwrap());
        let draw = |inserter: &mut Inserter, pictures: &[RgbaImage]| {
            let mut frame = base(W, W);
            inserter.insert(&mut frame, &spec, &FrameInputs { pictures, ..FrameInputs::default() }).unwrap();
            frame
        };
        let before = draw(&mut kept, &p);
        let after = draw(&mut kept, &q);
        let fresh = draw(&mut Inserter::new(), &q);
        assert!(before != fresh, "{name}: the change does not show");
        assert!(after == fresh, "{name}: drawn from the panel of the earlier picture");
    }
}

/// A far anchor is clamped where the line from the image centre towards it meets the inset
/// border, not into the nearest corner (an arrow to it keeps its direction).
#[test]
fn a_far_anchor_is_clamped_in_its_direction() {
    let spec = spec_for(TASK, variants::find("glow_halo").unwrap());
    // 3,128 px left and 228 px up of the centre: about 4° above the horizontal.
    let off = Anchors { source: Some(Anchor::at(-3000.0, -100.0).with_radius(16.0)), ..anchors() };
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    assert_eq!(insert(&spec, &mut frame, &FrameInputs::anchored(off)).unwrap().source, AnchorUse::Clamped);
    let diff = changed(&frame0, &frame);
    let (ys, n) = diff.iter().fold((0, 0), |(s, n), (_, y)| (s + y, n + 1));
    let mean_y = ys as f32 / n as f32;
    assert!((100.0..140.0).contains(&mean_y), "the glow sits at mean row {mean_y}, expected about 120 (the corner is row 15)");
}

/// Tiny frames (down to 1×1) give a drawing or an error, never a panic.
#[test]
fn every_variant_survives_tiny_frames() {
    for side in 1..=40u32 {
        let (g, p) = (ghosts(side, side), pictures());
        let inputs = FrameInputs { anchors: anchors(), ghost_layers: &g, pictures: &p };
        for v in VARIANTS {
            let spec = spec_for(TASK, v);
            let mut frame = base(side, side);
            let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| insert(&spec, &mut frame, &inputs)))
                .unwrap_or_else(|_| panic!("{} panicked on a {side}x{side} frame", v.name));
        }
    }
}

/// Specs that share a task key but not their content (another instruction, other objects) are
/// drawn as a fresh inserter draws each, never from the other's kept captions, codes or labels.
#[test]
fn specs_sharing_a_task_key_do_not_share_drawings() {
    let other = "pick up the ketchup and place it in the basket";
    let mut kept = Inserter::new();
    for v in VARIANTS {
        let inputs = FrameInputs::anchored(anchors());
        for task in [TASK, other, TASK] {
            let Ok(spec) = CueSpec::new("test/0", &parse(task).unwrap(), 0, v) else { continue };
            let (mut want, mut got) = (base(W, W), base(W, W));
            let fresh = Inserter::new().insert(&mut want, &spec, &inputs);
            assert_eq!(fresh.ok(), kept.insert(&mut got, &spec, &inputs).ok(), "{}", v.name);
            assert!(got == want, "{}: {task:?} drawn from another spec's drawing", v.name);
        }
    }
}

/// The inserter keeps the layers it drew from anchors alone: frames of two cameras, one whose
/// anchors move and one whose stay, over two backgrounds, must come out as a fresh inserter
/// draws them. Variants that need ghost layers or pictures fail without them and are skipped.
#[test]
fn kept_layers_give_the_bytes_of_a_fresh_draw() {
    let moved = |k: u32| Anchors {
        source: Some(Anchor::at(SRC.0 + f64::from(k % 2) * 9.0, SRC.1).with_radius(16.0)),
        target: Some(Anchor::at(TGT.0, TGT.1).with_radius(22.0)),
    };
    let mut dark = base(W, W);
    dark.data.iter_mut().for_each(|c| *c /= 3);
    let mut kept = Inserter::new();
    for v in VARIANTS {
        let spec = spec_for(TASK, v);
        for k in 0..6 {
            for (camera, anchors) in [("still", anchors()), ("moving", moved(k / 2))] {
                let background = if k % 3 == 0 { &dark } else { &base(W, W) };
                let inputs = FrameInputs::anchored(anchors);
                let (mut want, mut got) = (background.clone(), background.clone());
                let fresh = Inserter::new().insert(&mut want, &spec, &inputs);
                let again = kept.insert(&mut got, &spec, &inputs);
                assert_eq!(fresh.is_ok(), again.is_ok(), "{}", v.name);
                assert_eq!(fresh.ok(), again.ok(), "{}", v.name);
                assert!(got == want, "{}: frame {k} of the {camera} camera differs from a fresh draw", v.name);
            }
        }
    }
}

#[test]
fn anchors_outside_the_image_are_clamped_with_an_indicator() {
    let spec = spec_for(TASK, variants::find("glow_halo").unwrap());
    let off = Anchors { source: Some(Anchor::at(-50.0, 128.0).with_radius(16.0)), ..anchors() };
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    let report = insert(&spec, &mut frame, &FrameInputs::anchored(off)).unwrap();
    assert_eq!(report.source, AnchorUse::Clamped);
    let diff = changed(&frame0, &frame);
    // Everything drawn hugs the left border (6 % inset = 15 px, plus the glow).
    assert!(!diff.is_empty() && diff.iter().all(|(x, _)| *x < 60), "{:?}", diff.iter().max());
    // The indicator: a white-rimmed triangle right at the clamped point, pointing left.
    let white = diff
        .iter()
        .filter(|(x, y)| *x < 30 && (118..138).contains(y))
        .filter(|(x, y)| frame.pixel(*x, *y).unwrap().iter().all(|&c| c > 230))
        .count();
    assert!(white > 3, "no indicator rim near the clamped point");
}

#[test]
fn anchors_behind_the_camera_are_skipped() {
    let frame0 = base(W, W);
    let behind = Anchors { target: Some(Anchor { in_front: false, ..Anchor::at(TGT.0, TGT.1) }), ..anchors() };
    // An arrow needs both ends: nothing is drawn and the frame is unchanged.
    let arrow = spec_for(TASK, variants::find("straight_arrow_red").unwrap());
    let mut frame = frame0.clone();
    let report = insert(&arrow, &mut frame, &FrameInputs::anchored(behind)).unwrap();
    assert_eq!((report.source, report.target, report.drawn), (AnchorUse::InView, AnchorUse::Skipped, false));
    assert_eq!(frame, frame0);
    // Two spotlights: the source one is still drawn.
    let dual = spec_for(TASK, variants::find("dual_spotlights").unwrap());
    let mut frame = frame0.clone();
    let report = insert(&dual, &mut frame, &FrameInputs::anchored(behind)).unwrap();
    assert!(report.drawn && report.target == AnchorUse::Skipped);
    let diff = changed(&frame0, &frame);
    assert!(changed_near(&diff, SRC, 40.0) > 100 && changed_near(&diff, TGT, 20.0) == 0);
    // No anchors at all: a scene-anchored cue leaves the frame alone.
    let mut frame = frame0.clone();
    let report = insert(&dual, &mut frame, &FrameInputs::default()).unwrap();
    assert_eq!((report.source, report.drawn), (AnchorUse::Skipped, false));
    assert_eq!(frame, frame0);
}

/// Bounding box of changed pixels in normalised coordinates.
fn normalised_bbox(a: &RgbImage, b: &RgbImage) -> [f64; 4] {
    let diff = changed(a, b);
    let (w, h) = (a.width as f64, a.height as f64);
    let xs = diff.iter().map(|p| p.0 as f64 / w);
    let ys = diff.iter().map(|p| p.1 as f64 / h);
    [xs.clone().fold(1.0, f64::min), ys.clone().fold(1.0, f64::min), xs.fold(0.0, f64::max), ys.fold(0.0, f64::max)]
}

#[test]
fn fixed_region_cues_keep_their_layout_across_resolutions() {
    let p = pictures();
    for v in VARIANTS.iter().filter(|v| v.family.insert_mode() == InsertMode::FixedRegion) {
        let spec = spec_for(TASK, v);
        let boxes: Vec<[f64; 4]> = [128u32, 256, 512]
            .iter()
            .map(|&s| {
                let frame0 = base(s, s);
                let mut frame = frame0.clone();
                insert(&spec, &mut frame, &FrameInputs { pictures: &p, ..FrameInputs::default() }).unwrap();
                normalised_bbox(&frame0, &frame)
            })
            .collect();
        for b in &boxes[1..] {
            for k in 0..4 {
                assert!((b[k] - boxes[0][k]).abs() < 0.04, "{}: {:?} vs {:?}", v.name, b, boxes[0]);
            }
        }
    }
    // A region parameter moves the cue.
    let mut spec = spec_for(TASK, variants::find("caption_bar").unwrap());
    spec.params.region = Some(NormBox::new(0.0, 0.0, 0.5, 0.25));
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    insert(&spec, &mut frame, &FrameInputs::default()).unwrap();
    let b = normalised_bbox(&frame0, &frame);
    assert!(b[2] < 0.51 && b[3] < 0.26, "{b:?}");
}

/// Decodes every QR code in the frame.
fn decode_qr(img: &RgbImage) -> Vec<String> {
    let mut prepared = rqrr::PreparedImage::prepare_from_greyscale(img.width as usize, img.height as usize, |x, y| {
        let p = img.pixel(x as u32, y as u32).unwrap();
        ((p[0] as u32 * 3 + p[1] as u32 * 6 + p[2] as u32) / 10) as u8
    });
    prepared.detect_grids().into_iter().filter_map(|g| g.decode().ok().map(|(_, s)| s)).collect()
}

#[test]
fn qr_payloads_round_trip() {
    let instructions = [
        TASK,
        "put the white mug on the left plate and put the yellow and white mug on the right plate",
        "turn on the stove",
        "pick up the black bowl between the plate and the ramekin and place it on the plate",
    ];
    for instruction in instructions {
        let mut frame = base(W, W);
        let spec = spec_for(instruction, variants::find("qr_instruction").unwrap());
        insert(&spec, &mut frame, &FrameInputs::default()).unwrap();
        assert_eq!(decode_qr(&frame), [instruction.to_string()]);

        let mut frame = base(W, W);
        let spec = spec_for(instruction, variants::find("qr_json").unwrap());
        insert(&spec, &mut frame, &FrameInputs::default()).unwrap();
        let decoded = decode_qr(&frame);
        assert_eq!(decoded.len(), 1, "{instruction}");
        let json: serde_json::Value = serde_json::from_str(&decoded[0]).unwrap();
        let parsed = parse(instruction).unwrap();
        assert_eq!(json["task"], "test/0");
        assert_eq!(json["steps"].as_array().unwrap().len(), parsed.steps.len());
        assert_eq!(json["steps"][0]["source"], parsed.steps[0].source);
        assert_eq!(json["steps"][0]["relation"], parsed.steps[0].relation.name());
        // The locating phrase, where there is one, says which of two alike objects is meant.
        assert_eq!(json["steps"][0]["source_qualifier"].as_str(), parsed.steps[0].source_qualifier.as_deref(), "{instruction}");
    }
}

#[test]
fn fiducial_tag_reads_back_from_the_frame() {
    let spec = spec_for(TASK, variants::find("fiducial_tag").unwrap());
    let mut frame = base(W, W);
    insert(&spec, &mut frame, &FrameInputs::default()).unwrap();
    // Default region (0.74, 0.02, 0.24 wide): the tag square starts at the region's top-left.
    let (x0, y0, w, h) = NormBox::new(0.74, 0.02, 0.24, 0.3).to_pixels(W, W);
    let side = w.min((h as f32 * 0.8) as u32);
    let mut rgba = Vec::new();
    for y in 0..side {
        for x in 0..side {
            let p = frame.pixel(x0 as u32 + (w - side) / 2 + x, y0 as u32 + y).unwrap();
            rgba.extend_from_slice(&[p[0], p[1], p[2], 255]);
        }
    }
    let d = fiducial::decode(fiducial::read(&rgba, side).unwrap()).expect("tag decodes");
    assert_eq!((d.id, d.rotation, d.errors), (fiducial_id(&spec), 0, 0));
    assert_eq!(action_code(&spec), "ON:BOWL>PLATE");
}

#[test]
fn ghost_layers_are_composited_with_their_alphas() {
    let spec = spec_for(TASK, variants::find("ghost_fade").unwrap());
    let g = ghosts(W, W);
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    let mut custom = spec.clone();
    custom.params.alphas = Some(vec![0.0, 0.0, 0.0, 1.0]);
    insert(&custom, &mut frame, &FrameInputs { ghost_layers: &g, ..FrameInputs::default() }).unwrap();
    // Only the last pose shows, fully opaque.
    assert_eq!(pixel(&frame, TGT), [30, 30, 35]);
    let first = (SRC.0 + (TGT.0 - SRC.0) * 0.25, SRC.1 + (TGT.1 - SRC.1) * 0.25);
    assert_eq!(pixel(&frame, first), pixel(&frame0, first));
    // Default ramp: later poses are darker (more opaque) than earlier ones.
    let mut frame = frame0.clone();
    insert(&spec, &mut frame, &FrameInputs { ghost_layers: &g, ..FrameInputs::default() }).unwrap();
    let mid = (SRC.0 + (TGT.0 - SRC.0) * 0.5, SRC.1 + (TGT.1 - SRC.1) * 0.5);
    assert!(pixel(&frame, TGT)[1] < pixel(&frame, mid)[1] && pixel(&frame, mid)[1] < pixel(&frame, first)[1]);
    // Wrong number of alphas or a wrong layer size are errors.
    custom.params.alphas = Some(vec![0.5]);
    assert!(matches!(
        insert(&custom, &mut frame.clone(), &FrameInputs { ghost_layers: &g, ..FrameInputs::default() }),
        Err(CueError::BadParam(_))
    ));
    let small = ghosts(64, 64);
    assert!(matches!(
        insert(&spec, &mut frame.clone(), &FrameInputs { ghost_layers: &small, ..FrameInputs::default() }),
        Err(CueError::BadParam(_))
    ));
}

#[test]
fn ghost_outlines_trace_only_the_silhouette_edges() {
    let spec = spec_for(TASK, variants::find("ghost_outline").unwrap());
    let g = ghosts(W, W);
    let frame0 = base(W, W);
    let mut frame = frame0.clone();
    insert(&spec, &mut frame, &FrameInputs { ghost_layers: &g, ..FrameInputs::default() }).unwrap();
    let diff = changed(&frame0, &frame);
    assert!(diff.len() > 100);
    // Every changed pixel lies on the rim (radius 12) of one of the four discs.
    let centres: Vec<(f64, f64)> =
        (1..=4).map(|i| (SRC.0 + (TGT.0 - SRC.0) * i as f64 / 4.0, SRC.1 + (TGT.1 - SRC.1) * i as f64 / 4.0)).collect();
    for (x, y) in &diff {
        let d = centres.iter().map(|c| (*x as f64 + 0.5 - c.0).hypot(*y as f64 + 0.5 - c.1)).fold(f64::MAX, f64::min);
        assert!((8.5..=12.8).contains(&d), "pixel ({x}, {y}) at {d:.1} from the nearest centre");
    }
    assert_eq!(pixel(&frame, TGT), pixel(&frame0, TGT), "the inside of the last pose stays clear");
}

#[test]
fn bad_input_is_an_error_and_leaves_the_frame_alone() {
    let frame0 = base(W, W);
    let good = spec_for(TASK, variants::find("straight_arrow_red").unwrap());
    let cases: Vec<(CueSpec, FrameInputs<'_>)> = vec![
        (CueSpec { variant: "no_such_cue".into(), ..good.clone() }, FrameInputs::anchored(anchors())),
        (CueSpec { family: Family::F1, ..good.clone() }, FrameInputs::anchored(anchors())),
        (CueSpec { insert_mode: InsertMode::FixedRegion, ..good.clone() }, FrameInputs::anchored(anchors())),
        (
            CueSpec { params: CueParams { scale: Some(f32::NAN), ..CueParams::default() }, ..good.clone() },
            FrameInputs::anchored(anchors()),
        ),
        (
            CueSpec {
                params: CueParams { region: Some(NormBox::new(0.8, 0.8, 0.5, 0.5)), ..CueParams::default() },
                ..spec_for(TASK, variants::find("caption_bar").unwrap())
            },
            FrameInputs::default(),
        ),
        (spec_for(TASK, variants::find("ghost_outline").unwrap()), FrameInputs::default()),
        (spec_for(TASK, variants::find("before_after").unwrap()), FrameInputs::default()),
    ];
    for (spec, inputs) in &cases {
        let mut frame = frame0.clone();
        let err = insert(spec, &mut frame, inputs).expect_err(&spec.variant);
        assert!(!err.to_string().is_empty());
        assert_eq!(frame, frame0, "{} changed the frame on error", spec.variant);
    }
    let mut broken = frame0.clone();
    broken.data.pop();
    assert!(matches!(insert(&good, &mut broken, &FrameInputs::anchored(anchors())), Err(CueError::Frame(_))));
    let bad_picture = [RgbaImage { width: 10, height: 10, data: vec![0; 7] }];
    let goal = spec_for(TASK, variants::find("goal_inset").unwrap());
    assert!(matches!(
        insert(&goal, &mut frame0.clone(), &FrameInputs { pictures: &bad_picture, ..FrameInputs::default() }),
        Err(CueError::Input { .. })
    ));
    let nan = Anchors { source: Some(Anchor::at(f64::NAN, 3.0)), ..anchors() };
    let report = insert(&good, &mut frame0.clone(), &FrameInputs::anchored(nan)).unwrap();
    assert_eq!(report.source, AnchorUse::Skipped);
}

#[test]
fn spec_json_round_trips_and_ids_are_stable() {
    let mut spec =
        spec_for("open the top drawer and put the bowl inside", variants::find("curved_arrow_yellow").unwrap());
    spec.task = "libero_goal/3".into();
    spec.params.color = Some([255, 0, 0]);
    assert_eq!(spec.id(), "libero_goal/3/F2/curved_arrow_yellow");
    assert_eq!((spec.step, spec.source.as_str(), spec.target.as_deref()), (1, "bowl", Some("top drawer")));
    let json = serde_json::to_string(&spec).unwrap();
    let back: CueSpec = serde_json::from_str(&json).unwrap();
    assert_eq!(back, spec);
    assert!(json.contains("\"insert_mode\":\"scene_anchored\""));
    assert!(matches!(variants::find("ghost_fade").unwrap().needs, Needs::MovingSource));
}
