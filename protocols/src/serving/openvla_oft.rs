//! OpenVLA-OFT's HTTP server (`vla-scripts/deploy.py`): `POST /act` with a JSON body in which
//! numpy arrays are `json_numpy` objects `{"__numpy__": base64(C-order bytes), "dtype":
//! "<f8"|"|u1"…, "shape": [..]}` (json_numpy 2.x; an empty shape is a scalar).
//!
//! Request (the observation dict of `run_libero_eval.py` plus the instruction): `full_image`
//! and `wrist_image` (`|u1` 256×256×3, rotated; the server resizes them with the eval script's
//! own `resize_image_for_policy` and center-crops), `state` (`<f8`, 8), `instruction` (the
//! task description; the server builds `In: What action should the robot take to …?`).
//! Reply: the action chunk as a JSON list of rows (each a json_numpy array of 7 or a plain
//! list), or one json_numpy array (H, 7). On any server-side exception `deploy.py` answers
//! the JSON string `"error"` with HTTP 200.

use base64::Engine;
use base64::engine::general_purpose::STANDARD;
use serde_json::{Map, Value, json};

use super::{ModelInput, ServingConfig, Transport, rows7};
use crate::policy::PolicyError;

pub struct OftTransport {
    agent: ureq::Agent,
    url: String,
    timeout_s: f64,
}

impl OftTransport {
    pub fn new(config: &ServingConfig) -> Result<OftTransport, PolicyError> {
        let url = config.url.clone();
        // Requests go through the agent's own connections; this one only finds a server that is
        // not up before the first episode, instead of as every episode's error.
        address(&url)?.connect(&url, config.connect_timeout)?;
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .timeout_connect(Some(config.connect_timeout))
            .timeout_global(Some(config.request_timeout))
            .http_status_as_error(false)
            .build()
            .into();
        Ok(OftTransport { agent, url, timeout_s: config.request_timeout.as_secs_f64() })
    }
}

/// The server's address: `http://host:port/act` (port 80 where none is given).
pub fn address(url: &str) -> Result<crate::remote::Address, PolicyError> {
    if !url.starts_with("http://") {
        return Err(PolicyError::Connection(format!(
            "{url}: expected http://host:port/act (TLS is not built in; use an ssh tunnel)"
        )));
    }
    crate::remote::Address::parse(url, Some(80))
}

/// json_numpy's encoding of an array.
pub fn array(dtype: &str, shape: &[usize], data: &[u8]) -> Value {
    json!({"__numpy__": STANDARD.encode(data), "dtype": dtype, "shape": shape})
}

/// The JSON request body.
pub fn encode(input: &ModelInput) -> Value {
    let image = |img: &vifo_cues::RgbImage| array("|u1", &[img.height as usize, img.width as usize, 3], &img.data);
    let state: Vec<u8> = input.state.iter().flat_map(|v| v.to_le_bytes()).collect();
    json!({
        "full_image": image(&input.image),
        "wrist_image": image(&input.wrist),
        "state": array("<f8", &[input.state.len()], &state),
        "instruction": input.instruction,
    })
}

fn bad(m: String) -> PolicyError {
    PolicyError::Malformed(m)
}

/// A json_numpy object as `(shape, values)`; `field` names it in errors.
fn decode_array(obj: &Map<String, Value>, field: &str) -> Result<(Vec<usize>, Vec<f64>), PolicyError> {
    let Some(data) = obj.get("__numpy__") else {
        let keys: Vec<&str> = obj.keys().map(String::as_str).take(8).collect();
        return Err(bad(format!(
            "`{field}` is an object without `__numpy__` (keys: {}), expected a json_numpy array or a list of numbers",
            keys.join(", ")
        )));
    };
    let data = data.as_str().ok_or_else(|| bad(format!("`{field}.__numpy__` is not a string")))?;
    let bytes = STANDARD.decode(data).map_err(|e| bad(format!("`{field}.__numpy__` is not base64: {e}")))?;
    let dtype =
        obj.get("dtype").and_then(Value::as_str).ok_or_else(|| bad(format!("`{field}` has no string `dtype`")))?;
    let shape: Vec<usize> = obj
        .get("shape")
        .and_then(Value::as_array)
        .ok_or_else(|| bad(format!("`{field}` has no `shape` list")))?
        .iter()
        .map(|d| d.as_u64().map(|n| n as usize))
        .collect::<Option<_>>()
        .ok_or_else(|| bad(format!("`{field}.shape` holds a non-size")))?;
    let size = match dtype {
        "<f4" => 4,
        "<f8" => 8,
        other => {
            return Err(bad(format!("`{field}` has dtype {other:?}, expected \"<f4\" or \"<f8\"")));
        }
    };
    let n = shape
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| bad(format!("`{field}.shape` overflows")))?;
    if n.checked_mul(size) != Some(bytes.len()) {
        return Err(bad(format!(
            "`{field}` of shape {shape:?} and dtype {dtype} needs {} bytes, got {}",
            n * size,
            bytes.len()
        )));
    }
    let values = if size == 4 {
        bytes.chunks_exact(4).map(|b| f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))).collect()
    } else {
        bytes.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))).collect()
    };
    Ok((shape, values))
}

