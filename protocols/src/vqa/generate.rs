//! Four questions per cue instance.
//!
//! Distractors are built like the answer, from the same kind of parts:
//! - detection: the phrases of three other cue families;
//! - semantic and decision: a 2×2 design over the step's parts — {source, other object} ×
//!   {target, other target}, or {relation, its opposite} × {fixture, other fixture} for state
//!   changes — so every option shares exactly one part with two others and none is the
//!   "centre" a text-only model could pick; other targets must be able to take the relation
//!   (something to put things in or on), and without one the options vary the source only;
//!   options that would state any step of the task are skipped;
//! - grounding: object names, the other anchor of the step first (the arrow starts at the
//!   bowl but points to the plate), then scene objects and same-kind variants ("middle
//!   drawer" for "top drawer").
//!
//! Scene names come from the caller ([`Scene`]); a few generic tabletop names stand in when
//! a scene has too few. Alternatives closest in length to the true part come first, so the
//! option length does not point at the answer. Randomness is a stable hash of the question
//! id, and the answer letter is balanced (±1) over A–D per stage, per family and per question
//! wording, so the questions depend only on the input set.

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};
use vifo_cues::{CueSpec, Family, Relation, Step};

use super::wording::{self, Role};
use super::{LETTERS, Question, Stage, VqaError};
use crate::runner::stable_hash;

/// A scene object or fixture: its id as goal atoms name it (`akita_black_bowl_1`) and a
/// human name in the style of the instructions (`black bowl`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SceneEntity {
    pub id: String,
    pub name: String,
}

impl SceneEntity {
    pub fn new(id: &str, name: &str) -> SceneEntity {
        SceneEntity { id: id.to_string(), name: name.to_string() }
    }
}

/// What is in a task's scene; the pool distractors are drawn from.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Scene {
    /// Movable objects.
    pub objects: Vec<SceneEntity>,
    /// Static parts (cabinets, stoves, racks, the table).
    pub fixtures: Vec<SceneEntity>,
}

impl Scene {
    /// The step with its parts named as the scene names them when the instruction's phrase
    /// is a shorter form of that name ("bowl" → "black bowl", "cabinet" → "wooden cabinet"),
    /// so answer and distractors come from the same list of names. Phrases saying more than
    /// the name ("left plate", "top drawer") stay as written.
    fn named(&self, step: &Step) -> Step {
        let name = |phrase: &str, id: Option<&str>| -> String {
            id.and_then(|id| self.objects.iter().chain(&self.fixtures).find(|e| e.id == id))
                .filter(|e| words(phrase).is_subset(&words(&e.name)))
                .map_or_else(|| phrase.to_string(), |e| e.name.clone())
        };
        Step {
            source: name(&step.source, step.source_id.as_deref()),
            target: step.target.as_deref().map(|t| name(t, step.target_id.as_deref())),
            ..step.clone()
        }
    }
}

/// Used when a scene offers too few distinct names.
const FALLBACK_NAMES: [&str; 6] = ["red cup", "green apple", "blue towel", "wooden spoon", "metal tray", "paper box"];

/// Words that name one of several parts of the same kind.
const SIBLINGS: [&[&str]; 3] = [&["top", "middle", "bottom"], &["left", "right"], &["front", "back"]];

/// The questions of every instance. `scenes` maps a task key (`libero_goal/3`) to its scene.
pub fn generate(instances: &[CueSpec], scenes: &BTreeMap<String, Scene>) -> Result<Vec<Question>, VqaError> {
    let mut seen = BTreeSet::new();
    let mut drafts = Vec::with_capacity(instances.len() * 4);
    for spec in instances {
        let id = spec.id();
        if !seen.insert(id.clone()) {
            return Err(VqaError::DuplicateInstance(id));
        }
        let scene = scenes
            .get(&spec.task)
            .ok_or_else(|| VqaError::MissingScene { instance: id.clone(), task: spec.task.clone() })?;
        drafts.extend(instance_drafts(spec, scene)?);
    }
    Ok(balance(drafts))
}

/// The image file of an instance inside the export folder.
pub fn image_path(instance_id: &str) -> String {
    format!("images/{}.png", instance_id.replace('/', "-"))
}

/// A question before its answer letter is fixed.
struct Draft {
    id: String,
    instance_id: String,
    family: Family,
    stage: Stage,
    question: String,
    answer: String,
    distractors: [String; 3],
}

