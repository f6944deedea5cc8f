//! A [`Policy`] served by an openpi websocket policy server (`scripts/serve_policy.py`), or by
//! any adapter that speaks its protocol.
//!
//! Protocol (openpi `websocket_client_policy.py` / `websocket_policy_server.py`): plain
//! RFC 6455 websocket; right after the handshake the server sends one binary msgpack
//! document (its metadata, often the empty map); then each request is one binary frame with
//! one msgpack document and each reply likewise. A text frame is a server-side error (openpi
//! sends the traceback). Payloads use msgpack-numpy ([`ndarray`]).
//!
//! LIBERO request, as `examples/libero/main.py` builds it: `observation/image` and
//! `observation/wrist_image` (`|u1`, 224×224×3, see [`image`] for orientation and resizing),
//! `observation/state` (`<f8`, 8: [`Observation::state8`]) and `prompt` (the instruction).
//! Reply: `actions` (`<f4` or `<f8`, H×7); other keys (timings, extras) are kept but unused.
//! Actions are queued: the server is asked only when the queue is empty and the first
//! `replan_steps` of each chunk are used.
//!
//! Failures never panic: unreachable or dropped servers are [`PolicyError::Connection`], slow
//! ones [`PolicyError::Timeout`], bad replies [`PolicyError::Malformed`] naming the problem. After
//! any failure the connection is dropped; the next [`Policy::reset`] reconnects.

pub mod address;
pub mod deadline;
pub mod image;
pub mod ndarray;

use std::collections::VecDeque;
use std::io;
use std::time::Duration;

use rmpv::Value;
use tungstenite::client::ClientRequestBuilder;
use tungstenite::http::Uri;
use tungstenite::{Message, WebSocket};

use crate::policy::{Observation, Policy, PolicyError};
pub use address::Address;
use deadline::DeadlineStream;

/// How to reach and use a server.
#[derive(Clone, Debug)]
pub struct RemoteConfig {
    /// `ws://host:port` (a bare `host:port` gets `ws://` prepended, as openpi's client does).
    pub url: String,
    /// Actions used from each chunk before asking again (openpi LIBERO: 5).
    pub replan_steps: usize,
    /// Limit for the TCP connect, the handshake and the metadata message.
    pub connect_timeout: Duration,
    /// Limit for one request: sending the observation and receiving the whole reply.
    pub request_timeout: Duration,
    /// Side of the square images sent (openpi LIBERO: 224).
    pub image_size: u32,
    /// Sent as `Authorization: Api-Key <key>` when set (openpi's client option).
    pub api_key: Option<String>,
    /// Name in results files; default `openpi@<url>`.
    pub name: Option<String>,
}

impl RemoteConfig {
    /// The name its records carry: `name`, or `openpi@<url>`.
    pub fn policy_name(&self) -> String {
        self.name.clone().unwrap_or_else(|| format!("openpi@{}", self.url))
    }

    pub fn new(url: &str) -> RemoteConfig {
        RemoteConfig {
            url: url.to_string(),
            replan_steps: 5,
            connect_timeout: Duration::from_secs(10),
            // openpi's first inference compiles the model and can take a minute or more.
            request_timeout: Duration::from_secs(180),
            image_size: 224,
            api_key: None,
            name: None,
        }
    }
}

/// One reply of the server.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply {
    /// The action chunk, H rows of `[dx, dy, dz, dax, day, daz, gripper]`.
    pub actions: Vec<[f64; 7]>,
    /// Every other top-level entry (`policy_timing`, `server_timing`, model extras).
    pub extra: Vec<(String, Value)>,
}

/// An openpi websocket policy client.
pub struct RemotePolicy {
    config: RemoteConfig,
    uri: Uri,
    address: Address,
    conn: Option<WebSocket<DeadlineStream>>,
    /// True when the connection was made before the current episode and has not served a
    /// request since: the server may have closed it while we were idle.
    idle: bool,
    metadata: Value,
    queue: VecDeque<[f64; 7]>,
    requests: usize,
}

impl RemotePolicy {
    /// Connects with default settings (replan 5, 224 px images).
    pub fn connect(url: &str) -> Result<RemotePolicy, PolicyError> {
        RemotePolicy::with_config(RemoteConfig::new(url))
    }

