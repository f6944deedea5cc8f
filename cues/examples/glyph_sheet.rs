//! Draws every glyph (objects, predicates, actors, hands) and one sign per signage category
//! at two sizes into `<folder>/glyphs.png` and `<folder>/signs.png` (default folder
//! `/tmp/vifo-cue-gallery`). For looking at the vector art while developing.
//!
//! `cargo run -p vifo-cues --example glyph_sheet -- /tmp/gallery`

use tiny_skia::{Color, Pixmap};
use vifo_cues::draw::geom::{unit_box, v2};
use vifo_cues::draw::{blit_over, to_rgba_image};
use vifo_cues::glyphs::Pen;
use vifo_cues::glyphs::actor::{self, Actor};
use vifo_cues::glyphs::hand::{self, DEFAULT_COLORS, Pose};
use vifo_cues::glyphs::object::{self, ObjectShape};
use vifo_cues::glyphs::predicate::{self, Predicate};
use vifo_cues::signage::{Category, Modifier, SignSpec, SignTarget, compose_pixmap, modifier::Direction};

fn save(pm: &Pixmap, path: &std::path::Path) {
    let img = to_rgba_image(pm);
    image::save_buffer(path, &img.data, img.width, img.height, image::ExtendedColorType::Rgba8).unwrap();
    println!("wrote {}", path.display());
}

fn main() {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/vifo-cue-gallery".into()));
    std::fs::create_dir_all(&out).unwrap();

    let mut pm = Pixmap::new(800, 400).unwrap();
    pm.fill(Color::from_rgba8(230, 230, 230, 255));
    let pen = Pen { ink: [20, 60, 160, 255], paper: [230, 230, 230, 255] };
    let cell = |i: usize, row: f32| unit_box(10.0 + (i % 10) as f32 * 70.0, row + (i / 10) as f32 * 70.0, 60.0, 60.0);
    use ObjectShape::*;
    let shapes = [
        Bowl, Plate, Mug, Bottle, Carton, Can, Pot, Pan, Book, Basket, Cabinet, Stove, Microwave, Rack, Human, Station,
        Generic,
    ];
    for (i, s) in shapes.iter().enumerate() {
        object::draw(&mut pm, *s, pen, cell(i, 10.0));
    }
    for (i, p) in Predicate::ALL.iter().enumerate() {
        predicate::draw(&mut pm, *p, pen, cell(i, 160.0));
    }
    for (i, a) in [Actor::Arm, Actor::Gripper, Actor::Mobile].iter().enumerate() {
        actor::draw(&mut pm, *a, pen, unit_box(500.0 + i as f32 * 70.0, 230.0, 60.0, 60.0));
    }
    hand::draw(&mut pm, Pose::Point, v2(150.0, 340.0), v2(1.0, 0.0), 80.0, DEFAULT_COLORS);
    hand::draw(&mut pm, Pose::Point, v2(200.0, 340.0), v2(-1.0, 0.3), 80.0, DEFAULT_COLORS);
    hand::draw(&mut pm, Pose::Grasp, v2(400.0, 340.0), v2(1.0, 0.0), 80.0, DEFAULT_COLORS);
    hand::draw(&mut pm, Pose::Flat, v2(600.0, 340.0), v2(0.3, 1.0), 80.0, DEFAULT_COLORS);
    save(&pm, &out.join("glyphs.png"));

    let mut sheet = Pixmap::new(8 * 140, 2 * 190).unwrap();
    sheet.fill(Color::from_rgba8(120, 140, 120, 255));
    let examples = [
        (Predicate::Grasp, "black bowl", Some(Modifier::Negation)),
        (Predicate::Place, "plate", None),
        (Predicate::Avoid, "stove", Some(Modifier::HazardMark)),
        (Predicate::Place, "wine bottle", Some(Modifier::Authorized)),
        (Predicate::Place, "basket", Some(Modifier::Direction(Direction::Right))),
        (Predicate::HandOver, "human", None),
        (Predicate::Inspect, "cabinet", None),
        (Predicate::Charge, "charger dock", Some(Modifier::Alignment)),
    ];
    for (i, (category, (predicate, target, modifier))) in Category::ALL.iter().zip(examples).enumerate() {
        let spec =
            SignSpec { category: *category, actor: Actor::Arm, predicate, target: SignTarget::named(target), modifier };
        blit_over(&mut sheet, &compose_pixmap(&spec, 128), 6 + i as i32 * 140, 6);
        blit_over(&mut sheet, &compose_pixmap(&spec, 56), 6 + i as i32 * 140, 200);
    }
    save(&sheet, &out.join("signs.png"));
}