fn instance_drafts(spec: &CueSpec, scene: &Scene) -> Result<Vec<Draft>, VqaError> {
    let id = spec.id();
    let bad = |m: String| VqaError::BadInstance(id.clone(), m);
    let step =
        spec.steps.get(spec.step).ok_or_else(|| bad(format!("no step {} in {} steps", spec.step, spec.steps.len())))?;
    if step.source.trim().is_empty() {
        return Err(bad("the shown step has no source".into()));
    }
    let words = wording::cue_words(&spec.variant, spec.family);
    let steps: Vec<Step> = spec.steps.iter().map(|st| scene.named(st)).collect();
    let step = &steps[spec.step];
    let ctx = Ctx { id: &id, scene, steps: &steps };
    let draft = |stage: Stage, question: String, (answer, distractors): (String, [String; 3])| Draft {
        id: format!("{id}/{}", stage.name()),
        instance_id: id.clone(),
        family: spec.family,
        stage,
        question,
        answer,
        distractors,
    };
    Ok(vec![
        draft(Stage::Detection, wording::DETECTION_QUESTION.to_string(), detection(&id, spec.family)),
        draft(
            Stage::Semantic,
            wording::semantic_question(spec.family, words.noun),
            ctx.acts(step, "semantic", wording::goal_statement),
        ),
        draft(Stage::Grounding, wording::grounding_question(&words), ctx.grounding(step, &words)),
        draft(
            Stage::Decision,
            wording::decision_question(spec.family, words.noun),
            ctx.acts(step, "decision", wording::imperative),
        ),
    ])
}

fn detection(id: &str, family: Family) -> (String, [String; 3]) {
    let others =
        shuffled(id, Family::ALL.iter().filter(|&&f| f != family).map(|&f| wording::detection_phrase(f).to_string()));
    (wording::detection_phrase(family).to_string(), take3(others))
}

/// The first three of `v`; the pools above always hold more, this only rules out a panic.
fn take3(v: Vec<String>) -> [String; 3] {
    let mut it = v.into_iter().chain((1..).map(|i| format!("other object {i}")));
    [(); 3].map(|()| it.next().unwrap_or_default())
}

/// What one instance's distractors are drawn from.
struct Ctx<'a> {
    id: &'a str,
    scene: &'a Scene,
    steps: &'a [Step],
}

type Render = fn(Relation, &str, Option<&str>) -> String;

