//! LeRobot's async inference server (`src/lerobot/async_inference/policy_server.py`, service
//! `transport.AsyncInference` in `src/lerobot/transport/services.proto`), used synchronously:
//! one observation, then its action chunk.
//!
//! `grpc://host:port?policy_type=<type>&pretrained=<name or path>[&device=cuda]
//! [&actions_per_chunk=10][&wrist=wrist_image][&kw.<name>=<value>…]`. At connect: `Ready`, then
//! `SendPolicyInstructions` with a pickled `RemotePolicyConfig(policy_type,
//! pretrained_name_or_path, lerobot_features, actions_per_chunk, device, rename_map,
//! policy_kwargs)`; `policy_kwargs` (the `kw.` keys, as strings: MolmoAct2's vendored server
//! reads it, e.g. `kw.norm_tag=libero&kw.inference_action_mode=continuous`) is an extra
//! attribute that upstream LeRobot ignores. Per request: `SendObservations`, a client stream of
//! `Observation{transfer_state, data}` chunks (2 MiB each; BEGIN, MIDDLE…, END; a single chunk
//! is END) of a pickled `TimedObservation(timestamp, timestep, observation, must_go=True)`, then
//! `GetActions`, whose `Actions.data` is a pickled `list[TimedAction(timestamp, timestep,
//! action)]` with one torch tensor (7,) per action. The server answers an empty `Actions` when
//! no observation arrived in time and when the policy raised on it; the observation was sent
//! and queued (`must_go`) before `GetActions`, so an empty answer is the policy's failure, an
//! error naming the server's log, not a reason to ask again.
//!
//! The raw observation is what a LeRobot robot reports: one float per state name (LIBERO's
//! 8-D state, named below), the cameras `image` (agentview) and the wrist camera (`wrist=`,
//! default `wrist_image`, the name MolmoAct2's LIBERO evaluation maps robot0_eye_in_hand to;
//! LeRobot's LIBERO env default is `image2`) as uint8 H×W×3 arrays, and `task`. `lerobot_features`
//! describes them as `hw_to_dataset_features` would. The async server runs only the policy's
//! processors, so frames and state arrive already as lerobot-eval's `LiberoProcessorStep`
//! makes them (the profile's job).
//!
//! Hand-written prost messages (the proto has five one-field messages), no protoc, no TLS.

use std::time::{Duration, SystemTime, UNIX_EPOCH};

use tonic::client::Grpc;
use tonic::codegen::http::uri::PathAndQuery;
use tonic::transport::{Channel, Endpoint};
use tonic_prost::ProstCodec;

use super::pickle::{self, Value, Writer};
use super::{ModelInput, ServingConfig, Transport, rows7};
use crate::policy::PolicyError;

/// `services.proto` messages.
#[derive(Clone, PartialEq, prost::Message)]
pub struct Empty {}

#[derive(Clone, PartialEq, prost::Message)]
pub struct Observation {
    /// `TransferState`: 1 BEGIN, 2 MIDDLE, 3 END.
    #[prost(int32, tag = "1")]
    pub transfer_state: i32,
    #[prost(bytes = "vec", tag = "2")]
    pub data: Vec<u8>,
}

#[derive(Clone, PartialEq, prost::Message)]
pub struct Actions {
    #[prost(bytes = "vec", tag = "1")]
    pub data: Vec<u8>,
}

#[derive(Clone, PartialEq, prost::Message)]
pub struct PolicySetup {
    #[prost(bytes = "vec", tag = "1")]
    pub data: Vec<u8>,
}

/// LeRobot's `CHUNK_SIZE` for streamed observations.
const CHUNK: usize = 2 << 20;
const HELPERS: &str = "lerobot.async_inference.helpers";
/// Names of the 8 state entries in the raw observation.
pub const STATE_NAMES: [&str; 8] =
    ["x", "y", "z", "axis_angle_x", "axis_angle_y", "axis_angle_z", "gripper_left", "gripper_right"];

/// The policy setup, from the URL's query.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    pub endpoint: String,
    pub policy_type: String,
    pub pretrained: String,
    pub device: String,
    pub actions_per_chunk: usize,
    /// The wrist camera's name in the observation and its features.
    pub wrist: String,
    /// `kw.<name>=<value>` entries, sent as `RemotePolicyConfig.policy_kwargs`.
    pub policy_kwargs: Vec<(String, String)>,
}