/// One row: a json_numpy array of 7 (or more) or a plain list of numbers.
fn row(v: &Value, field: &str) -> Result<Vec<f64>, PolicyError> {
    match v {
        Value::Object(o) => {
            let (shape, values) = decode_array(o, field)?;
            if shape.len() != 1 {
                return Err(bad(format!("`{field}` has shape {shape:?}, expected (7,)")));
            }
            Ok(values)
        }
        Value::Array(xs) => xs
            .iter()
            .map(|x| x.as_f64())
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| bad(format!("`{field}` is a list with a non-number"))),
        other => Err(bad(format!("`{field}` is {other}, expected an array of 7"))),
    }
}

/// Checks and decodes one reply body.
pub fn parse(body: &str) -> Result<Vec<[f64; 7]>, PolicyError> {
    let doc: Value = serde_json::from_str(body).map_err(|e| bad(format!("reply is not JSON: {e}")))?;
    match &doc {
        Value::String(s) => Err(PolicyError::Other(format!(
            "policy server answered {s:?} (deploy.py's reply to an exception; see its log)"
        ))),
        Value::Array(rows) => {
            if rows.is_empty() {
                return Err(bad("reply is an empty action chunk".into()));
            }
            let rows: Vec<Vec<f64>> =
                rows.iter().enumerate().map(|(i, r)| row(r, &format!("actions[{i}]"))).collect::<Result<_, _>>()?;
            let cols = rows[0].len();
            if let Some(i) = rows.iter().position(|r| r.len() != cols) {
                return Err(bad(format!("`actions[{i}]` has {} values, `actions[0]` {cols}", rows[i].len())));
            }
            let flat: Vec<f64> = rows.concat();
            exact7(rows7(&flat, rows.len(), cols, "actions")?, cols)
        }
        Value::Object(o) => {
            let (shape, values) = decode_array(o, "actions")?;
            if shape.len() != 2 {
                return Err(bad(format!("`actions` has shape {shape:?}, expected (H, 7)")));
            }
            exact7(rows7(&values, shape[0], shape[1], "actions")?, shape[1])
        }
        other => Err(bad(format!("reply is {other}, expected a list of actions"))),
    }
}

/// OFT's LIBERO actions have exactly 7 values (`ACTION_DIM`).
fn exact7(rows: Vec<[f64; 7]>, cols: usize) -> Result<Vec<[f64; 7]>, PolicyError> {
    if cols != 7 {
        return Err(bad(format!("`actions` rows have {cols} values, expected 7")));
    }
    Ok(rows)
}

/// Whether the server closed the connection under the request (rather than refused it or let
/// it time out).
fn closed_by_peer(e: &std::io::Error) -> bool {
    use std::io::ErrorKind::*;
    matches!(e.kind(), ConnectionReset | ConnectionAborted | BrokenPipe | UnexpectedEof)
}

/// A reply larger than this is refused unread: an action chunk is a few kilobytes.
const MAX_REPLY_BYTES: u64 = 64 << 20;