impl Ctx<'_> {
    /// Names that could stand in for `phrase` (the entity `step_id` names), best first: those
    /// closest in length (so option length says nothing), same-kind variants before scene
    /// entities of `pool` at equal length, then generic names.
    fn alternatives(
        &self,
        salt: &str,
        phrase: &str,
        step_id: Option<&str>,
        pool: &[&SceneEntity],
        avoid: &[&str],
    ) -> Vec<String> {
        let salt = format!("{}|{salt}", self.id);
        let len = phrase.chars().count();
        let scene = pool.iter().filter(|e| !step_id.is_some_and(|i| is_entity_of(&e.id, i))).map(|e| e.name.clone());
        let mut ranked: Vec<(usize, usize, u64, String)> = siblings(phrase)
            .into_iter()
            .map(|c| (0, c))
            .chain(scene.map(|c| (1, c)))
            .map(|(tier, c)| (c.chars().count().abs_diff(len) / 3, tier, stable_hash(&format!("{salt}|{c}")), c))
            .collect();
        ranked.sort();
        let mut out: Vec<String> = ranked.into_iter().map(|(.., c)| c).collect();
        out.extend(shuffled(&salt, FALLBACK_NAMES.iter().map(|s| s.to_string())));
        let mut seen = BTreeSet::new();
        out.retain(|c| {
            !same_thing(c, phrase) && !avoid.iter().any(|a| same_thing(c, a)) && seen.insert(c.to_lowercase())
        });
        out
    }

    /// Semantic or decision options: the step in the 2×2 design described above.
    fn acts(&self, step: &Step, salt: &str, render: Render) -> (String, [String; 3]) {
        let (s, t, r) = (step.source.as_str(), step.target.as_deref(), step.relation);
        let answer = render(r, s, t);
        let true_steps: BTreeSet<String> =
            self.steps.iter().map(|st| render(st.relation, &st.source, st.target.as_deref())).collect();
        let objects: Vec<&SceneEntity> = self.scene.objects.iter().collect();
        let everything: Vec<&SceneEntity> = self.scene.objects.iter().chain(&self.scene.fixtures).collect();
        let fixtures: Vec<&SceneEntity> = self.scene.fixtures.iter().collect();
        let candidates: Vec<[String; 3]> = if let Some(t) = t {
            let s_alt = self.alternatives(&format!("{salt}|s"), s, step.source_id.as_deref(), &objects, &[t]);
            let mut t_alt = self.alternatives(&format!("{salt}|t"), t, step.target_id.as_deref(), &everything, &[s]);
            // "in the ketchup" would give itself away: only targets that can take the relation.
            // Generic names are no plausible target either: they would differ in length and
            // not be in the picture.
            t_alt.retain(|c| wording::fits(c, r) && !FALLBACK_NAMES.contains(&c.as_str()));
            if t_alt.is_empty() {
                // No other plausible target in the scene: four sources, one target. A source of
                // another true step is dropped before the triples are taken, not with every
                // triple it is in (which left scene objects beside it unused for generic names).
                let s_alt: Vec<String> = s_alt.into_iter().filter(|c| !true_steps.contains(&render(r, c, Some(t)))).collect();
                s_alt
                    .windows(3)
                    .map(|w| [render(r, &w[0], Some(t)), render(r, &w[1], Some(t)), render(r, &w[2], Some(t))])
                    .collect()
            } else {
                pairs(&s_alt, &t_alt)
                    .filter(|(s2, t2)| !same_thing(s2, t2))
                    .map(|(s2, t2)| [render(r, s, Some(t2)), render(r, s2, Some(t)), render(r, s2, Some(t2))])
                    .collect()
            }
        } else if let Some(r2) = wording::opposite(r) {
            let mut s_alt = self.alternatives(&format!("{salt}|s"), s, step.source_id.as_deref(), &fixtures, &[]);
            // Things that open (or switch) first; a scene may have none besides the answer.
            s_alt.sort_by_key(|c| !wording::fits(c, r));
            s_alt.iter().map(|s2| [render(r2, s, None), render(r, s2, None), render(r2, s2, None)]).collect()
        } else {
            let mut s_alt = self.alternatives(&format!("{salt}|s"), s, step.source_id.as_deref(), &objects, &[]);
            s_alt.retain(|c| !true_steps.contains(&render(r, c, None)));
            s_alt.windows(3).map(|w| [render(r, &w[0], None), render(r, &w[1], None), render(r, &w[2], None)]).collect()
        };
        let fits = |c: &[String; 3]| {
            let texts: BTreeSet<&String> = c.iter().chain([&answer]).collect();
            texts.len() == 4 && c.iter().all(|x| !true_steps.contains(x))
        };
        let chosen = candidates
            .into_iter()
            .find(fits)
            .unwrap_or_else(|| self.generic_acts(r, s, t, render, &true_steps, &answer));
        (answer, chosen)
    }

    /// Last resort when the scene cannot make a valid design: generic names only.
    fn generic_acts(
        &self,
        r: Relation,
        s: &str,
        t: Option<&str>,
        render: Render,
        avoid: &BTreeSet<String>,
        answer: &str,
    ) -> [String; 3] {
        let mut out: Vec<String> = Vec::new();
        for name in shuffled(self.id, FALLBACK_NAMES.iter().map(|s| s.to_string())) {
            let text = match t {
                Some(t) => render(r, &name, Some(t)),
                None => render(r, &name, None),
            };
            if text != answer && !avoid.contains(&text) && !out.contains(&text) && !same_thing(&name, s) {
                out.push(text);
            }
        }
        take3(out)
    }

    /// Grounding options: "the <object>".
    fn grounding(&self, step: &Step, words: &wording::CueWords) -> (String, [String; 3]) {
        let (answer, answer_id, other) = match (words.role, &step.target) {
            (Role::Target, Some(t)) => (t.as_str(), step.target_id.as_deref(), Some(step.source.as_str())),
            _ => (step.source.as_str(), step.source_id.as_deref(), step.target.as_deref()),
        };
        let everything: Vec<&SceneEntity> = self.scene.objects.iter().chain(&self.scene.fixtures).collect();
        let mut pool = self.alternatives("grounding", answer, answer_id, &everything, &[]);
        if let Some(o) = other {
            pool.retain(|c| !same_thing(c, o));
            if !words.symmetric && !same_thing(o, answer) {
                pool.insert(0, o.to_string());
            }
        }
        let the = |n: &str| format!("the {n}");
        (the(answer), take3(pool.iter().map(|n| the(n)).collect()))
    }
}

