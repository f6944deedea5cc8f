use tiny_skia::Pixmap;
use vifo_cues::draw::geom::{unit_box, v2};
use vifo_cues::glyphs::{Pen, actor, hand, object, predicate};
fn main() {
    let mut pm = Pixmap::new(800, 400).unwrap();
    pm.fill(tiny_skia::Color::from_rgba8(230, 230, 230, 255));
    let pen = Pen { ink: [20, 60, 160, 255], paper: [230, 230, 230, 255] };
    use object::ObjectShape::*;
    for (i, s) in [
        Bowl, Plate, Mug, Bottle, Carton, Can, Pot, Pan, Book, Basket, Cabinet, Stove, Microwave, Rack, Human, Station,
        Generic,
    ]
    .iter()
    .enumerate()
    {
        object::draw(
            &mut pm,
            *s,
            pen,
            unit_box(10.0 + (i % 10) as f32 * 70.0, 10.0 + (i / 10) as f32 * 70.0, 60.0, 60.0),
        );
    }
    for (i, p) in predicate::Predicate::ALL.iter().enumerate() {
        predicate::draw(
            &mut pm,
            *p,
            pen,
            unit_box(10.0 + (i % 10) as f32 * 70.0, 160.0 + (i / 10) as f32 * 70.0, 60.0, 60.0),
        );
    }
    for (i, a) in [actor::Actor::Arm, actor::Actor::Gripper, actor::Actor::Mobile].iter().enumerate() {
        actor::draw(&mut pm, *a, pen, unit_box(500.0 + i as f32 * 70.0, 230.0, 60.0, 60.0));
    }
    hand::draw(&mut pm, hand::Pose::Point, v2(150.0, 340.0), v2(1.0, 0.0), 80.0, hand::DEFAULT_COLORS);
    hand::draw(&mut pm, hand::Pose::Point, v2(200.0, 340.0), v2(-1.0, 0.3), 80.0, hand::DEFAULT_COLORS);
    hand::draw(&mut pm, hand::Pose::Grasp, v2(400.0, 340.0), v2(1.0, 0.0), 80.0, hand::DEFAULT_COLORS);
    hand::draw(&mut pm, hand::Pose::Flat, v2(600.0, 340.0), v2(0.3, 1.0), 80.0, hand::DEFAULT_COLORS);
    hand::draw(&mut pm, hand::Pose::Point, v2(750.0, 390.0), v2(0.0, 1.0), 60.0, hand::DEFAULT_COLORS);
    let img = vifo_cues::draw::to_rgba_image(&pm);
    use vifo_cues::signage::*;
    let mut sheet = Pixmap::new(8 * 140, 2 * 190).unwrap();
    sheet.fill(tiny_skia::Color::from_rgba8(120, 140, 120, 255));
    for (i, c) in Category::ALL.iter().enumerate() {
        let preds = [
            vifo_cues::glyphs::predicate::Predicate::Grasp,
            vifo_cues::glyphs::predicate::Predicate::Place,
            vifo_cues::glyphs::predicate::Predicate::Avoid,
            vifo_cues::glyphs::predicate::Predicate::Place,
            vifo_cues::glyphs::predicate::Predicate::Place,
            vifo_cues::glyphs::predicate::Predicate::HandOver,
            vifo_cues::glyphs::predicate::Predicate::Inspect,
            vifo_cues::glyphs::predicate::Predicate::Charge,
        ];
        let mods = [
            Some(Modifier::Negation),
            None,
            Some(Modifier::HazardMark),
            Some(Modifier::Authorized),
            Some(Modifier::Direction(modifier::Direction::Right)),
            None,
            None,
            Some(Modifier::Alignment),
        ];
        let spec = SignSpec {
            category: *c,
            actor: vifo_cues::glyphs::actor::Actor::Arm,
            predicate: preds[i],
            target: SignTarget::named(
                ["black bowl", "plate", "stove", "wine bottle", "basket", "human", "cabinet", "charger dock"][i],
            ),
            modifier: mods[i],
        };
        let sign = compose_pixmap(&spec, 128);
        sheet.draw_pixmap(
            6 + i as i32 * 140,
            6,
            sign.as_ref(),
            &tiny_skia::PixmapPaint::default(),
            tiny_skia::Transform::identity(),
            None,
        );
        let small = compose_pixmap(&spec, 56);
        sheet.draw_pixmap(
            6 + i as i32 * 140,
            200,
            small.as_ref(),
            &tiny_skia::PixmapPaint::default(),
            tiny_skia::Transform::identity(),
            None,
        );
    }
    let s = vifo_cues::draw::to_rgba_image(&sheet);
    image::save_buffer("/tmp/signs.png", &s.data, s.width, s.height, image::ExtendedColorType::Rgba8).unwrap();
    image::save_buffer("/tmp/glyphs.png", &img.data, img.width, img.height, image::ExtendedColorType::Rgba8).unwrap();
}
