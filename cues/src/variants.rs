//! The catalogue of cue variants: stable snake_case names, one-line descriptions, what a task
//! must offer for the variant to apply, and the function that draws it.
//!
//! Each entry carries its draw function, so a catalogued variant cannot lack a renderer and a
//! renderer cannot exist without a name.

use serde::Serialize;

use crate::error::CueError;
use crate::families::{code, geometric, gesture, ghost, highlight, pictorial, signs, text};
use crate::insert::Ctx;
use crate::parse::{Relation, Step};
use crate::signage::Category;
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
    /// A step with one of these relations (prohibition, maintenance and system-state signs).
    Relation(&'static [Relation]),
    /// A step whose target (the source when it has none) names one of these things, as a
    /// whole word (hazard and hand-over signs, drawn at that thing).
    Names(&'static [&'static str]),
}

impl Needs {
    /// Whether one step offers what a variant with these needs conveys (`ShortText` is about
    /// the instruction, not a step: any step).
    pub fn met_by(self, step: &Step) -> bool {
        match self {
            Needs::Nothing | Needs::ShortText(_) => true,
            Needs::Target => step.target.is_some(),
            Needs::MovingSource => step.relation.moves_source(),
            Needs::Relation(rs) => rs.contains(&step.relation),
            Needs::Names(words) => names_any(step.target.as_deref().unwrap_or(&step.source), words),
        }
    }
}

/// Whether `phrase` contains one of `words` as whole words ("front of the stove" names the
/// stove; "stovetop" does not).
fn names_any(phrase: &str, words: &[&str]) -> bool {
    let padded = format!(" {} ", phrase.to_lowercase());
    words.iter().any(|w| padded.contains(&format!(" {w} ")))
}

/// What a variant's drawing is: the fact the composition statistics (`composition`) read
/// what an instance encodes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Form {
    /// The instruction as text, or as a code whose payload holds its words (QR, barcode).
    Words,
    /// A readable code of the shown step's relation and objects (`ON:BOWL>PLATE`).
    StepCode,
    /// An opaque code standing for the shown step (fiducial id).
    Tag,
    /// A picture of the goal state.
    GoalPicture,
    /// A start picture and a goal picture.
    BeforeAfter,
    /// Numbered keyframes of a demonstration, the last being the goal.
    Storyboard,
    /// Drawn object and action pictograms per step, in order.
    Pictograms,
    /// A mark on the source and/or target (crosshair, ring, box, glow, pointing hand).
    Mark,
    /// A directed path, arrow or ordered badges from the source to the target.
    Path,
    /// A hand closing on the source (the grasp as a gesture).
    Grasp,
    /// Future poses of the moved object, the last one where it ends.
    Poses,
    /// A robot sign of this category (its pictogram states an action predicate).
    Sign(Category),
}

/// Which of the shown step's things a drawing is placed at. Two steps of one task give
/// visibly different instances of a variant only if these things differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Marks {
    /// Nothing in the scene: a fixed image region showing the whole task.
    Region,
    Source,
    /// The target, or the source when the step has none.
    Target,
    /// Source and target.
    Both,
}

/// One cue variant.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Variant {
    pub name: &'static str,
    pub family: Family,
    pub description: &'static str,
    pub needs: Needs,
    pub form: Form,
    pub marks: Marks,
    #[serde(skip)]
    pub(crate) draw: fn(&mut Ctx<'_>) -> Result<(), CueError>,
}

macro_rules! v {
    ($name:literal, $family:ident, $needs:expr, $form:expr, $marks:ident, $draw:path, $desc:literal) => {
        Variant {
            name: $name,
            family: Family::$family,
            description: $desc,
            needs: $needs,
            form: $form,
            marks: Marks::$marks,
            draw: $draw,
        }
    };
}

use Form::{BeforeAfter, GoalPicture, Grasp, Mark, Path, Pictograms, Poses, Sign, StepCode, Storyboard, Tag, Words};
use Needs::{MovingSource, Nothing, ShortText, Target};

