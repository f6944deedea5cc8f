//! Renders every cue variant over a synthetic tabletop and writes one contact sheet per task
//! (PNG), plus every single frame in a sub-folder, into the folder given as the first argument (default `/tmp/vifo-cue-gallery`).
//! For looking at cues while developing; the output is not part of the repository.
//!
//! `cargo run -p vifo-cues --example gallery -- /tmp/gallery`

use tiny_skia::{Pixmap, PixmapPaint, Transform};
use vifo_cues::draw::geom::{ellipse, rect, v2};
use vifo_cues::draw::text::{Align, Face, block_path, fit};
use vifo_cues::draw::{self, from_rgb_image, to_rgba_image};
use vifo_cues::{Anchor, Anchors, CueSpec, FrameInputs, Inserter, RgbImage, RgbaImage, VARIANTS, parse};

const SIZE: u32 = 256;

/// A tabletop with a black bowl (source) at `bowl` and a white plate (target) at `plate`.
fn scene(bowl: Option<(f32, f32)>, plate: (f32, f32)) -> Pixmap {
    let mut pm = Pixmap::new(SIZE, SIZE).unwrap();
    pm.fill(tiny_skia::Color::from_rgba8(168, 190, 205, 255));
    let id = Transform::identity();
    draw::fill(&mut pm, &rect(0.0, 90.0, 256.0, 166.0).unwrap(), [150, 112, 80, 255], id);
    draw::fill(&mut pm, &rect(18.0, 30.0, 50.0, 62.0).unwrap(), [120, 84, 52, 255], id);
    draw::fill(&mut pm, &ellipse(v2(plate.0, plate.1), 28.0, 12.0).unwrap(), [245, 245, 240, 255], id);
    draw::fill(&mut pm, &ellipse(v2(plate.0, plate.1 - 1.0), 18.0, 7.0).unwrap(), [225, 225, 220, 255], id);
    draw::fill(&mut pm, &ellipse(v2(200.0, 200.0), 14.0, 14.0).unwrap(), [200, 60, 40, 255], id);
    if let Some(b) = bowl {
        bowl_shape(&mut pm, b, 255);
    }
    pm
}

fn bowl_shape(pm: &mut Pixmap, at: (f32, f32), alpha: u8) {
    let id = Transform::identity();
    draw::fill(pm, &ellipse(v2(at.0, at.1), 18.0, 11.0).unwrap(), [30, 30, 34, alpha], id);
    draw::fill(pm, &ellipse(v2(at.0, at.1 - 4.0), 15.0, 5.0).unwrap(), [60, 60, 66, alpha], id);
}

fn rgb(pm: &Pixmap) -> RgbImage {
    let rgba = to_rgba_image(pm);
    RgbImage::from_raw(SIZE, SIZE, rgba.data.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()).unwrap()
}

fn label(pm: &mut Pixmap, text: &str, x: f32, y: f32, w: f32) {
    let b = fit(Face::SansBold, text, w, 16.0, 6.0, 12.0);
    if let Some(p) = block_path(&b, x, y, w, Align::Left) {
        draw::fill(pm, &p, [20, 20, 20, 255], Transform::identity());
    }
}

fn sheet(
    out: &std::path::Path,
    name: &str,
    instruction: &str,
    anchors: Anchors,
    bowl: Option<(f32, f32)>,
    plate: (f32, f32),
) {
    let parsed = parse(instruction).unwrap();
    let base = rgb(&scene(bowl, plate));
    // Ghost layers: the bowl along an arc from its place to the plate; pictures: start, goal.
    let from = bowl.unwrap_or(plate);
    let ghosts: Vec<RgbaImage> = (1..=4)
        .map(|i| {
            let t = i as f32 / 4.0;
            let p =
                (from.0 + (plate.0 - from.0) * t, from.1 + (plate.1 - 6.0 - from.1) * t - 40.0 * t * (1.0 - t) * 4.0);
            let mut l = Pixmap::new(SIZE, SIZE).unwrap();
            bowl_shape(&mut l, p, 255);
            to_rgba_image(&l)
        })
        .collect();
    let mut goal = scene(None, plate);
    bowl_shape(&mut goal, (plate.0, plate.1 - 6.0), 255);
    let pictures = [to_rgba_image(&scene(bowl, plate)), to_rgba_image(&goal)];
    let inputs = FrameInputs { anchors, ghost_layers: &ghosts, pictures: &pictures };
    let cols = 7;
    let cell = SIZE + 8;
    let rows = VARIANTS.len().div_ceil(cols);
    let mut sheet = Pixmap::new(cols as u32 * cell, rows as u32 * (cell + 18) + 24).unwrap();
    sheet.fill(tiny_skia::Color::WHITE);
    let title_w = sheet.width() as f32 - 12.0;
    label(&mut sheet, &format!("{name}: {instruction}"), 6.0, 4.0, title_w);
    let mut inserter = Inserter::new();
    for (i, v) in VARIANTS.iter().enumerate() {
        let step = parsed.steps.iter().position(|s| s.target.is_some()).unwrap_or(0);
        let spec = CueSpec::new(name, &parsed, step, v).unwrap();
        let mut frame = base.clone();
        let text = match inserter.insert(&mut frame, &spec, &inputs) {
            Ok(r) => {
                format!("{} {:?}/{:?}", v.name, r.source, r.target).replace("InView", "in").replace("NotUsed", "-")
            }
            Err(e) => format!("{}: {e}", v.name),
        };
        let single = out.join(name);
        std::fs::create_dir_all(&single).unwrap();
        image::save_buffer(
            single.join(format!("{}.png", v.name)),
            &frame.data,
            SIZE,
            SIZE,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
        let (x, y) = ((i % cols) as u32 * cell + 4, (i / cols) as u32 * (cell + 18) + 24);
        let pm = from_rgb_image(&frame).unwrap();
        sheet.draw_pixmap(x as i32, y as i32 + 16, pm.as_ref(), &PixmapPaint::default(), Transform::identity(), None);
        label(&mut sheet, &text, x as f32, y as f32, SIZE as f32);
    }
    let img = to_rgba_image(&sheet);
    let path = out.join(format!("{name}.png"));
    image::save_buffer(&path, &img.data, img.width, img.height, image::ExtendedColorType::Rgba8).unwrap();
    println!("wrote {}", path.display());
}

fn main() {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/vifo-cue-gallery".into()));
    std::fs::create_dir_all(&out).unwrap();
    let bowl = (70.0, 160.0);
    let plate = (185.0, 120.0);
    let anchors = Anchors {
        source: Some(Anchor::at(70.0, 160.0).with_radius(18.0)),
        target: Some(Anchor::at(185.0, 120.0).with_radius(26.0)),
    };
    sheet(
        &out,
        "spatial0",
        "pick up the black bowl between the plate and the ramekin and place it on the plate",
        anchors,
        Some(bowl),
        plate,
    );
    let off = Anchors {
        source: Some(Anchor::at(-40.0, 200.0).with_radius(18.0)),
        target: Some(Anchor { in_front: false, ..Anchor::at(185.0, 120.0) }),
    };
    sheet(&out, "offscreen", "put the bowl on the plate", off, Some(bowl), plate);
    let drawer = Anchors { source: Some(Anchor::at(43.0, 60.0).with_radius(20.0)), target: None };
    sheet(&out, "goal0", "open the middle drawer of the cabinet", drawer, None, plate);
    sheet(
        &out,
        "libero10_3",
        "put the black bowl in the bottom drawer of the cabinet and close it",
        anchors,
        Some(bowl),
        plate,
    );
}