impl Setup {
    pub fn parse(url: &str) -> Result<Setup, PolicyError> {
        let bad = |m: String| PolicyError::Connection(format!("{url}: {m}"));
        let rest = url.strip_prefix("grpc://").ok_or_else(|| bad("expected grpc://host:port?…".into()))?;
        let query = rest.split_once('?').map_or("", |(_, q)| q);
        let address = crate::remote::Address::parse(url, None)?;
        let mut setup = Setup {
            endpoint: format!("http://{address}"),
            policy_type: String::new(),
            pretrained: String::new(),
            device: "cuda".into(),
            actions_per_chunk: 10,
            wrist: "wrist_image".into(),
            policy_kwargs: Vec::new(),
        };
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (k, v) = pair.split_once('=').ok_or_else(|| bad(format!("query entry {pair:?} is not key=value")))?;
            match k {
                "policy_type" => setup.policy_type = v.into(),
                "pretrained" => setup.pretrained = v.into(),
                "device" => setup.device = v.into(),
                "wrist" if !v.is_empty() && v != "image" => setup.wrist = v.into(),
                "wrist" => return Err(bad(format!("wrist {v:?}: expected the wrist camera's name, other than image"))),
                k if k.starts_with("kw.") && k.len() > 3 => setup.policy_kwargs.push((k[3..].into(), v.into())),
                "actions_per_chunk" => {
                    setup.actions_per_chunk =
                        v.parse().ok().filter(|&n| n > 0).ok_or_else(|| bad(format!("actions_per_chunk {v:?}")))?
                }
                other => return Err(bad(format!("unknown query key {other:?}"))),
            }
        }
        if setup.policy_type.is_empty() || setup.pretrained.is_empty() {
            return Err(bad("the server loads the policy the client names: add ?policy_type=…&pretrained=…".into()));
        }
        Ok(setup)
    }
}

pub struct LeRobotTransport {
    runtime: tokio::runtime::Runtime,
    grpc: Grpc<Channel>,
    timeout: Duration,
    setup: Setup,
    image_side: usize,
    timestep: i64,
    /// A request failed: the server may have restarted since its policy was set up (gRPC
    /// reconnects by itself, to a server that has none), so the next episode sets it up again.
    set_up_again: bool,
}

/// An error with its causes: tonic's own says only "transport error", its sources why.
fn causes(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(&format!(": {s}"));
        source = s.source();
    }
    text
}

fn status(e: tonic::Status, timeout: Duration, what: &str) -> PolicyError {
    match e.code() {
        tonic::Code::Unavailable => PolicyError::Connection(format!("{what}: {}", e.message())),
        tonic::Code::DeadlineExceeded => PolicyError::Timeout(timeout.as_secs_f64()),
        code => PolicyError::Other(format!("policy server error in {what} ({code:?}): {}", e.message())),
    }
}

impl LeRobotTransport {
    pub fn connect(config: &ServingConfig) -> Result<LeRobotTransport, PolicyError> {
        let setup = Setup::parse(&config.url)?;
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .map_err(|e| PolicyError::Other(format!("cannot start the gRPC runtime: {e}")))?;
        let endpoint = Endpoint::from_shared(setup.endpoint.clone())
            .map_err(|e| PolicyError::Connection(format!("{}: {e}", config.url)))?
            .connect_timeout(config.connect_timeout);
        let channel = runtime
            .block_on(endpoint.connect())
            .map_err(|e| PolicyError::Connection(format!("cannot connect to {}: {}", config.url, causes(&e))))?;
        let grpc = Grpc::new(channel).max_decoding_message_size(64 << 20);
        let mut t = LeRobotTransport {
            runtime,
            grpc,
            timeout: config.request_timeout,
            setup,
            image_side: config.profile.image_size.unwrap_or(config.frame_size) as usize,
            timestep: 0,
            set_up_again: false,
        };
        t.set_up()?;
        Ok(t)
    }

    /// Tells the server a client is ready and which policy to load.
    fn set_up(&mut self) -> Result<(), PolicyError> {
        self.unary::<Empty, Empty>("Ready", Empty {})?;
        let data = policy_setup(&self.setup, self.image_side);
        self.unary::<PolicySetup, Empty>("SendPolicyInstructions", PolicySetup { data })?;
        Ok(())
    }