/// Pairs (i, j) of two lists in order of i + j, so early choices stay the most plausible.
fn pairs<'a>(a: &'a [String], b: &'a [String]) -> impl Iterator<Item = (&'a str, &'a str)> {
    let n = a.len() + b.len();
    (0..n).flat_map(move |sum| (0..=sum).filter_map(move |i| Some((a.get(i)?.as_str(), b.get(sum - i)?.as_str()))))
}

/// Fixes each answer letter: per stage, questions ordered by family, wording and hash get
/// A, B, C, D, A, … from a stage-specific start. Every family and every wording is then a
/// contiguous run of that cycle, so letters are balanced (±1) per stage, per family and
/// stage, and per wording. The distractors fill the other slots in hash order.
fn balance(drafts: Vec<Draft>) -> Vec<Question> {
    let mut slot = vec![0usize; drafts.len()];
    for stage in Stage::ALL {
        let mut members: Vec<usize> = (0..drafts.len()).filter(|&i| drafts[i].stage == stage).collect();
        members.sort_by_key(|&i| (drafts[i].family, &drafts[i].question, stable_hash(&drafts[i].id), i));
        let start = (stable_hash(stage.name()) % 4) as usize;
        for (rank, i) in members.into_iter().enumerate() {
            slot[i] = (start + rank) % 4;
        }
    }
    drafts
        .into_iter()
        .zip(slot)
        .map(|(d, at)| {
            let mut options = shuffled(&d.id, d.distractors.iter().cloned());
            options.insert(at, d.answer);
            Question {
                image: image_path(&d.instance_id),
                id: d.id,
                instance_id: d.instance_id,
                family: d.family,
                stage: d.stage,
                question: d.question,
                options,
                answer: LETTERS[at].to_string(),
            }
        })
        .collect()
}

/// `items` in the order of a stable hash of (salt, item).
fn shuffled(salt: &str, items: impl IntoIterator<Item = String>) -> Vec<String> {
    let mut v: Vec<(u64, String)> = items.into_iter().map(|s| (stable_hash(&format!("{salt}|{s}")), s)).collect();
    v.sort();
    v.into_iter().map(|(_, s)| s).collect()
}

/// Lower-case words, a plural `s` dropped, so "moka pots" and "moka pot" compare equal.
fn words(s: &str) -> BTreeSet<String> {
    s.split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty() && !matches!(*w, "the" | "a" | "an" | "of"))
        .map(|w| {
            let w = w.to_lowercase();
            match w.strip_suffix('s') {
                Some(stem) if stem.len() >= 3 && !stem.ends_with('s') => stem.to_string(),
                _ => w,
            }
        })
        .collect()
}

/// True when one name's words contain the other's ("bowl" and "black bowl"): they may name
/// the same thing, so one cannot be a distractor for the other.
fn same_thing(a: &str, b: &str) -> bool {
    let (a, b) = (words(a), words(b));
    !a.is_empty() && !b.is_empty() && (a.is_subset(&b) || b.is_subset(&a))
}

/// Whether a goal-atom argument (`wooden_cabinet_1_top_region`) names this entity or one of
/// its regions.
fn is_entity_of(entity_id: &str, atom_arg: &str) -> bool {
    atom_arg == entity_id || atom_arg.strip_prefix(entity_id).is_some_and(|rest| rest.starts_with('_'))
}

/// "top drawer" → "middle drawer", "bottom drawer".
fn siblings(phrase: &str) -> Vec<String> {
    let tokens: Vec<&str> = phrase.split(' ').collect();
    let mut out = Vec::new();
    for (i, t) in tokens.iter().enumerate() {
        if let Some(group) = SIBLINGS.iter().find(|g| g.contains(t)) {
            for alt in group.iter().filter(|a| *a != t) {
                let mut v = tokens.clone();
                v[i] = alt;
                out.push(v.join(" "));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn name_helpers() {
        assert!(same_thing("bowl", "black bowl"));
        assert!(same_thing("moka pots", "moka pot"));
        assert!(!same_thing("plate", "black bowl"));
        assert!(!same_thing("glass", "grass"));
        assert!(is_entity_of("wooden_cabinet_1", "wooden_cabinet_1_top_region"));
        assert!(!is_entity_of("plate_1", "plate_10"));
        assert_eq!(
            siblings("top drawer of the cabinet"),
            ["middle drawer of the cabinet", "bottom drawer of the cabinet"]
        );
        let (a, b) = (["a".to_string(), "b".to_string()], ["x".to_string(), "y".to_string()]);
        let p: Vec<_> = pairs(&a, &b).collect();
        assert_eq!(p, [("a", "x"), ("a", "y"), ("b", "x"), ("b", "y")]);
    }
}