const STATE_CHANGES: Needs = Needs::Relation(&[Relation::Open, Relation::Close, Relation::TurnOn, Relation::TurnOff]);
const OPENINGS: Needs = Needs::Relation(&[Relation::Open, Relation::Close]);
const SWITCHES: Needs = Needs::Relation(&[Relation::TurnOn, Relation::TurnOff]);
const HAZARDS: Needs = Needs::Names(signs::HAZARDS);
const HAND_OVER: Needs = Needs::Names(signs::CARRIERS);

/// Every variant, grouped by family.
#[rustfmt::skip]
pub const VARIANTS: &[Variant] = &[
    v!("caption_bar", F1, Nothing, Words, Region, text::caption_bar, "white instruction text on a dark translucent band across the bottom"),
    v!("top_banner_yellow", F1, Nothing, Words, Region, text::top_banner, "bold black instruction on an opaque yellow banner across the top"),
    v!("sticky_note", F1, ShortText(45), Words, Region, text::sticky_note, "hand-lettered instruction on a tilted yellow sticky note, top right"),
    v!("straight_arrow_red", F2, Target, Path, Both, geometric::straight_arrow, "red block arrow with a white rim from the source to the target"),
    v!("curved_arrow_yellow", F2, Target, Path, Both, geometric::curved_arrow, "yellow arc arrow bulging upwards from the source to the target"),
    v!("dashed_path_cyan", F2, Target, Path, Both, geometric::dashed_path, "cyan dashed path from a ring on the source to an arrowhead at the target"),
    v!("chevron_trail_green", F2, Target, Path, Both, geometric::chevron_trail, "a row of green chevrons leading from the source to the target"),
    v!("numbered_waypoints", F2, Target, Path, Both, geometric::numbered_waypoints, "green badge 1 on the source, blue badge 2 on the target, joined by a line"),
    v!("target_crosshair_magenta", F2, Nothing, Mark, Target, geometric::crosshair, "magenta crosshair on the target (on the source when there is none)"),
    v!("bullseye_rings_green", F2, Nothing, Mark, Target, geometric::bullseye, "green concentric rings around the target (the source when there is none)"),
    v!("bounding_boxes", F2, Nothing, Mark, Both, geometric::bounding_boxes, "orange labelled box around the source, blue dashed box around the target"),
    v!("ghost_fade", F3, MovingSource, Poses, Both, ghost::fade, "future object poses composited with opacity rising towards the final pose"),
    v!("ghost_outline", F3, MovingSource, Poses, Both, ghost::outline, "cyan outlines of the future object poses only"),
    v!("ghost_trail_path", F3, MovingSource, Poses, Both, ghost::trail_path, "faint future poses joined by a path through their centres ending in an arrow"),
    v!("goal_inset", F4, Nothing, GoalPicture, Region, pictorial::goal_inset, "goal-state picture in a white-framed inset, top right, tagged GOAL"),
    v!("goal_polaroid", F4, Nothing, GoalPicture, Region, pictorial::goal_polaroid, "goal-state picture as a tilted instant photo with a hand-written caption"),
    v!("goal_monitor", F4, Nothing, GoalPicture, Region, pictorial::goal_monitor, "goal-state picture on a dark monitor panel with a title bar, bottom left"),
    v!("before_after", F4, Nothing, BeforeAfter, Region, pictorial::before_after, "start and goal pictures side by side with an arrow, along the bottom"),
    v!("keyframe_storyboard", F4, Nothing, Storyboard, Region, pictorial::storyboard, "up to four numbered keyframes of a demonstration, along the bottom"),
    v!("pictogram_strip", F4, Nothing, Pictograms, Region, pictorial::pictogram_strip, "object, action and target pictograms for each step on a white strip"),
    v!("step_cards", F4, Nothing, Pictograms, Region, pictorial::step_cards, "one numbered card per step with action pictogram and object name, left side"),
    v!("hand_point_source", F5, Nothing, Mark, Source, gesture::point_source, "a drawn hand pointing its index finger at the source"),
    v!("hand_grasp_source", F5, MovingSource, Grasp, Source, gesture::grasp_source, "a drawn hand closing around the source in a grasp"),
    v!("hand_point_then_place", F5, Target, Path, Both, gesture::point_then_place, "hand 1 points at the source, flat hand 2 shows the target, dashed arrow between"),
    v!("sign_mandatory_source", F6, Nothing, Sign(Category::Mandatory), Source, signs::mandatory_source, "blue mandatory-action sign on a post at the source"),
    v!("sign_zone_target", F6, Target, Sign(Category::TargetZone), Target, signs::zone_target, "purple target-zone sign on a post at the target"),
    v!("sign_permission_source", F6, Nothing, Sign(Category::Permission), Source, signs::permission_source, "green permission sign with an authorised check at the source"),
    v!("sign_prohibition_source", F6, STATE_CHANGES, Sign(Category::Prohibition), Source, signs::prohibition_source, "red prohibition sign at the fixture forbidding the opposite action (do not close what is to be opened)"),
    v!("sign_hazard", F6, HAZARDS, Sign(Category::Hazard), Target, signs::hazard, "yellow hazard triangle at the hot appliance the step puts something on or in, or operates (stove, microwave)"),
    v!("sign_handover_target", F6, HAND_OVER, Sign(Category::HumanRobot), Target, signs::handover_target, "orange human-robot sign with a hand-over pictogram at the carrier the object goes into (basket, caddy, tray)"),
    v!("sign_maintenance_source", F6, OPENINGS, Sign(Category::Maintenance), Source, signs::maintenance_source, "teal service sign at the drawer or door the step opens or closes"),
    v!("sign_system_state", F6, SWITCHES, Sign(Category::SystemState), Source, signs::system_state, "navy system-state panel at the appliance with a power badge showing the state to reach"),
    v!("spotlight_cone", F7, Nothing, Mark, Source, highlight::spotlight_cone, "a warm light cone from above ending in a bright pool on the source"),
    v!("glow_halo", F7, Nothing, Mark, Source, highlight::glow_halo, "soft yellow glow around the source"),
    v!("dim_surround", F7, Nothing, Mark, Both, highlight::dim_surround, "everything darkened except soft lit circles on the source and target"),
    v!("color_wash_target", F7, Nothing, Mark, Target, highlight::color_wash, "green light wash over the target (the source when there is none)"),
    v!("rim_light", F7, Nothing, Mark, Source, highlight::rim_light, "thin bright ring with a cyan outer glow around the source"),
    v!("dual_spotlights", F7, Target, Mark, Both, highlight::dual_spotlights, "cyan light pool on the source and magenta pool on the target"),
    v!("light_path", F7, Target, Path, Both, highlight::light_path, "glowing neon band from the source to the target"),
    v!("qr_instruction", F8, Nothing, Words, Region, code::qr_instruction, "QR code of the instruction text, bottom right"),
    v!("qr_json", F8, Nothing, Words, Region, code::qr_json, "QR code of a JSON task description (steps with source, relation, target), top left"),
    v!("barcode_code128", F8, Nothing, StepCode, Region, code::barcode, "Code 128 barcode of a compact action code with the code printed below"),
    v!("fiducial_tag", F8, Nothing, Tag, Region, code::fiducial, "VIFO-36 fiducial tag with a stable id hashed from relation and objects, top right"),
];

/// The variant with this name.
pub fn find(name: &str) -> Option<&'static Variant> {
    VARIANTS.iter().find(|v| v.name == name)
}

/// The variants of one family, in catalogue order.
pub fn of_family(family: Family) -> impl Iterator<Item = &'static Variant> {
    VARIANTS.iter().filter(move |v| v.family == family)
}
