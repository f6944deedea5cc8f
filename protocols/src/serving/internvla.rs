//! InternVLA-A1.5's envelope over openpi's websocket transport
//! (`evaluation/LIBERO/policy_server/tools/websocket_policy_{server,client}.py`,
//! `model2libero_interface.py`).
//!
//! Metadata (checked at connect, as the LIBERO client does): `protocol_version` ≥ 2.1,
//! `preprocessing_owner == "server_canonical"`, `deterministic_inference_preprocess` true,
//! `chunk_size` ≥ replan steps, `action_dim` (default 7).
//! Request: `{"type": "infer", "request_id": "libero-<step>", "payload": {"examples": [{"image":
//! [primary, wrist] (|u1 256×256×3 each), "lang", "task" (both the instruction), "state" (<f4, 8)}],
//! "do_sample": false}}`.
//! Reply: `{"status", "ok", "type": "inference_result", "request_id", "protocol_version",
//! "data": {"actions": (B, T, D), "action_space"?: {"low", "high"}}}` or `ok: false` with
//! `error.message`. The client uses `actions[0]`, clips to `action_space` when given, keeps
//! the first `action_dim` columns, and — like the script, which works in float32 — rounds
//! each value to float32.

use rmpv::Value;

use super::{ModelInput, ServingConfig, Transport};
use crate::policy::{Policy, PolicyError};
use crate::remote::ndarray::{self, get, kind};
use crate::remote::{RemoteConfig, RemotePolicy};

pub struct InternVlaTransport {
    remote: RemotePolicy,
}

impl InternVlaTransport {
    pub fn connect(config: &ServingConfig) -> Result<InternVlaTransport, PolicyError> {
        let remote = RemotePolicy::with_config(RemoteConfig {
            connect_timeout: config.connect_timeout,
            request_timeout: config.request_timeout,
            ..RemoteConfig::new(&config.url)
        })?;
        check_metadata(remote.metadata(), config.profile.replan_steps.max(1))?;
        Ok(InternVlaTransport { remote })
    }
}

fn bad(m: String) -> PolicyError {
    PolicyError::Malformed(m)
}

/// Checks the server's metadata as the LIBERO client does.
pub fn check_metadata(meta: &Value, replan_steps: usize) -> Result<(), PolicyError> {
    let Value::Map(m) = meta else {
        return Err(bad(format!("server metadata is {}, expected a map", kind(meta))));
    };
    let version = get(m, "protocol_version").and_then(Value::as_str).unwrap_or("");
    let parsed: Option<(u32, u32)> = version.split_once('.').and_then(|(a, b)| {
        let minor = b.split('.').next().unwrap_or(b);
        Some((a.parse().ok()?, minor.parse().ok()?))
    });
    match parsed {
        Some(v) if v >= (2, 1) => {}
        _ => {
            return Err(bad(format!("metadata `protocol_version` is {version:?}, the LIBERO client needs >= 2.1")));
        }
    }
    if get(m, "preprocessing_owner").and_then(Value::as_str) != Some("server_canonical") {
        return Err(bad("metadata `preprocessing_owner` must be \"server_canonical\"".into()));
    }
    if get(m, "deterministic_inference_preprocess").and_then(Value::as_bool) != Some(true) {
        return Err(bad("metadata `deterministic_inference_preprocess` must be true".into()));
    }
    let chunk = get(m, "chunk_size").map_or(Some(1), Value::as_u64);
    match chunk {
        Some(c) if c as usize >= replan_steps => {}
        _ => {
            return Err(bad(format!(
                "metadata `chunk_size` is {}, less than replan_steps = {replan_steps}",
                get(m, "chunk_size").map_or("absent (1)".to_string(), ToString::to_string)
            )));
        }
    }
    match get(m, "action_dim").map_or(Some(7), Value::as_u64) {
        Some(d) if d >= 7 => Ok(()),
        _ => Err(bad("metadata `action_dim` must be an integer >= 7".into())),
    }
}

