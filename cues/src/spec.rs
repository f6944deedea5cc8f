//! The cue specification C = (e_src, e_tgt, r_task, f_cue, v_cue, m_insert, φ) of the paper.

use serde::{Deserialize, Serialize};

use crate::error::CueError;
use crate::parse::{ParsedTask, Relation, Step};
use crate::variants::{self, Variant};

/// The eight cue families.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Family {
    /// Text overlay.
    F1,
    /// Geometric symbol (arrows, paths, rings, boxes).
    F2,
    /// Ghost trajectory (future object poses).
    F3,
    /// Pictorial demonstration (goal images, pictograms).
    F4,
    /// Hand gesture.
    F5,
    /// Visual signage.
    F6,
    /// Visual highlight / lighting.
    F7,
    /// Machine-readable code.
    F8,
}

impl Family {
    pub const ALL: [Family; 8] =
        [Family::F1, Family::F2, Family::F3, Family::F4, Family::F5, Family::F6, Family::F7, Family::F8];

    /// Descriptive name.
    pub fn name(self) -> &'static str {
        match self {
            Family::F1 => "text overlay",
            Family::F2 => "geometric symbol",
            Family::F3 => "ghost trajectory",
            Family::F4 => "pictorial demonstration",
            Family::F5 => "hand gesture",
            Family::F6 => "visual signage",
            Family::F7 => "visual highlight",
            Family::F8 => "machine-readable code",
        }
    }

    /// How the family is put into the image (paper appendix B).
    pub fn insert_mode(self) -> InsertMode {
        match self {
            Family::F2 | Family::F5 | Family::F6 | Family::F7 => InsertMode::SceneAnchored,
            Family::F1 | Family::F4 | Family::F8 => InsertMode::FixedRegion,
            Family::F3 => InsertMode::SimulatorState,
        }
    }
}

impl std::fmt::Display for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{self:?}")
    }
}

/// The three insertion modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InsertMode {
    /// Drawn at projected object positions, every frame.
    SceneAnchored,
    /// Drawn into a reserved, resolution-independent image region.
    FixedRegion,
    /// Composited from caller-rendered future-state layers.
    SimulatorState,
}

/// A box in normalised image coordinates: top-left (x/W, y/H), size (w/W, h/H).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NormBox {
    pub x: f32,
    pub y: f32,
    pub w: f32,
    pub h: f32,
}

impl NormBox {
    pub const fn new(x: f32, y: f32, w: f32, h: f32) -> NormBox {
        NormBox { x, y, w, h }
    }

    /// Checks that the box is finite, non-empty and inside the unit square.
    pub fn validate(&self) -> Result<(), CueError> {
        let ok = [self.x, self.y, self.w, self.h].iter().all(|v| v.is_finite())
            && self.x >= 0.0
            && self.y >= 0.0
            && self.w > 0.0
            && self.h > 0.0
            && self.x + self.w <= 1.0 + 1e-4
            && self.y + self.h <= 1.0 + 1e-4;
        if ok {
            Ok(())
        } else {
            Err(CueError::BadParam(format!("region {self:?} must be a non-empty box inside [0,1]²")))
        }
    }

    /// The box in whole pixels of a `width` × `height` frame (at least 1 px each way).
    pub fn to_pixels(&self, width: u32, height: u32) -> (i32, i32, u32, u32) {
        let x = (self.x * width as f32).round() as i32;
        let y = (self.y * height as f32).round() as i32;
        let w = ((self.w * width as f32).round() as u32).max(1);
        let h = ((self.h * height as f32).round() as u32).max(1);
        (x, y, w, h)
    }
}

/// Family-specific rendering parameters φ. Every field is optional; the variant's defaults
/// apply where a field is absent.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct CueParams {
    /// Main colour (RGB).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<[u8; 3]>,
    /// Fixed-region placement, overriding the variant's default box.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<NormBox>,
    /// Ghost opacities α_i, one per layer (F3); default ramps 0.25 → 0.65.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alphas: Option<Vec<f32>>,
    /// Size multiplier for scene-anchored drawings (1 = designed size).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f32>,
    /// Text payload for text and code cues, replacing the instruction (Part II conflict cues).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub text: Option<String>,
}