impl Transport for OftTransport {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let url = &self.url;
        let body = encode(input);
        let send = || self.agent.post(url).send_json(&body);
        // A kept-alive connection that the server's keep-alive closes just as the request goes
        // out ends in a reset before any reply: one fresh connection is safe to try, because
        // inference keeps no server state (the websocket clients reconnect likewise).
        let sent = match send() {
            Err(ureq::Error::Io(e)) if closed_by_peer(&e) => send(),
            other => other,
        };
        let mut response = sent.map_err(|e| match e {
            ureq::Error::Timeout(_) => PolicyError::Timeout(self.timeout_s),
            other => PolicyError::Connection(format!("{url}: {other}")),
        })?;
        let status = response.status().as_u16();
        let text = response
            .body_mut()
            .with_config()
            .limit(MAX_REPLY_BYTES)
            .read_to_string()
            .map_err(|e| match e {
                ureq::Error::BodyExceedsLimit(_) => {
                    bad(format!("{url}: the reply is larger than {} MiB, far more than an action chunk", MAX_REPLY_BYTES >> 20))
                }
                ureq::Error::Timeout(_) => PolicyError::Timeout(self.timeout_s),
                other => PolicyError::Connection(format!("{url}: reading the reply: {other}")),
            })?;
        if !(200..300).contains(&status) {
            let snippet: String = text.chars().take(300).collect();
            return Err(PolicyError::Other(format!("{url}: HTTP status {status}: {snippet}")));
        }
        parse(&text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replies_decode_or_name_the_problem() {
        let f32row = |v: f32| array("<f4", &[7], &[v; 7].iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>());
        let ok = json!([f32row(0.5), f32row(1.5)]).to_string();
        assert_eq!(parse(&ok).unwrap()[1][3], 1.5);
        let whole = array("<f8", &[2, 7], &[0.25f64; 14].iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>());
        assert_eq!(parse(&whole.to_string()).unwrap().len(), 2);
        assert_eq!(parse("[[0,0,0,0,0,0,1]]").unwrap()[0][6], 1.0);
        let cases = [
            ("\"error\"".to_string(), "answered \"error\""),
            ("{\"x\": 1}".to_string(), "`actions` is an object without `__numpy__` (keys: x)"),
            ("{\"__numpy__\": 1}".to_string(), "`actions.__numpy__` is not a string"),
            (json!([array("<i8", &[7], &[0; 56])]).to_string(), "dtype \"<i8\""),
            (json!([array("<f8", &[7], &[0; 48])]).to_string(), "needs 56 bytes, got 48"),
            ("[[0,0,0,0,0,0]]".to_string(), "1 rows of 6"),
            ("[]".to_string(), "empty action chunk"),
            ("not json".to_string(), "not JSON"),
        ];
        for (body, expected) in cases {
            let e = parse(&body).unwrap_err().to_string();
            assert!(e.contains(expected), "{body}: {e}");
        }
    }

    /// Reads one HTTP request (headers and a `Content-Length` body) from `s`.
    fn read_request(s: &mut std::net::TcpStream) {
        use std::io::Read;
        let mut buf = Vec::new();
        let mut byte = [0u8; 1];
        while !buf.ends_with(b"\r\n\r\n") {
            s.read_exact(&mut byte).unwrap();
            buf.push(byte[0]);
        }
        let head = String::from_utf8_lossy(&buf).to_ascii_lowercase();
        let len: usize = head
            .lines()
            .find_map(|l| l.strip_prefix("content-length:"))
            .map_or(0, |v| v.trim().parse().unwrap());
        s.read_exact(&mut vec![0; len]).unwrap();
    }

    /// A kept-alive connection that the server closes just as the next request goes out (its
    /// keep-alive ran out) costs that request one fresh connection, not the episode.
    #[test]
    fn a_kept_alive_connection_closed_by_the_server_is_tried_once_afresh() {
        use std::io::Write;
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let url = format!("http://{}/act", listener.local_addr().unwrap());
        let server = std::thread::spawn(move || {
            let reply = |s: &mut std::net::TcpStream| {
                let body = "[[0,0,0,0,0,0,1]]";
                write!(s, "HTTP/1.1 200 OK\r\ncontent-type: application/json\r\ncontent-length: {}\r\n\r\n{body}", body.len())
                    .unwrap();
            };
            // `OftTransport::new`'s check that a server is up: connected, then closed.
            drop(listener.accept().unwrap());
            let (mut first, _) = listener.accept().unwrap();
            read_request(&mut first);
            reply(&mut first);
            // The second request arrives on the kept-alive connection: close it unanswered,
            // with the request unread (the client then sees a reset or an early end).
            first.peek(&mut [0u8; 1]).unwrap();
            drop(first);
            let (mut second, _) = listener.accept().unwrap();
            read_request(&mut second);
            reply(&mut second);
        });
        let config = ServingConfig::new(&url, None, super::super::Profile::named("openvla-oft")).unwrap();
        let mut transport = OftTransport::new(&config).unwrap();
        let input = ModelInput::new(&config.profile, &super::super::tests::observation(), true).unwrap();
        assert_eq!(transport.infer(&input).unwrap()[0][6], 1.0);
        assert_eq!(transport.infer(&input).unwrap()[0][6], 1.0);
        server.join().unwrap();
    }
}