/// The msgpack request.
pub fn encode(input: &ModelInput) -> Result<Vec<u8>, PolicyError> {
    let image =
        |img: &vifo_cues::RgbImage| ndarray::encode_u8(&[img.height as usize, img.width as usize, 3], img.data.clone());
    let state: Vec<u8> = input.state.iter().flat_map(|&v| (v as f32).to_le_bytes()).collect();
    let example = Value::Map(vec![
        (Value::from("image"), Value::Array(vec![image(&input.image), image(&input.wrist)])),
        (Value::from("lang"), Value::from(input.instruction.as_str())),
        (Value::from("task"), Value::from(input.instruction.as_str())),
        (Value::from("state"), ndarray::encode("<f4", &[input.state.len()], state)),
    ]);
    let doc = Value::Map(vec![
        (Value::from("type"), Value::from("infer")),
        (Value::from("request_id"), Value::from(format!("libero-{}", input.step))),
        (
            Value::from("payload"),
            Value::Map(vec![
                (Value::from("examples"), Value::Array(vec![example])),
                (Value::from("do_sample"), Value::Boolean(false)),
            ]),
        ),
    ]);
    let mut bytes = Vec::new();
    rmpv::encode::write_value(&mut bytes, &doc)
        .map_err(|e| PolicyError::Other(format!("encoding the request: {e}")))?;
    Ok(bytes)
}

/// A float array under `field`, as `(shape, values)`.
fn floats(v: &Value, field: &str) -> Result<(Vec<usize>, Vec<f64>), PolicyError> {
    let a = ndarray::decode(v)
        .map_err(|e| bad(format!("`{field}`: {e}")))?
        .ok_or_else(|| bad(format!("`{field}` is {}, expected a numpy array", kind(v))))?;
    let values = a.to_f64().map_err(|e| bad(format!("`{field}`: {e}")))?;
    Ok((a.shape, values))
}

/// Checks and decodes one reply into the chunk the LIBERO client would execute.
pub fn parse(bytes: &[u8]) -> Result<Vec<[f64; 7]>, PolicyError> {
    let doc = ndarray::document(bytes, "reply").map_err(bad)?;
    let Value::Map(m) = &doc else {
        return Err(bad(format!("reply is {}, expected a map", kind(&doc))));
    };
    let ok = get(m, "ok").ok_or_else(|| bad("reply has no `ok`".into()))?;
    if ok.as_bool() != Some(true) {
        let message = get(m, "error")
            .and_then(|e| if let Value::Map(e) = e { get(e, "message").and_then(Value::as_str) } else { None })
            .unwrap_or("(no error.message)");
        let status = get(m, "status").and_then(Value::as_str).unwrap_or("?");
        return Err(PolicyError::Other(format!("policy server error (`ok` = {ok}, `status` = {status:?}): {message}")));
    }
    let Some(Value::Map(data)) = get(m, "data") else {
        return Err(bad("reply has no `data` map".into()));
    };
    let actions = get(data, "actions").ok_or_else(|| bad("reply has no `data.actions`".into()))?;
    let (shape, values) = floats(actions, "data.actions")?;
    if shape.len() != 3 || shape[0] == 0 || shape[1] == 0 || shape[2] == 0 {
        return Err(bad(format!("`data.actions` has shape {shape:?}, expected (B, T, D) with B, T, D >= 1")));
    }
    let (t, d) = (shape[1], shape[2]);
    if let Some(i) = values[..t * d].iter().position(|v| !v.is_finite()) {
        return Err(bad(format!("`data.actions`[0, {}, {}] is {}", i / d, i % d, values[i])));
    }
    let bounds = match get(data, "action_space") {
        Some(Value::Map(space)) => match (get(space, "low"), get(space, "high")) {
            (Some(l), Some(h)) => {
                let (lo, hi) = (floats(l, "data.action_space.low")?.1, floats(h, "data.action_space.high")?.1);
                (lo.len() == hi.len() && !lo.is_empty()).then_some((lo, hi))
            }
            _ => None,
        },
        _ => None,
    };
    let f32r = |v: f64| f64::from(v as f32);
    let mut chunk = Vec::with_capacity(t);
    for row in values[..t * d].chunks_exact(d) {
        let mut a = [0.0; 7];
        for (j, slot) in a.iter_mut().enumerate() {
            // Columns beyond D are zero-padded, as np.pad does.
            let mut v = if j < d { f32r(row[j]) } else { 0.0 };
            if let Some((lo, hi)) = &bounds
                && j < lo.len().min(d)
            {
                v = v.clamp(f32r(lo[j]), f32r(hi[j]));
            }
            *slot = v;
        }
        chunk.push(a);
    }
    Ok(chunk)
}

impl Transport for InternVlaTransport {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let request = encode(input)?;
        self.remote.round_trip(&request, parse)
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.remote.reset()
    }
}
