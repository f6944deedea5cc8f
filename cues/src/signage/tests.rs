use super::*;
use crate::parse::parse;

fn spec(category: Category, predicate: Predicate) -> SignSpec {
    SignSpec {
        category,
        actor: Actor::Arm,
        predicate,
        target: SignTarget { shape: Some(ObjectShape::Bowl), label: None },
        modifier: None,
    }
}

#[test]
fn every_category_has_its_own_frame() {
    let signs: Vec<RgbaImage> = Category::ALL.iter().map(|&c| compose(&spec(c, Predicate::Grasp))).collect();
    for (i, a) in signs.iter().enumerate() {
        let opaque = a.data.chunks_exact(4).filter(|p| p[3] > 0).count();
        assert!(opaque > a.data.len() / 4 / 3, "{:?} covers too little", Category::ALL[i]);
        for b in &signs[i + 1..] {
            let differing = a.data.chunks_exact(4).zip(b.data.chunks_exact(4)).filter(|(p, q)| p != q).count();
            assert!(differing > a.data.len() / 4 / 10);
        }
    }
}

#[test]
fn parts_change_the_sign_and_composition_is_deterministic() {
    let base = spec(Category::Mandatory, Predicate::Place);
    let image = compose(&base);
    assert_eq!(image, compose(&base));
    let variants = [
        SignSpec { predicate: Predicate::Open, ..base.clone() },
        SignSpec { actor: Actor::Mobile, ..base.clone() },
        SignSpec { target: SignTarget { shape: Some(ObjectShape::Plate), label: None }, ..base.clone() },
        SignSpec { modifier: Some(Modifier::Negation), ..base.clone() },
        SignSpec { modifier: Some(Modifier::Direction(modifier::Direction::Right)), ..base.clone() },
        SignSpec { modifier: Some(Modifier::HazardMark), ..base.clone() },
        SignSpec { modifier: Some(Modifier::Authorized), ..base.clone() },
        SignSpec { modifier: Some(Modifier::Alignment), ..base.clone() },
        SignSpec { modifier: Some(Modifier::Status { on: true }), ..base.clone() },
    ];
    let on = compose(&SignSpec { modifier: Some(Modifier::Status { on: true }), ..base.clone() });
    assert_ne!(on, compose(&SignSpec { modifier: Some(Modifier::Status { on: false }), ..base.clone() }));
    for v in &variants {
        assert_ne!(compose(v), image, "{v:?} looks like the base sign");
    }
}

#[test]
fn a_label_adds_a_plate_below() {
    let plain = compose(&spec(Category::TargetZone, Predicate::Place));
    let labelled =
        compose(&SignSpec { target: SignTarget::named("plate"), ..spec(Category::TargetZone, Predicate::Place) });
    assert_eq!(plain.height, DEFAULT_SIZE);
    assert!(labelled.height > DEFAULT_SIZE + DEFAULT_SIZE / 4);
    let plate_dark = labelled.data[(DEFAULT_SIZE * DEFAULT_SIZE * 4) as usize..]
        .chunks_exact(4)
        .filter(|p| p[3] > 0 && p[0] < 80)
        .count();
    assert!(plate_dark > 20, "the label text is drawn on the plate");
}

#[test]
fn libero_steps_fill_predicate_and_target() {
    let task = parse("put the black bowl in the bottom drawer of the cabinet and close it").unwrap();
    let at_target = SignSpec::for_step(Category::TargetZone, &task.steps[0], false);
    assert_eq!(at_target.predicate, Predicate::Place);
    assert_eq!(at_target.target.label.as_deref(), Some("bottom drawer of the cabinet"));
    assert_eq!(at_target.target.shape, Some(ObjectShape::Cabinet));
    let on_source = SignSpec::for_step(Category::Mandatory, &task.steps[0], true);
    assert_eq!((on_source.predicate, on_source.target.shape), (Predicate::Grasp, Some(ObjectShape::Bowl)));
    let close = SignSpec::for_step(Category::Mandatory, &task.steps[1], true);
    assert_eq!(close.predicate, Predicate::Close);
    let right = parse("put the chocolate pudding to the right of the plate").unwrap();
    let sign = SignSpec::for_step(Category::TargetZone, right.primary(), false);
    assert_eq!(sign.modifier, Some(Modifier::Direction(modifier::Direction::Right)));
}

#[test]
fn categories_add_their_meaning_to_a_step() {
    let task = parse("turn on the stove and put the moka pot on it").unwrap();
    // Prohibition forbids the opposite of the state change: "do not turn off".
    let no = SignSpec::for_step(Category::Prohibition, &task.steps[0], true);
    assert_eq!((no.predicate, no.modifier), (Predicate::TurnOff, Some(Modifier::Negation)));
    let state = SignSpec::for_step(Category::SystemState, &task.steps[0], true);
    assert_eq!((state.predicate, state.modifier), (Predicate::TurnOn, Some(Modifier::Status { on: true })));
    let basket = parse("pick up the orange juice and place it in the basket").unwrap();
    let handover = SignSpec::for_step(Category::HumanRobot, &basket.steps[0], false);
    assert_eq!((handover.predicate, handover.target.label.as_deref()), (Predicate::HandOver, Some("basket")));
}
