//! LIBERO-VIFO in the browser: a cue-following episode behind a small JavaScript API.
//!
//! ```js
//! import init, { VifoDemo, tasks, instances } from "./vifo_web.js";
//! await init();
//! const demo = new VifoDemo(128, true);                  // 128² frames, wrist camera on
//! demo.reset("libero_goal/0", 0, "libero_goal/0/F1/caption_bar", "authorized");
//! demo.setPolicy("expert-cue");                          // or "zero", "random", ...
//! const status = demo.step();                            // or demo.stepAction([dx, dy, dz, dax, day, daz, g])
//! ctx.putImageData(new ImageData(new Uint8ClampedArray(demo.agentview().buffer), 128, 128), 0, 0);
//! ```
//!
//! Every call that can fail throws a JavaScript `Error` naming what was wrong (an unknown task,
//! cue or condition, an action that is not seven finite numbers); nothing the page passes traps
//! the module. The episode logic is [`demo`], plain Rust, which `vifo web episode` runs natively
//! to check the page's state hash.

pub mod demo;

use js_sys::{Array, Float32Array, Float64Array};
use vifo_scenes::view::CameraName;
use wasm_bindgen::prelude::*;

pub use demo::{Demo, Status};

fn js_error(message: String) -> JsError {
    JsError::new(&message)
}

fn to_js<T: serde::Serialize>(value: &T) -> Result<JsValue, JsError> {
    let text = serde_json::to_string(value).map_err(|e| js_error(e.to_string()))?;
    js_sys::JSON::parse(&text).map_err(|_| js_error("internal: status is not JSON".into()))
}

/// The 40 built-in tasks: `[{key, suite, index, instruction}]`.
#[wasm_bindgen]
pub fn tasks() -> Result<JsValue, JsError> {
    to_js(&demo::tasks())
}

/// The cue instances of a task: `[{id, family, family_name, variant, conveys, paper}]`.
#[wasm_bindgen]
pub fn instances(task: &str) -> Result<JsValue, JsError> {
    to_js(&demo::instances(task).map_err(js_error)?)
}

/// The four language conditions, in the paper's order.
#[wasm_bindgen(js_name = languageConditions)]
pub fn language_conditions() -> Vec<String> {
    vifo_protocols::Protocol::ALL.iter().map(|p| p.name().to_string()).collect()
}

/// The built-in policies `setPolicy` accepts.
#[wasm_bindgen]
pub fn policies() -> Vec<String> {
    vifo_protocols::policies::NAMES.iter().map(|s| s.to_string()).collect()
}

/// One demo episode (see the module docs).
#[wasm_bindgen]
pub struct VifoDemo {
    inner: Demo,
}

#[wasm_bindgen]
impl VifoDemo {
    /// Renders `size`² frames of agentview and, with `wrist`, of the wrist camera.
    #[wasm_bindgen(constructor)]
    pub fn new(size: u32, wrist: bool) -> Result<VifoDemo, JsError> {
        Ok(VifoDemo { inner: Demo::new(size, wrist).map_err(js_error)? })
    }

    #[wasm_bindgen(getter)]
    pub fn size(&self) -> u32 {
        self.inner.size()
    }

    /// Steps with this built-in policy from now on.
    #[wasm_bindgen(js_name = setPolicy)]
    pub fn set_policy(&mut self, name: &str) -> Result<(), JsError> {
        self.inner.set_policy(name).map_err(js_error)
    }

    /// Starts an episode; `cueId` may be null for `original`; `seed` (a whole number, or its
    /// decimal digits as a string: benchmark seeds need all 64 bits) defaults to the
    /// benchmark's seed of the episode. Returns the status.
    pub fn reset(
        &mut self,
        task: &str,
        init_state: f64,
        cue_id: Option<String>,
        language_condition: &str,
        seed: JsValue,
    ) -> Result<JsValue, JsError> {
        let init = whole(init_state, "initState")?;
        let seed = seed_of(&seed)?;
        let status = self.inner.reset(task, init as usize, cue_id.as_deref(), language_condition, seed).map_err(js_error)?;
        to_js(&status)
    }

    /// One control step with the current policy; returns the status.
    pub fn step(&mut self) -> Result<JsValue, JsError> {
        let status = self.inner.step().map_err(js_error)?;
        to_js(&status)
    }

    /// One control step with an action from the page: an Array, Float64Array or Float32Array
    /// of 7 finite numbers. Anything else throws and leaves the episode as it was.
    #[wasm_bindgen(js_name = stepAction)]
    pub fn step_action(&mut self, action: JsValue) -> Result<JsValue, JsError> {
        let action = action_values(&action)?;
        let status = self.inner.step_action(&action).map_err(js_error)?;
        to_js(&status)
    }

    /// The running episode's status.
    pub fn status(&self) -> Result<JsValue, JsError> {
        to_js(&self.inner.status().map_err(js_error)?)
    }

    /// A hash of the latest frames (both cameras, cue included), 16 hex digits; `vifo web
    /// episode` prints the native run's.
    #[wasm_bindgen(js_name = frameHash)]
    pub fn frame_hash(&self) -> Result<String, JsError> {
        self.inner.frame_hash().map_err(js_error)
    }

    /// The latest agentview frame, RGBA, top row first.
    pub fn agentview(&mut self) -> Result<Vec<u8>, JsError> {
        Ok(self.inner.frame_rgba(CameraName::AgentView).map_err(js_error)?.to_vec())
    }

    /// The latest wrist camera frame, RGBA, top row first.
    pub fn wrist(&mut self) -> Result<Vec<u8>, JsError> {
        Ok(self.inner.frame_rgba(CameraName::EyeInHand).map_err(js_error)?.to_vec())
    }
}

/// A whole number from JavaScript (indices and seeds arrive as doubles).
/// A seed given as a whole number or as decimal digits (absent: `None`).
fn seed_of(value: &JsValue) -> Result<Option<u64>, JsError> {
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    if let Some(number) = value.as_f64() {
        return whole(number, "seed").map(Some);
    }
    match value.as_string() {
        Some(text) => demo::parse_seed(&text).map(Some).map_err(js_error),
        None => Err(js_error("seed must be a whole number or a string of decimal digits".to_string())),
    }
}

fn whole(value: f64, name: &str) -> Result<u64, JsError> {
    if value.is_finite() && value >= 0.0 && value.fract() == 0.0 && value <= 9_007_199_254_740_991.0 {
        Ok(value as u64)
    } else {
        Err(js_error(format!("{name} must be a whole number from 0 to 2^53-1, got {value}")))
    }
}

/// The numbers of an action array, or an error naming what is wrong with it.
fn action_values(action: &JsValue) -> Result<Vec<f64>, JsError> {
    if let Some(array) = action.dyn_ref::<Float64Array>() {
        return Ok(array.to_vec());
    }
    if let Some(array) = action.dyn_ref::<Float32Array>() {
        return Ok(array.to_vec().into_iter().map(f64::from).collect());
    }
    let array = action.dyn_ref::<Array>().ok_or_else(|| {
        js_error("action must be an Array, Float64Array or Float32Array of 7 numbers [dx, dy, dz, dax, day, daz, gripper]".into())
    })?;
    array
        .iter()
        .enumerate()
        .map(|(i, v)| v.as_f64().ok_or_else(|| js_error(format!("action[{i}] is not a number: {v:?}"))))
        .collect()
}