/// A task-conditioned cue: which task it shows, with which variant, inserted how.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CueSpec {
    /// Task key, e.g. "libero_goal/3".
    pub task: String,
    /// The instruction the cue conveys (text and code cues print or encode it).
    pub instruction: String,
    /// Index into `steps` of the step this cue shows (e_src, r_task, e_tgt below).
    pub step: usize,
    /// e_src: the manipulated object (or the fixture acted on).
    pub source: String,
    /// e_tgt: target object or region, if the relation has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<String>,
    /// r_task.
    pub relation: Relation,
    /// All steps of the task, in order.
    pub steps: Vec<Step>,
    /// f_cue.
    pub family: Family,
    /// v_cue: a variant name from [`crate::variants::VARIANTS`].
    pub variant: String,
    /// m_insert.
    pub insert_mode: InsertMode,
    /// φ.
    #[serde(default)]
    pub params: CueParams,
}

impl CueSpec {
    /// The spec for `variant` showing step `step` of a parsed task.
    pub fn new(task: &str, parsed: &ParsedTask, step: usize, variant: &Variant) -> Result<CueSpec, CueError> {
        let s = parsed.steps.get(step).ok_or_else(|| {
            CueError::BadSpec(format!("task {task} has {} steps, no step {step}", parsed.steps.len()))
        })?;
        Ok(CueSpec {
            task: task.to_string(),
            instruction: parsed.instruction.clone(),
            step,
            source: s.source.clone(),
            target: s.target.clone(),
            relation: s.relation,
            steps: parsed.steps.clone(),
            family: variant.family,
            variant: variant.name.to_string(),
            insert_mode: variant.family.insert_mode(),
            params: CueParams::default(),
        })
    }

    /// Stable id: `<task>/<family>/<variant>`, e.g. `libero_goal/3/F2/curved_arrow_yellow`,
    /// with `@<step number>` added when the spec shows a later step than the variant's first
    /// fitting one (`libero_10/4/F2/straight_arrow_red@2`; see [`crate::instances`]).
    pub fn id(&self) -> String {
        let first = variants::find(&self.variant)
            .and_then(|v| crate::instances::first_step(&self.steps, &self.instruction, v.needs));
        match first {
            Some(first) if first != self.step => format!("{}/{}/{}@{}", self.task, self.family, self.variant, self.step + 1),
            _ => format!("{}/{}/{}", self.task, self.family, self.variant),
        }
    }

    /// The variant, after checking that the spec is consistent (known variant of the stated
    /// family, matching insertion mode, sane parameters).
    pub fn check(&self) -> Result<&'static Variant, CueError> {
        let v = variants::find(&self.variant).ok_or_else(|| CueError::UnknownVariant(self.variant.clone()))?;
        if v.family != self.family {
            return Err(CueError::BadSpec(format!("variant {} belongs to {}, not {}", v.name, v.family, self.family)));
        }
        if self.insert_mode != self.family.insert_mode() {
            return Err(CueError::BadSpec(format!(
                "{} cues are inserted {:?}, not {:?}",
                self.family,
                self.family.insert_mode(),
                self.insert_mode
            )));
        }
        if self.source.trim().is_empty() {
            return Err(CueError::BadSpec("empty source".into()));
        }
        if let Some(r) = &self.params.region {
            r.validate()?;
        }
        if let Some(s) = self.params.scale
            && !(s.is_finite() && (0.05..=20.0).contains(&s))
        {
            return Err(CueError::BadParam(format!("scale {s} must be within [0.05, 20]")));
        }
        if let Some(alphas) = &self.params.alphas
            && alphas.iter().any(|a| !(a.is_finite() && (0.0..=1.0).contains(a)))
        {
            return Err(CueError::BadParam(format!("alphas {alphas:?} must lie in [0, 1]")));
        }
        Ok(v)
    }

    /// The text a text or code cue shows: the `text` parameter, else the instruction.
    pub fn payload_text(&self) -> &str {
        self.params.text.as_deref().unwrap_or(&self.instruction)
    }
}
