//! The catalogue of cue variants: stable snake_case names, one-line descriptions, what a task
//! must offer for the variant to apply, and the function that draws it.
//!
//! Each entry carries its draw function, so a catalogued variant cannot lack a renderer and a
//! renderer cannot exist without a name.

use serde::Serialize;

use crate::error::CueError;
use crate::families::{code, geometric, gesture, ghost, highlight, pictorial, signs, text};
use crate::insert::Ctx;
use crate::spec::Family;

/// What a task must offer for a variant to convey it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Needs {
    /// Any task.
    Nothing,
    /// A step with a target object or region (arrows, paths, zone signs).
    Target,
    /// A step that moves its source object (ghost trajectories, grasping hands).
    MovingSource,
    /// An instruction of at most this many characters (small text surfaces stay legible).
    ShortText(usize),
}

/// One cue variant.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Variant {
    pub name: &'static str,
    pub family: Family,
    pub description: &'static str,
    pub needs: Needs,
    #[serde(skip)]
    pub(crate) draw: fn(&mut Ctx<'_>) -> Result<(), CueError>,
}

macro_rules! v {
    ($name:literal, $family:ident, $needs:expr, $draw:path, $desc:literal) => {
        Variant { name: $name, family: Family::$family, description: $desc, needs: $needs, draw: $draw }
    };
}

use Needs::{MovingSource, Nothing, ShortText, Target};

/// Every variant, grouped by family.
#[rustfmt::skip]
pub const VARIANTS: &[Variant] = &[
    v!("caption_bar", F1, Nothing, text::caption_bar, "white instruction text on a dark translucent band across the bottom"),
    v!("top_banner_yellow", F1, Nothing, text::top_banner, "bold black instruction on an opaque yellow banner across the top"),
    v!("sticky_note", F1, ShortText(45), text::sticky_note, "hand-lettered instruction on a tilted yellow sticky note, top right"),
    v!("straight_arrow_red", F2, Target, geometric::straight_arrow, "red block arrow with a white rim from the source to the target"),
    v!("curved_arrow_yellow", F2, Target, geometric::curved_arrow, "yellow arc arrow bulging upwards from the source to the target"),
    v!("dashed_path_cyan", F2, Target, geometric::dashed_path, "cyan dashed path from a ring on the source to an arrowhead at the target"),
    v!("chevron_trail_green", F2, Target, geometric::chevron_trail, "a row of green chevrons leading from the source to the target"),
    v!("numbered_waypoints", F2, Target, geometric::numbered_waypoints, "green badge 1 on the source, blue badge 2 on the target, joined by a line"),
    v!("target_crosshair_magenta", F2, Nothing, geometric::crosshair, "magenta crosshair on the target (on the source when there is none)"),
    v!("bullseye_rings_green", F2, Nothing, geometric::bullseye, "green concentric rings around the target (the source when there is none)"),
    v!("bounding_boxes", F2, Nothing, geometric::bounding_boxes, "orange labelled box around the source, blue dashed box around the target"),
    v!("ghost_fade", F3, MovingSource, ghost::fade, "future object poses composited with opacity rising towards the final pose"),
    v!("ghost_outline", F3, MovingSource, ghost::outline, "cyan outlines of the future object poses only"),
    v!("ghost_trail_path", F3, MovingSource, ghost::trail_path, "faint future poses joined by a path through their centres ending in an arrow"),
    v!("goal_inset", F4, Nothing, pictorial::goal_inset, "goal-state picture in a white-framed inset, top right, tagged GOAL"),
    v!("goal_polaroid", F4, Nothing, pictorial::goal_polaroid, "goal-state picture as a tilted instant photo with a hand-written caption"),
    v!("goal_monitor", F4, Nothing, pictorial::goal_monitor, "goal-state picture on a dark monitor panel with a title bar, bottom left"),
    v!("before_after", F4, Nothing, pictorial::before_after, "start and goal pictures side by side with an arrow, along the bottom"),
    v!("keyframe_storyboard", F4, Nothing, pictorial::storyboard, "up to four numbered keyframes of a demonstration, along the bottom"),
    v!("pictogram_strip", F4, Nothing, pictorial::pictogram_strip, "object, action and target pictograms for each step on a white strip"),
    v!("step_cards", F4, Nothing, pictorial::step_cards, "one numbered card per step with action pictogram and object name, left side"),
    v!("hand_point_source", F5, Nothing, gesture::point_source, "a drawn hand pointing its index finger at the source"),
    v!("hand_grasp_source", F5, MovingSource, gesture::grasp_source, "a drawn hand closing around the source in a grasp"),
    v!("hand_point_then_place", F5, Target, gesture::point_then_place, "hand 1 points at the source, flat hand 2 shows the target, dashed arrow between"),
    v!("sign_mandatory_source", F6, Nothing, signs::mandatory_source, "blue mandatory-action sign on a post at the source"),
    v!("sign_zone_target", F6, Target, signs::zone_target, "purple target-zone sign on a post at the target"),
    v!("sign_permission_source", F6, Nothing, signs::permission_source, "green permission sign with an authorised check at the source"),
    v!("spotlight_cone", F7, Nothing, highlight::spotlight_cone, "a warm light cone from above ending in a bright pool on the source"),
    v!("glow_halo", F7, Nothing, highlight::glow_halo, "soft yellow glow around the source"),
    v!("dim_surround", F7, Nothing, highlight::dim_surround, "everything darkened except soft lit circles on the source and target"),
    v!("color_wash_target", F7, Nothing, highlight::color_wash, "green light wash over the target (the source when there is none)"),
    v!("rim_light", F7, Nothing, highlight::rim_light, "thin bright ring with a cyan outer glow around the source"),
    v!("dual_spotlights", F7, Target, highlight::dual_spotlights, "cyan light pool on the source and magenta pool on the target"),
    v!("light_path", F7, Target, highlight::light_path, "glowing neon band from the source to the target"),
    v!("qr_instruction", F8, Nothing, code::qr_instruction, "QR code of the instruction text, bottom right"),
    v!("qr_json", F8, Nothing, code::qr_json, "QR code of a JSON task description (steps with source, relation, target), top left"),
    v!("barcode_code128", F8, Nothing, code::barcode, "Code 128 barcode of a compact action code with the code printed below"),
    v!("fiducial_tag", F8, Nothing, code::fiducial, "VIFO-36 fiducial tag with a stable id hashed from relation and objects, top right"),
];

/// The variant with this name.
pub fn find(name: &str) -> Option<&'static Variant> {
    VARIANTS.iter().find(|v| v.name == name)
}

/// The variants of one family, in catalogue order.
pub fn of_family(family: Family) -> impl Iterator<Item = &'static Variant> {
    VARIANTS.iter().filter(move |v| v.family == family)
}
