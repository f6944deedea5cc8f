//! The words of the questions: cue names per variant, question templates per family and
//! stage, and the two ways a step is phrased as an option (goal statement, imperative).
//!
//! Rules that keep a text-only model from reading the answer off the question: a question
//! never names the objects of its task; detection is asked the same way for every family;
//! all four options of a question are built by one template from the same kind of parts, so
//! they share form and length.

use vifo_cues::{Family, Relation};

/// Which entity a grounding question asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// The manipulated object (or the fixture acted on).
    Source,
    /// The target; the source when the step has none.
    Target,
}

/// How a variant is named and grounded.
#[derive(Clone, Copy)]
pub(crate) struct CueWords {
    /// Short name used in the questions ("red arrow").
    pub noun: &'static str,
    pub role: Role,
    /// Grounding question; `{cue}` is replaced by `noun`.
    pub grounding: &'static str,
    /// The cue marks source and target alike (two equal lit circles, an undirected band):
    /// the other anchor is then no fair distractor.
    pub symmetric: bool,
}

const fn w(noun: &'static str, role: Role, grounding: &'static str, symmetric: bool) -> CueWords {
    CueWords { noun, role, grounding, symmetric }
}

use Role::{Source, Target};

/// Per-variant words; variants added to the catalogue later fall back to [`family_words`].
#[rustfmt::skip]
const VARIANT_WORDS: &[(&str, CueWords)] = &[
    ("caption_bar", w("caption bar", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("top_banner_yellow", w("yellow banner", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("sticky_note", w("sticky note", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("straight_arrow_red", w("red arrow", Target, "Which object does the {cue} point to?", false)),
    ("curved_arrow_yellow", w("curved yellow arrow", Target, "Which object does the {cue} point to?", false)),
    ("dashed_path_cyan", w("dashed cyan path", Target, "Which object does the {cue} end at?", false)),
    ("chevron_trail_green", w("row of green chevrons", Target, "Which object does the {cue} lead to?", false)),
    ("numbered_waypoints", w("numbered badges", Source, "Which object carries the badge with the number 1?", false)),
    ("target_crosshair_magenta", w("magenta crosshair", Target, "Which object is marked by the {cue}?", false)),
    ("bullseye_rings_green", w("green rings", Target, "Which object is circled by the {cue}?", false)),
    ("bounding_boxes", w("labelled boxes", Source, "Which object is inside the orange box?", false)),
    ("ghost_fade", w("faded copies of an object", Source, "Which object is shown by the {cue}?", false)),
    ("ghost_outline", w("cyan outlines of an object", Source, "Which object is traced by the {cue}?", false)),
    ("ghost_trail_path", w("faded trail of object poses", Source, "Which object is shown by the {cue}?", false)),
    ("goal_inset", w("framed goal picture", Source, "Which object does the {cue} show being handled first?", false)),
    ("goal_polaroid", w("instant photo", Source, "Which object does the {cue} show being handled first?", false)),
    ("goal_monitor", w("monitor panel", Source, "Which object does the {cue} show being handled first?", false)),
    ("before_after", w("before and after pictures", Source, "Which object do the {cue} show being handled first?", false)),
    ("keyframe_storyboard", w("storyboard of keyframes", Source, "Which object does the {cue} show being handled first?", false)),
    ("pictogram_strip", w("pictogram strip", Source, "Which object does the {cue} show being handled first?", false)),
    ("step_cards", w("numbered step cards", Source, "Which object do the {cue} show being handled first?", false)),
    ("hand_point_source", w("pointing hand", Source, "Which object is the {cue} pointing at?", false)),
    ("hand_grasp_source", w("grasping hand", Source, "Which object is the {cue} closing around?", false)),
    ("hand_point_then_place", w("pair of hands", Target, "Which object is the flat open hand held over?", false)),
    // A sign is asked what it refers to (its label names the object), not where it stands: as
    // a scene object (§4.2) it stands clear of everything the goal names.
    ("sign_mandatory_source", w("blue mandatory sign", Source, "Which object does the {cue} refer to?", false)),
    ("sign_zone_target", w("purple zone sign", Target, "Which object does the {cue} refer to?", false)),
    ("sign_permission_source", w("green permission sign", Source, "Which object does the {cue} refer to?", false)),
    ("sign_prohibition_source", w("red prohibition sign", Source, "Which object does the {cue} refer to?", false)),
    ("sign_hazard", w("yellow hazard sign", Target, "Which object does the {cue} refer to?", false)),
    ("sign_handover_target", w("orange hand-over sign", Target, "Which object does the {cue} refer to?", false)),
    ("sign_maintenance_source", w("teal service sign", Source, "Which object does the {cue} refer to?", false)),
    ("sign_system_state", w("navy status panel", Source, "Which object does the {cue} refer to?", false)),
    ("spotlight_cone", w("spotlight", Source, "Which object is lit by the {cue}?", false)),
    ("glow_halo", w("yellow glow", Source, "Which object is surrounded by the {cue}?", false)),
    ("dim_surround", w("lit circles in a dimmed scene", Source, "Which object is lit up in the dimmed scene?", true)),
    ("color_wash_target", w("green light wash", Target, "Which object is covered by the {cue}?", false)),
    ("rim_light", w("bright ring of light", Source, "Which object is outlined by the {cue}?", false)),
    ("dual_spotlights", w("two coloured spotlights", Source, "Which object is lit by the cyan spotlight?", false)),
    ("light_path", w("glowing neon band", Target, "Which object is at one end of the {cue}?", true)),
    ("qr_instruction", w("QR code", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("qr_json", w("QR code", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("barcode_code128", w("barcode", Source, "Which object does the {cue} name as the first one to handle?", false)),
    ("fiducial_tag", w("fiducial tag", Source, "Which object does the {cue} refer to as the first one to handle?", false)),
];

/// Words for a family when the variant is not in the table.
fn family_words(family: Family) -> CueWords {
    match family {
        Family::F1 => w("text overlay", Source, "Which object does the {cue} name as the first one to handle?", false),
        Family::F2 => w("geometric marker", Source, "Which object is marked by the {cue}?", false),
        Family::F3 => w("faded copies of an object", Source, "Which object is shown by the {cue}?", false),
        Family::F4 => w("inset picture", Source, "Which object does the {cue} show being handled first?", false),
        Family::F5 => w("drawn hand", Source, "Which object is the {cue} pointing at?", false),
        Family::F6 => w("sign", Source, "Which object does the {cue} refer to?", false),
        Family::F7 => w("light highlight", Source, "Which object is lit by the {cue}?", false),
        Family::F8 => {
            w("machine-readable code", Source, "Which object does the {cue} name as the first one to handle?", false)
        }
    }
}

pub(crate) fn cue_words(variant: &str, family: Family) -> CueWords {
    VARIANT_WORDS.iter().find(|(v, _)| *v == variant).map(|(_, w)| *w).unwrap_or_else(|| family_words(family))
}

/// The one detection question, the same for every family.
pub(crate) const DETECTION_QUESTION: &str = "Which kind of visual cue appears in the image?";

/// Detection options: one phrase per family, all 28 characters long so that length says
/// nothing about the family.
pub(crate) fn detection_phrase(family: Family) -> &'static str {
    match family {
        Family::F1 => "a written instruction banner",
        Family::F2 => "an arrow or geometric marker",
        Family::F3 => "ghostly copies of the object",
        Family::F4 => "a small inset picture window",
        Family::F5 => "a drawn human hand gesturing",
        Family::F6 => "a sign board on a short post",
        Family::F7 => "a patch of coloured lighting",
        Family::F8 => "a QR code, barcode or marker",
    }
}

/// The semantic question: what the cue conveys.
pub(crate) fn semantic_question(family: Family, noun: &str) -> String {
    let verb = match family {
        Family::F1 => "requested by",
        Family::F2 => "indicated by",
        Family::F3 | Family::F4 => "shown by",
        Family::F5 => "asked for by",
        Family::F6 => "required by",
        Family::F7 => "suggested by",
        Family::F8 => "encoded in",
    };
    format!("Which outcome is {verb} the {noun} in the image?")
}

/// The decision question: what to do, following the cue.
pub(crate) fn decision_question(family: Family, noun: &str) -> String {
    match family {
        Family::F1 | Family::F8 => format!("According to the {noun}, what should the robot do?"),
        Family::F2 => format!("Following the {noun}, what should the robot do next?"),
        Family::F3 => format!("What should the robot do to carry out the motion of the {noun}?"),
        Family::F4 => format!("What should the robot do to reach what the {noun} shows?"),
        Family::F5 => format!("What should the robot do in response to the {noun}?"),
        Family::F6 => format!("What should the robot do to comply with the {noun}?"),
        Family::F7 => format!("Given the {noun}, what should the robot do next?"),
    }
}

pub(crate) fn grounding_question(words: &CueWords) -> String {
    words.grounding.replace("{cue}", words.noun)
}

/// A relation of the same kind with the opposite effect, for state changes.
pub(crate) fn opposite(relation: Relation) -> Option<Relation> {
    match relation {
        Relation::Open => Some(Relation::Close),
        Relation::Close => Some(Relation::Open),
        Relation::TurnOn => Some(Relation::TurnOff),
        Relation::TurnOff => Some(Relation::TurnOn),
        _ => None,
    }
}

/// Head words of things one puts objects in.
const CONTAINERS: [&str; 15] = [
    "basket",
    "bowl",
    "drawer",
    "compartment",
    "microwave",
    "caddy",
    "box",
    "mug",
    "cup",
    "pot",
    "pan",
    "tray",
    "bin",
    "jar",
    "cabinet",
];

/// Head words of things one puts objects on.
const SURFACES: [&str; 11] =
    ["plate", "stove", "cabinet", "table", "rack", "tray", "shelf", "counter", "board", "box", "pan"];

/// Head words of things that open and close.
const OPENABLE: [&str; 9] = ["drawer", "door", "microwave", "cabinet", "compartment", "lid", "box", "fridge", "oven"];

/// Head words of things that switch on and off.
const SWITCHABLE: [&str; 8] = ["stove", "burner", "microwave", "light", "lamp", "faucet", "oven", "switch"];

/// Whether `name` is a believable target of `relation` (for state changes: a believable
/// thing to open or switch), so that a distractor such as "put the soup in the ketchup" or
/// "open the table" cannot be ruled out from the text alone.
pub(crate) fn fits(name: &str, relation: Relation) -> bool {
    let has = |list: &[&str]| name.split(' ').any(|w| list.contains(&w));
    match relation {
        Relation::In => has(&CONTAINERS),
        Relation::On => has(&SURFACES),
        Relation::PushTo => has(&["front", "back", "left", "right", "side"]),
        Relation::Open | Relation::Close => has(&OPENABLE),
        Relation::TurnOn | Relation::TurnOff => has(&SWITCHABLE),
        _ => true,
    }
}

/// The preposition that places the source relative to the target.
fn placement(relation: Relation) -> &'static str {
    match relation {
        Relation::In => "in",
        Relation::Under => "under",
        Relation::LeftOf => "to the left of",
        Relation::RightOf => "to the right of",
        Relation::FrontOf => "in front of",
        Relation::Behind => "behind",
        Relation::NextTo => "next to",
        _ => "on",
    }
}

/// "put the bowl on the plate", "open the top drawer": what the robot does. Closing is
/// "shut", as long as "open", so the pair differs in meaning only.
pub(crate) fn imperative(relation: Relation, source: &str, target: Option<&str>) -> String {
    match (relation, target) {
        (Relation::PushTo, Some(t)) => format!("push the {source} to the {t}"),
        (r, Some(t)) if r.needs_target() => format!("put the {source} {} the {t}", placement(r)),
        (Relation::Close, _) => format!("shut the {source}"),
        (r, _) => format!("{} the {source}", r.verb()),
    }
}

/// "the bowl ends up on the plate", "the top drawer ends up open": the state the cue asks for.
pub(crate) fn goal_statement(relation: Relation, source: &str, target: Option<&str>) -> String {
    match (relation, target) {
        (Relation::PushTo, Some(t)) => format!("the {source} ends up pushed to the {t}"),
        (r, Some(t)) if r.needs_target() => format!("the {source} ends up {} the {t}", placement(r)),
        (Relation::Open, _) => format!("the {source} ends up open"),
        (Relation::Close, _) => format!("the {source} ends up shut"),
        (Relation::TurnOn, _) => format!("the {source} ends up switched on"),
        (Relation::TurnOff, _) => format!("the {source} ends up switched off"),
        (_, _) => format!("the {source} ends up lifted off the table"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vifo_cues::VARIANTS;

    #[test]
    fn every_catalogued_variant_has_its_own_words() {
        for v in VARIANTS {
            assert!(VARIANT_WORDS.iter().any(|(name, _)| *name == v.name), "{} lacks question words", v.name);
        }
        for (name, _) in VARIANT_WORDS {
            assert!(vifo_cues::variants::find(name).is_some(), "{name} is not a catalogued variant");
        }
    }

    #[test]
    fn phrases() {
        assert_eq!(imperative(Relation::In, "bowl", Some("top drawer")), "put the bowl in the top drawer");
        assert_eq!(
            imperative(Relation::PushTo, "plate", Some("front of the stove")),
            "push the plate to the front of the stove"
        );
        assert_eq!(imperative(Relation::TurnOn, "stove", None), "turn on the stove");
        assert_eq!(
            goal_statement(Relation::RightOf, "pudding", Some("plate")),
            "the pudding ends up to the right of the plate"
        );
        assert_eq!(goal_statement(Relation::Close, "microwave", None), "the microwave ends up shut");
        assert_eq!(
            imperative(Relation::Close, "microwave", None).len(),
            imperative(Relation::Open, "microwave", None).len()
        );
        let lengths: Vec<usize> = Family::ALL.iter().map(|&f| detection_phrase(f).len()).collect();
        assert!(lengths.iter().all(|&n| n == 28), "{lengths:?}");
    }
}