    /// Connects and reads the server's metadata message.
    pub fn with_config(config: RemoteConfig) -> Result<RemotePolicy, PolicyError> {
        if config.replan_steps == 0 {
            return Err(PolicyError::Other("replan_steps must be at least 1".into()));
        }
        if config.image_size == 0 {
            return Err(PolicyError::Other("image_size must be at least 1".into()));
        }
        let (uri, address) = parse_url(&config.url)?;
        let mut policy = RemotePolicy {
            config,
            uri,
            address,
            conn: None,
            idle: false,
            metadata: Value::Map(vec![]),
            queue: VecDeque::new(),
            requests: 0,
        };
        policy.reconnect()?;
        Ok(policy)
    }

    /// The metadata message of the current connection (openpi's `get_server_metadata`).
    pub fn metadata(&self) -> &Value {
        &self.metadata
    }

    /// Requests sent so far (over all connections).
    pub fn requests(&self) -> usize {
        self.requests
    }

    /// Sends one observation and returns the whole reply, bypassing the action queue.
    pub fn infer(&mut self, obs: &Observation) -> Result<Reply, PolicyError> {
        let request = encode_request(obs, self.config.image_size)?;
        self.round_trip(&request, parse_reply)
    }

    /// Sends one encoded request and reads the reply with `parse`: the transport for other
    /// request layouts over openpi's protocol (`crate::serving`).
    pub fn round_trip<T>(
        &mut self,
        request: &[u8],
        parse: impl FnOnce(&[u8]) -> Result<T, PolicyError>,
    ) -> Result<T, PolicyError> {
        if self.conn.is_none() {
            self.reconnect()?;
        }
        let result = match self.exchange(request) {
            // A connection idle since the last episode may have been closed by the server's
            // keep-alive; one fresh attempt is safe because inference has no server state.
            Err(PolicyError::Connection(_)) if self.idle => {
                self.reconnect()?;
                self.exchange(request)
            }
            other => other,
        };
        self.idle = false;
        // A server that sent something unreadable may be in any state: start afresh.
        let reply = result.and_then(|bytes| parse(&bytes));
        if reply.is_err() {
            self.hang_up();
        }
        self.requests += 1;
        reply
    }

    fn reconnect(&mut self) -> Result<(), PolicyError> {
        self.hang_up();
        let (conn, metadata) = open(&self.uri, &self.address, &self.config)?;
        self.conn = Some(conn);
        self.metadata = metadata;
        self.idle = false;
        Ok(())
    }

    /// Ends the connection, if any, with a websocket close handshake, so that the server sees
    /// a normal close rather than a dropped stream (servers other than openpi's log a
    /// traceback for each of those). Waits at most [`CLOSE_WAIT`] for the server's answer; a
    /// connection already broken just goes.
    fn hang_up(&mut self) {
        let Some(mut conn) = self.conn.take() else { return };
        conn.get_mut().limit(CLOSE_WAIT);
        if conn.close(None).is_err() {
            return;
        }
        // Until the server's close arrives (`read` then fails with `ConnectionClosed`) or the
        // time is up; an unread reply in the socket would turn our TCP close into a reset.
        while conn.read().is_ok() {}
    }

    /// One request/reply round trip within the request timeout.
    fn exchange(&mut self, request: &[u8]) -> Result<Vec<u8>, PolicyError> {
        let timeout = self.config.request_timeout;
        let conn = self.conn.as_mut().ok_or_else(|| PolicyError::Connection("not connected".into()))?;
        conn.get_mut().limit(timeout);
        nothing_waiting(conn, timeout)?;
        conn.send(Message::binary(request.to_vec())).map_err(|e| ws_error(e, timeout, "sending the observation"))?;
        read_binary(conn, timeout, "waiting for the reply")
    }
}

impl Policy for RemotePolicy {
    fn name(&self) -> String {
        self.config.policy_name()
    }

    /// Clears the action queue; reconnects if the last episode lost the connection.
    fn reset(&mut self) -> Result<(), PolicyError> {
        self.queue.clear();
        if self.conn.is_none() {
            self.reconnect()
        } else {
            self.idle = true;
            Ok(())
        }
    }