    fn request(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let timestep = self.timestep;
        self.timestep += 1;
        let now = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0.0, |d| d.as_secs_f64());
        self.send_observation(observation(input, &self.setup.wrist, timestep, now))?;
        let reply: Actions = self.unary("GetActions", Empty {})?;
        if reply.data.is_empty() {
            return Err(PolicyError::Other(format!(
                "the server answered no actions for observation #{timestep}: its policy failed on it \
                 (LeRobot answers an empty chunk when the policy raises; the server's log has the error)"
            )));
        }
        parse(&reply.data, timestep)
    }

    fn unary<A, B>(&mut self, method: &'static str, message: A) -> Result<B, PolicyError>
    where
        A: prost::Message + Send + Sync + 'static,
        B: prost::Message + Default + Send + Sync + 'static,
    {
        let timeout = self.timeout;
        let grpc = &mut self.grpc;
        let call = async move {
            grpc.ready().await.map_err(|e| PolicyError::Connection(format!("{method}: {e}")))?;
            let path = PathAndQuery::from_static(path(method));
            let reply = grpc
                .unary(tonic::Request::new(message), path, ProstCodec::<A, B>::default())
                .await
                .map_err(|e| status(e, timeout, method))?;
            Ok(reply.into_inner())
        };
        self.runtime
            .block_on(async { tokio::time::timeout(timeout, call).await })
            .map_err(|_| PolicyError::Timeout(timeout.as_secs_f64()))?
    }

    fn send_observation(&mut self, bytes: Vec<u8>) -> Result<(), PolicyError> {
        let timeout = self.timeout;
        let n = bytes.len().div_ceil(CHUNK).max(1);
        let chunks: Vec<Observation> = (0..n)
            .map(|i| Observation {
                transfer_state: if i + 1 == n {
                    3
                } else if i == 0 {
                    1
                } else {
                    2
                },
                data: bytes[i * CHUNK..((i + 1) * CHUNK).min(bytes.len())].to_vec(),
            })
            .collect();
        let grpc = &mut self.grpc;
        let call = async move {
            grpc.ready().await.map_err(|e| PolicyError::Connection(format!("SendObservations: {e}")))?;
            grpc.client_streaming(
                tonic::Request::new(tokio_stream::iter(chunks)),
                PathAndQuery::from_static(path("SendObservations")),
                ProstCodec::<Observation, Empty>::default(),
            )
            .await
            .map(|_| ())
            .map_err(|e| status(e, timeout, "SendObservations"))
        };
        self.runtime
            .block_on(async { tokio::time::timeout(timeout, call).await })
            .map_err(|_| PolicyError::Timeout(timeout.as_secs_f64()))?
    }
}

fn path(method: &str) -> &'static str {
    match method {
        "Ready" => "/transport.AsyncInference/Ready",
        "SendPolicyInstructions" => "/transport.AsyncInference/SendPolicyInstructions",
        "SendObservations" => "/transport.AsyncInference/SendObservations",
        _ => "/transport.AsyncInference/GetActions",
    }
}

/// A dataclass instance as pickle writes it: `cls.__new__(cls)`, then `__dict__` from `fields`.
fn dataclass(w: &mut Writer, class: &str, fields: impl FnOnce(&mut Writer)) {
    w.global(HELPERS, class);
    w.empty_tuple();
    w.newobj();
    w.begin_dict();
    fields(w);
    w.end_dict();
    w.build();
}

/// A feature entry of `hw_to_dataset_features`: `{"dtype", "shape", "names"}`.
fn feature(w: &mut Writer, dtype: &str, shape: &[usize], names: &[&str]) {
    w.begin_dict();
    w.str("dtype");
    w.str(dtype);
    w.str("shape");
    w.int_tuple(shape);
    w.str("names");
    w.begin_list();
    for n in names {
        w.str(n);
    }
    w.end_list();
    w.end_dict();
}

/// The pickled `RemotePolicyConfig`.
pub fn policy_setup(setup: &Setup, image_side: usize) -> Vec<u8> {
    let mut w = Writer::default();
    dataclass(&mut w, "RemotePolicyConfig", |w| {
        w.str("policy_type");
        w.str(&setup.policy_type);
        w.str("pretrained_name_or_path");
        w.str(&setup.pretrained);
        w.str("lerobot_features");
        w.begin_dict();
        w.str("observation.state");
        feature(w, "float32", &[8], &STATE_NAMES);
        for camera in ["image", setup.wrist.as_str()] {
            w.str(&format!("observation.images.{camera}"));
            feature(w, "image", &[image_side, image_side, 3], &["height", "width", "channels"]);
        }
        w.end_dict();
        w.str("actions_per_chunk");
        w.int(setup.actions_per_chunk as i64);
        w.str("device");
        w.str(&setup.device);
        w.str("rename_map");
        w.begin_dict();
        w.end_dict();
        w.str("policy_kwargs");
        w.begin_dict();
        for (k, v) in &setup.policy_kwargs {
            w.str(k);
            w.str(v);
        }
        w.end_dict();
    });
    w.finish()
}

