//! What cue instances encode (the paper's appendix statistics, panel b): objects, regions or
//! spatial relations; actions or motion; final states or results; rules or constraints;
//! procedural sequences. One instance can encode several.
//!
//! The components are read off the spec: the variant's [`Form`] (what its drawing is) and the
//! spec's steps. Nothing is tagged per instance by hand. The rules:
//!
//! | component | encoded by |
//! |---|---|
//! | objects / regions / relations | cues that mark things in the live scene (marks, paths, hands, ghosts, signs) or name them (text, codes); not the pictorial demonstrations, which show a picture or a pictogram instead of referring to the scene |
//! | actions / motion | directed paths and arrows, the grasping hand, ghost poses, storyboards, action pictograms, signs (their predicate pictogram), and text or codes that spell the instruction or the step's relation |
//! | final states / results | goal pictures, before/after pairs, storyboards (the last frame is the goal), ghost poses (the last is where the object ends), system-state signs (the status to reach) |
//! | rules / constraints | signs of the action-governance and hazard categories: prohibition, mandatory, permission, hazard |
//! | procedures | storyboards (numbered keyframes), and for tasks of two or more steps the cues that show every step in order: text and codes of the whole instruction, pictogram strips and step cards |

use std::collections::BTreeMap;

use serde::Serialize;

use crate::signage::Category;
use crate::spec::CueSpec;
use crate::variants::{self, Form};

/// A semantic component of the paper's statistics figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    Objects,
    Actions,
    FinalStates,
    Rules,
    Procedures,
}

impl Component {
    pub const ALL: [Component; 5] =
        [Component::Objects, Component::Actions, Component::FinalStates, Component::Rules, Component::Procedures];

    /// The label of the paper's figure.
    pub fn label(self) -> &'static str {
        match self {
            Component::Objects => "objects / regions / relations",
            Component::Actions => "actions / motion",
            Component::FinalStates => "final states / results",
            Component::Rules => "rules / constraints",
            Component::Procedures => "procedures",
        }
    }

    /// The share of the paper's 1,347 instances that encode the component, in percent.
    pub fn paper_percent(self) -> f64 {
        match self {
            Component::Objects => 80.0,
            Component::Actions => 54.0,
            Component::FinalStates => 24.1,
            Component::Rules => 10.5,
            Component::Procedures => 9.7,
        }
    }
}

/// The components one instance encodes (in [`Component::ALL`] order); empty for a spec whose
/// variant is unknown.
pub fn components(spec: &CueSpec) -> Vec<Component> {
    let Some(v) = variants::find(&spec.variant) else { return Vec::new() };
    let multi_step = spec.steps.len() >= 2;
    let form = v.form;
    let objects = !matches!(form, Form::GoalPicture | Form::BeforeAfter | Form::Storyboard | Form::Pictograms);
    let actions = matches!(
        form,
        Form::Path
            | Form::Grasp
            | Form::Poses
            | Form::Storyboard
            | Form::Pictograms
            | Form::Sign(_)
            | Form::Words
            | Form::StepCode
    );
    let final_states = matches!(
        form,
        Form::GoalPicture | Form::BeforeAfter | Form::Storyboard | Form::Poses | Form::Sign(Category::SystemState)
    );
    let rules = matches!(
        form,
        Form::Sign(Category::Prohibition | Category::Mandatory | Category::Permission | Category::Hazard)
    );
    let procedures = form == Form::Storyboard || (multi_step && matches!(form, Form::Words | Form::Pictograms));
    let flags = [objects, actions, final_states, rules, procedures];
    Component::ALL.into_iter().zip(flags).filter(|(_, on)| *on).map(|(c, _)| c).collect()
}

/// How many instances encode one component.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coverage {
    pub instances: usize,
    /// Percent of all instances.
    pub percent: f64,
    /// The paper's percent.
    pub paper_percent: f64,
}

/// Coverage of every component over a set of instances.
pub fn coverage(instances: &[CueSpec]) -> BTreeMap<Component, Coverage> {
    let mut counts: BTreeMap<Component, usize> = Component::ALL.iter().map(|&c| (c, 0)).collect();
    for spec in instances {
        for c in components(spec) {
            *counts.entry(c).or_default() += 1;
        }
    }
    let total = instances.len().max(1) as f64;
    counts
        .into_iter()
        .map(|(c, n)| (c, Coverage { instances: n, percent: 100.0 * n as f64 / total, paper_percent: c.paper_percent() }))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::parse;
    use Component::*;

    fn of(variant: &str, instruction: &str) -> Vec<Component> {
        let task = parse(instruction).unwrap();
        let v = variants::find(variant).unwrap();
        let step = crate::instances::step_for(&task, v.needs).unwrap();
        components(&CueSpec::new("t/0", &task, step, v).unwrap())
    }

    #[test]
    fn components_follow_what_the_variant_draws_and_the_steps() {
        let one = "put the bowl on the plate";
        let two = "turn on the stove and put the moka pot on it";
        assert_eq!(of("goal_inset", one), [FinalStates]);
        assert_eq!(of("keyframe_storyboard", one), [Actions, FinalStates, Procedures]);
        assert_eq!(of("step_cards", one), [Actions]);
        assert_eq!(of("step_cards", two), [Actions, Procedures]);
        assert_eq!(of("caption_bar", two), [Objects, Actions, Procedures]);
        assert_eq!(of("fiducial_tag", two), [Objects]);
        assert_eq!(of("glow_halo", one), [Objects]);
        assert_eq!(of("straight_arrow_red", one), [Objects, Actions]);
        assert_eq!(of("ghost_fade", one), [Objects, Actions, FinalStates]);
        assert_eq!(of("sign_prohibition_source", two), [Objects, Actions, Rules]);
        assert_eq!(of("sign_system_state", two), [Objects, Actions, FinalStates]);
        assert_eq!(of("sign_zone_target", one), [Objects, Actions]);
        let unknown = CueSpec { variant: "nope".into(), ..CueSpec::new("t/0", &parse(one).unwrap(), 0, variants::find("glow_halo").unwrap()).unwrap() };
        assert!(components(&unknown).is_empty());
    }
}