    /// Only when the queue is empty: the other steps play out the chunk.
    fn sees_images_next(&self) -> bool {
        self.queue.is_empty()
    }

    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError> {
        if self.queue.is_empty() {
            let reply = self.infer(obs)?;
            let n = self.config.replan_steps;
            if reply.actions.len() < n {
                return Err(PolicyError::Malformed(format!(
                    "action chunk has {} rows, fewer than replan_steps = {n}",
                    reply.actions.len()
                )));
            }
            self.queue.extend(&reply.actions[..n]);
        }
        self.queue.pop_front().ok_or_else(|| PolicyError::Malformed("empty action chunk".into()))
    }
}

impl Drop for RemotePolicy {
    fn drop(&mut self) {
        self.hang_up();
    }
}

/// The longest a client waits for the server's answer to its close.
const CLOSE_WAIT: Duration = Duration::from_millis(500);

/// `ws://host:port[/path]`; a bare `host:port` gets `ws://`. TLS is not built in.
pub fn parse_url(url: &str) -> Result<(Uri, Address), PolicyError> {
    let full = if url.contains("://") { url.to_string() } else { format!("ws://{url}") };
    let uri: Uri = full.parse().map_err(|e| PolicyError::Connection(format!("bad server address {url:?}: {e}")))?;
    match uri.scheme_str() {
        Some("ws") => {}
        Some("wss") => {
            return Err(PolicyError::Connection(format!(
                "{url}: wss:// (TLS) is not built in; reach the server through a local tunnel \
                 (ssh -L 8000:localhost:8000 host) and use ws://localhost:8000"
            )));
        }
        _ => return Err(PolicyError::Connection(format!("{url}: expected a ws://host:port address"))),
    }
    let address = Address::parse(&full, Some(80))?;
    Ok((uri, address))
}

/// TCP connect, websocket handshake and the metadata message, all within the connect timeout.
fn open(
    uri: &Uri,
    address: &Address,
    config: &RemoteConfig,
) -> Result<(WebSocket<DeadlineStream>, Value), PolicyError> {
    let timeout = config.connect_timeout;
    let stream = DeadlineStream::new(address.connect(&config.url, timeout)?, timeout);
    let mut request = ClientRequestBuilder::new(uri.clone());
    if let Some(key) = &config.api_key {
        request = request.with_header("Authorization", format!("Api-Key {key}"));
    }
    // A server that accepts the connection but never answers it: say which step waited.
    let slow = |what: &str| {
        PolicyError::Connection(format!(
            "{}: no answer {what} within the connect timeout of {:.1} s",
            config.url,
            timeout.as_secs_f64()
        ))
    };
    let slow_handshake = || slow("to the websocket handshake");
    let (mut ws, _) = tungstenite::client::client(request, stream).map_err(|e| match e {
        tungstenite::HandshakeError::Failure(e) => match ws_error(e, timeout, "during the websocket handshake") {
            PolicyError::Timeout(_) => slow_handshake(),
            other => other,
        },
        tungstenite::HandshakeError::Interrupted(_) => slow_handshake(),
    })?;
    let bytes = read_binary(&mut ws, timeout, "waiting for the server's metadata").map_err(|e| match e {
        PolicyError::Timeout(_) => slow("with the server's metadata"),
        other => other,
    })?;
    let metadata = ndarray::document(&bytes, "server metadata").map_err(PolicyError::Malformed)?;
    // openpi sends one dict; anything else is not an openpi server's handshake.
    if !matches!(metadata, Value::Map(_)) {
        return Err(PolicyError::Malformed(format!("server metadata is {}, expected one msgpack map", ndarray::kind(&metadata))));
    }
    Ok((ws, metadata))
}

/// Reads until a data message arrives (pings are answered by tungstenite on the way), within
/// the stream's deadline.
fn read_binary(ws: &mut WebSocket<DeadlineStream>, timeout: Duration, what: &str) -> Result<Vec<u8>, PolicyError> {
    loop {
        match ws.read().map_err(|e| ws_error(e, timeout, what))? {
            Message::Binary(b) => return Ok(b.to_vec()),
            Message::Text(t) => {
                return Err(PolicyError::Other(format!("policy server reported an error: {}", t.as_str().trim_end())));
            }
            Message::Close(frame) => {
                let why =
                    frame.map_or(String::new(), |f| format!(" (code {}, {:?})", u16::from(f.code), f.reason.as_str()));
                return Err(PolicyError::Connection(format!("server closed the connection {what}{why}")));
            }
            Message::Ping(_) | Message::Pong(_) | Message::Frame(_) => {}
        }
    }
}