/// The pickled `TimedObservation`, the wrist frame named `wrist`.
pub fn observation(input: &ModelInput, wrist: &str, timestep: i64, timestamp: f64) -> Vec<u8> {
    let mut w = Writer::default();
    dataclass(&mut w, "TimedObservation", |w| {
        w.str("timestamp");
        w.float(timestamp);
        w.str("timestep");
        w.int(timestep);
        w.str("observation");
        w.begin_dict();
        for (name, v) in STATE_NAMES.iter().zip(&input.state) {
            w.str(name);
            w.float(*v);
        }
        for (camera, img) in [("image", &input.image), (wrist, &input.wrist)] {
            w.str(camera);
            w.ndarray("|u1", &[img.height as usize, img.width as usize, 3], &img.data);
        }
        w.str("task");
        w.str(&input.instruction);
        w.end_dict();
        w.str("must_go");
        w.bool(true);
    });
    w.finish()
}

/// Checks and decodes `Actions.data`: the chunk answering the observation of `timestep`.
pub fn parse(data: &[u8], timestep: i64) -> Result<Vec<[f64; 7]>, PolicyError> {
    let bad = |m: String| PolicyError::Malformed(m);
    let v = pickle::read_all(data).map_err(|e| bad(format!("`Actions.data` is not a pickle: {e}")))?;
    let Value::List(items) = v else {
        return Err(bad(format!("`Actions.data` is {}, expected a list of TimedAction", v.kind())));
    };
    if items.is_empty() {
        return Err(bad("`Actions.data` is an empty list".into()));
    }
    let mut values = Vec::new();
    let mut cols = 0;
    for (i, item) in items.iter().enumerate() {
        let Value::Call { state: Some(state), .. } = item else {
            return Err(bad(format!("`actions[{i}]` is {}, expected a TimedAction", item.kind())));
        };
        let expected = timestep + i as i64;
        match state.get("timestep") {
            Some(Value::Int(t)) if *t == expected => {}
            other => {
                return Err(bad(format!(
                    "`actions[{i}].timestep` is {}, expected {expected} (the answer to another observation?)",
                    other.map_or("missing".into(), |v| format!("{v:?}"))
                )));
            }
        }
        let action = state.get("action").ok_or_else(|| bad(format!("`actions[{i}]` has no `action`")))?;
        let t = pickle::tensor(action).map_err(|e| bad(format!("`actions[{i}].action`: {e}")))?;
        if t.shape.len() != 1 || t.shape[0] < 7 || (cols != 0 && t.shape[0] != cols) {
            return Err(bad(format!("`actions[{i}].action` has shape {:?}, expected (7,)", t.shape)));
        }
        cols = t.shape[0];
        values.extend(t.values);
    }
    rows7(&values, items.len(), cols, "actions")
}

impl Transport for LeRobotTransport {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        let reply = self.request(input);
        self.set_up_again |= reply.is_err();
        reply
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        if self.set_up_again {
            self.set_up()?;
            self.set_up_again = false;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setups_come_from_the_url() {
        let s = Setup::parse("grpc://127.0.0.1:8080?policy_type=pi0&pretrained=lerobot/pi0_libero&device=cpu").unwrap();
        assert_eq!(s.endpoint, "http://127.0.0.1:8080");
        assert_eq!((s.policy_type.as_str(), s.device.as_str(), s.actions_per_chunk), ("pi0", "cpu", 10));
        let e = Setup::parse("grpc://h:1").unwrap_err().to_string();
        assert!(e.contains("policy_type"), "{e}");
        assert!(Setup::parse("grpc://h:1?policy_type=a&pretrained=b&colour=red").is_err());
        assert!(Setup::parse("grpc://h:1?policy_type=a&pretrained=b&actions_per_chunk=0").is_err());
        assert_eq!(s.wrist, "wrist_image");
        let s = Setup::parse("grpc://h:1?policy_type=a&pretrained=b&wrist=image2&kw.norm_tag=libero").unwrap();
        assert_eq!((s.wrist.as_str(), &s.policy_kwargs[..]), ("image2", &[("norm_tag".to_string(), "libero".to_string())][..]));
        assert!(Setup::parse("grpc://h:1?policy_type=a&pretrained=b&wrist=image").is_err());
        assert!(Setup::parse("grpc://h:1?policy_type=a&pretrained=b&kw.=x").is_err());
    }
}