/// Checks that the server sent no data message since its last reply (pings are answered on
/// the way): a reply nobody asked for would put every later chunk one request behind.
fn nothing_waiting(ws: &mut WebSocket<DeadlineStream>, timeout: Duration) -> Result<(), PolicyError> {
    let socket = |e: io::Error| PolicyError::Connection(format!("socket: {e}"));
    ws.get_ref().get_ref().set_nonblocking(true).map_err(socket)?;
    let found = loop {
        match ws.read() {
            Ok(Message::Ping(_) | Message::Pong(_) | Message::Frame(_)) => {}
            Ok(Message::Binary(_) | Message::Text(_)) => {
                break Err(PolicyError::Malformed(
                    "the server sent a message before this request (a second reply to an earlier one?)".into(),
                ));
            }
            Ok(Message::Close(_)) => {
                break Err(PolicyError::Connection("the server closed the connection since its last reply".into()));
            }
            Err(tungstenite::Error::Io(e)) if e.kind() == io::ErrorKind::WouldBlock => break Ok(()),
            Err(e) => break Err(ws_error(e, timeout, "before sending the observation")),
        }
    };
    ws.get_ref().get_ref().set_nonblocking(false).map_err(socket)?;
    found
}

fn ws_error(e: tungstenite::Error, timeout: Duration, what: &str) -> PolicyError {
    match e {
        tungstenite::Error::Io(io) if matches!(io.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut) => {
            PolicyError::Timeout(timeout.as_secs_f64())
        }
        tungstenite::Error::Capacity(c) => PolicyError::Malformed(format!("message too large {what}: {c}")),
        other => PolicyError::Connection(format!("{other} ({what})")),
    }
}

/// The msgpack request for one observation.
pub fn encode_request(obs: &Observation, image_size: u32) -> Result<Vec<u8>, PolicyError> {
    let side = image_size as usize;
    let mut entries = Vec::with_capacity(4);
    for (key, frame) in [("observation/image", &obs.agentview), ("observation/wrist_image", &obs.wrist)] {
        frame.validate().map_err(|e| PolicyError::Other(format!("{key}: {e}")))?;
        let img = image::openpi_image(frame, image_size);
        entries.push((Value::from(key), ndarray::encode_u8(&[side, side, 3], img.data)));
    }
    let state = obs.state8();
    if let Some(i) = state.iter().position(|v| !v.is_finite()) {
        return Err(PolicyError::Other(format!("observation/state[{i}] is {}", state[i])));
    }
    entries.push((Value::from("observation/state"), ndarray::encode_f64(&[8], &state)));
    entries.push((Value::from("prompt"), Value::from(obs.instruction.as_str())));
    let mut bytes = Vec::with_capacity(2 * side * side * 3 + 256);
    rmpv::encode::write_value(&mut bytes, &Value::Map(entries))
        .map_err(|e| PolicyError::Other(format!("encoding the request: {e}")))?;
    Ok(bytes)
}

/// Checks and decodes one reply.
pub fn parse_reply(bytes: &[u8]) -> Result<Reply, PolicyError> {
    let bad = |m: String| PolicyError::Malformed(m);
    let doc = ndarray::document(bytes, "reply").map_err(bad)?;
    let Value::Map(map) = doc else {
        return Err(bad(format!("reply is {}, expected a map with `actions`", ndarray::kind(&doc))));
    };
    let mut actions = None;
    let mut extra = Vec::new();
    for (k, v) in map {
        let key = ndarray::key_bytes(&k).map(|b| String::from_utf8_lossy(b).into_owned());
        match key.as_deref() {
            Some("actions") => actions = Some(v),
            Some(name) => extra.push((name.to_string(), v)),
            None => return Err(bad(format!("reply has a non-string key {k}"))),
        }
    }
    let keys: Vec<&str> = extra.iter().map(|(k, _)| k.as_str()).collect();
    let actions = actions.ok_or_else(|| bad(format!("reply has no `actions` (keys: {keys:?})")))?;
    let array = ndarray::decode(&actions)
        .map_err(|e| bad(format!("`actions`: {e}")))?
        .ok_or_else(|| bad(format!("`actions` is {}, expected a numpy array", ndarray::kind(&actions))))?;
    if array.shape.len() != 2 || array.shape[1] != 7 || array.shape[0] == 0 {
        return Err(bad(format!("`actions` has shape {:?}, expected (H, 7) with H >= 1", array.shape)));
    }
    let values = array.to_f64().map_err(|e| bad(format!("`actions`: {e}")))?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(bad(format!("`actions`[{}, {}] is {}", i / 7, i % 7, values[i])));
    }
    let actions = values.chunks_exact(7).map(|r| [r[0], r[1], r[2], r[3], r[4], r[5], r[6]]).collect();
    Ok(Reply { actions, extra })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reply(entries: Vec<(Value, Value)>) -> Vec<u8> {
        let mut b = Vec::new();
        rmpv::encode::write_value(&mut b, &Value::Map(entries)).unwrap();
        b
    }

    fn actions(rows: usize, cols: usize, value: f64) -> Value {
        ndarray::encode_f64(&[rows, cols], &vec![value; rows * cols])
    }

    #[test]
    fn good_replies_decode_and_keep_extras() {
        let f32s: Vec<u8> = (0..14).flat_map(|i| (i as f32 * 0.5).to_le_bytes()).collect();
        let r = parse_reply(&reply(vec![
            (Value::from("server_timing"), Value::Map(vec![(Value::from("infer_ms"), Value::F64(3.0))])),
            (Value::from("actions"), ndarray::encode("<f4", &[2, 7], f32s)),
        ]))
        .unwrap();
        assert_eq!(r.actions[1][0], 3.5);
        assert_eq!(r.extra[0].0, "server_timing");
    }

    #[test]
    fn malformed_replies_say_what_is_wrong() {
        let cases: Vec<(Vec<u8>, &str)> = vec![
            (vec![0x92, 0x01], "not a msgpack"),
            (reply(vec![(Value::from("policy_timing"), Value::Nil)]), "no `actions`"),
            (reply(vec![(Value::from("actions"), Value::from("go"))]), "expected a numpy array"),
            (reply(vec![(Value::from("actions"), actions(10, 8, 0.0))]), "shape [10, 8]"),
            (reply(vec![(Value::from("actions"), actions(0, 7, 0.0))]), "shape [0, 7]"),
            (reply(vec![(Value::from("actions"), actions(3, 7, f64::NAN))]), "`actions`[0, 0] is NaN"),
            (reply(vec![(Value::from("actions"), ndarray::encode("<f8", &[2, 7], vec![0; 8]))]), "needs 112 bytes"),
            ([reply(vec![(Value::from("actions"), actions(1, 7, 0.0))]), vec![0]].concat(), "unexpected bytes"),
            (vec![0x93, 1, 2, 3], "expected a map"),
        ];
        for (bytes, expected) in cases {
            match parse_reply(&bytes) {
                Err(PolicyError::Malformed(m)) => assert!(m.contains(expected), "{m:?} lacks {expected:?}"),
                other => panic!("{expected}: got {other:?}"),
            }
        }
    }

    #[test]
    fn addresses() {
        let (uri, address) = parse_url("localhost:8000").unwrap();
        assert_eq!((uri.to_string(), address.to_string()), ("ws://localhost:8000/".into(), "localhost:8000".into()));
        assert_eq!(parse_url("ws://h").unwrap().1.port, 80);
        // A port that is not one is refused, not read as ws://'s default 80.
        assert!(matches!(parse_url("ws://127.0.0.1:99999"), Err(PolicyError::Connection(m)) if m.contains("\"99999\"")));
        assert!(matches!(parse_url("wss://h:1"), Err(PolicyError::Connection(m)) if m.contains("TLS")));
        assert!(parse_url("http://h:1").is_err());
        assert!(matches!(RemotePolicy::connect("ws://127.0.0.1:1"), Err(PolicyError::Connection(_))));
    }
}
