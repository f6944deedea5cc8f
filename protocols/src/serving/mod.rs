//! Every serving path of the paper's VLAs behind one [`Policy`]: the URL scheme (and
//! `--policy-format` where a scheme is ambiguous) picks the wire format, a [`Profile`] the
//! model's observation and action conventions.
//!
//! | format | scheme | server |
//! |---|---|---|
//! | [`Format::Openpi`] | `ws://` | openpi `serve_policy.py`, our `serving/*_server.py` adapters |
//! | [`Format::InternVla`] | `ws://` + `--policy-format internvla` | InternVLA-A1.5's envelope over openpi's transport |
//! | [`Format::OpenVlaOft`] | `http://host:port/act` | OpenVLA-OFT `vla-scripts/deploy.py` (json_numpy) |
//! | [`Format::Xiaomi`] | `tcp://` | Xiaomi-Robotics-0 `deploy/server.py` (length prefix + pickle) |
//! | [`Format::LeRobot`] | `grpc://` | LeRobot async inference `policy_server.py` |
//!
//! A [`Transport`] turns one prepared observation ([`ModelInput`]) into one action chunk in
//! the model's own gripper convention; [`ServedPolicy`] does what every LIBERO client does
//! around it (prepare the observation per profile, queue the first `replan_steps` actions,
//! convert the gripper). Every malformed reply is a [`PolicyError::Malformed`] naming the
//! field; nothing panics. A [`PolicySpec`] turns a `--policy` string (a built-in's name or a
//! server's URL) into the policy a run makes.

pub mod internvla;
pub mod lerobot;
pub mod openpi;
pub mod openvla_oft;
pub mod pickle;
pub mod policy_spec;
pub mod profile;
pub mod xiaomi;

use std::collections::VecDeque;
use std::fmt;
use std::time::Duration;

use vifo_cues::RgbImage;

use crate::policy::{Observation, Policy, PolicyError};
pub use policy_spec::{PolicySpec, ServingOptions, Workers};
pub use profile::Profile;

/// A wire format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Openpi,
    InternVla,
    OpenVlaOft,
    Xiaomi,
    LeRobot,
}

impl Format {
    pub const ALL: [Format; 5] =
        [Format::Openpi, Format::InternVla, Format::OpenVlaOft, Format::Xiaomi, Format::LeRobot];

    /// `--policy-format` name.
    pub fn name(self) -> &'static str {
        match self {
            Format::Openpi => "openpi",
            Format::InternVla => "internvla",
            Format::OpenVlaOft => "openvla-oft",
            Format::Xiaomi => "xiaomi",
            Format::LeRobot => "lerobot",
        }
    }

    pub fn named(name: &str) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The URL scheme the format travels on.
    pub fn scheme(self) -> &'static str {
        match self {
            Format::Openpi | Format::InternVla => "ws",
            Format::OpenVlaOft => "http",
            Format::Xiaomi => "tcp",
            Format::LeRobot => "grpc",
        }
    }

    /// Checks `url`'s host, port (and LeRobot's query) for this format before anything
    /// connects, so that a mistake is one error up front rather than one per episode.
    pub fn check_url(self, url: &str) -> Result<(), PolicyError> {
        match self {
            Format::Openpi | Format::InternVla => crate::remote::parse_url(url).map(drop),
            Format::OpenVlaOft => openvla_oft::address(url).map(drop),
            Format::Xiaomi => xiaomi::address(url).map(drop),
            Format::LeRobot => lerobot::Setup::parse(url).map(drop),
        }
    }

    /// Whether the format's server holds one client at a time, so that a run must send it one
    /// episode at a time: Xiaomi's `deploy/server.py` accepts one connection at a time, and
    /// LeRobot's `policy_server` keeps one client's policy and observation queue (a second
    /// client's `Ready` resets them, and the two get each other's action chunks).
    pub fn serves_one_client(self) -> bool {
        matches!(self, Format::Xiaomi | Format::LeRobot)
    }

    /// The format of `url`: `explicit` when given (it must fit the scheme), else the
    /// profile's when its scheme fits, else the scheme's only or first format.
    pub fn resolve(url: &str, explicit: Option<Format>, profile: Option<&Profile>) -> Result<Format, PolicyError> {
        let scheme = url.split_once("://").map_or("ws", |(s, _)| s);
        let candidates: Vec<Format> = Format::ALL.into_iter().filter(|f| f.scheme() == scheme).collect();
        if candidates.is_empty() {
            return Err(PolicyError::Connection(format!(
                "{url}: unknown scheme {scheme:?}; expected ws://, http://, tcp:// or grpc://"
            )));
        }
        if let Some(f) = explicit {
            return if candidates.contains(&f) {
                Ok(f)
            } else {
                Err(PolicyError::Connection(format!(
                    "{url}: format {} travels on {}://, not {scheme}://",
                    f.name(),
                    f.scheme()
                )))
            };
        }
        Ok(profile.map(|p| p.format).filter(|f| candidates.contains(f)).unwrap_or(candidates[0]))
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One observation prepared as the profile says.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelInput {
    /// Third-person camera, oriented and sized for the model.
    pub image: RgbImage,
    /// Wrist camera, likewise.
    pub wrist: RgbImage,
    pub state: Vec<f64>,
    /// The instruction as the model's script formats it.
    pub instruction: String,
    /// First request of the episode.
    pub episode_start: bool,
    /// Control steps since the end of the settle phase.
    pub step: usize,
}

impl ModelInput {
    pub fn new(profile: &Profile, obs: &Observation, episode_start: bool) -> Result<ModelInput, PolicyError> {
        for (name, frame) in [("agentview", &obs.agentview), ("wrist", &obs.wrist)] {
            frame.validate().map_err(|e| PolicyError::Other(format!("{name} image: {e}")))?;
        }
        let state = profile.state(obs);
        if let Some(i) = state.iter().position(|v| !v.is_finite()) {
            return Err(PolicyError::Other(format!("state[{i}] is {}", state[i])));
        }
        Ok(ModelInput {
            image: profile.image(&obs.agentview),
            wrist: profile.image(&obs.wrist),
            state,
            instruction: profile.instruction(&obs.instruction),
            episode_start,
            step: obs.step,
        })
    }
}

/// One wire format's client.
pub trait Transport: Send {
    /// One request: the action chunk, rows of `[dx, dy, dz, dax, day, daz, gripper]` in the
    /// model's own gripper convention.
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError>;
    /// Called at the start of every episode (reconnect if the last one lost the server).
    fn reset(&mut self) -> Result<(), PolicyError> {
        Ok(())
    }
}

/// How to reach a server and which model it serves.
#[derive(Clone, Debug)]
pub struct ServingConfig {
    pub url: String,
    pub format: Format,
    pub profile: Profile,
    /// Side of the rendered frames (`--size`): what a profile without its own image size sends.
    pub frame_size: u32,
    /// TCP connect, handshake, metadata.
    pub connect_timeout: Duration,
    /// One request: sending the observation and receiving the whole reply.
    pub request_timeout: Duration,
    /// Name in results files; default `<profile>@<url>`.
    pub name: Option<String>,
}

impl ServingConfig {
    /// The name its records carry: `name`, or `<profile>@<url>`.
    pub fn policy_name(&self) -> String {
        self.name.clone().unwrap_or_else(|| format!("{}@{}", self.profile.name, self.url))
    }

    /// Whether the server holds one client at a time, so that a run must send it one episode at
    /// a time: its format's server does ([`Format::serves_one_client`]), or the profile's adapter
    /// keeps one episode's session for the whole server (`Profile::session`: a second client's
    /// reset would restart the first one's episode).
    pub fn serves_one_client(&self) -> bool {
        self.format.serves_one_client() || self.profile.session
    }

    /// `url` with `profile` (default: the profile of the URL's format), the format from the
    /// scheme and `format`.
    pub fn new(url: &str, format: Option<Format>, profile: Option<&Profile>) -> Result<ServingConfig, PolicyError> {
        let format = Format::resolve(url, format, profile)?;
        format.check_url(url)?;
        let profile = match profile {
            Some(p) => p.clone(),
            None => profile::PROFILES.iter().find(|p| p.format == format).cloned().expect("every format has a profile"),
        };
        Ok(ServingConfig {
            url: url.to_string(),
            format,
            profile,
            frame_size: 256,
            connect_timeout: Duration::from_secs(10),
            // First inferences compile or warm up CUDA kernels and can take minutes.
            request_timeout: Duration::from_secs(180),
            name: None,
        })
    }
}

/// A served model as a [`Policy`].
pub struct ServedPolicy {
    profile: Profile,
    name: String,
    transport: Box<dyn Transport>,
    queue: VecDeque<[f64; 7]>,
    episode_start: bool,
    requests: usize,
}

impl ServedPolicy {
    /// Connects with the format's transport.
    pub fn connect(config: &ServingConfig) -> Result<ServedPolicy, PolicyError> {
        let transport: Box<dyn Transport> = match config.format {
            Format::Openpi => Box::new(openpi::OpenpiTransport::connect(config)?),
            Format::InternVla => Box::new(internvla::InternVlaTransport::connect(config)?),
            Format::OpenVlaOft => Box::new(openvla_oft::OftTransport::new(config)?),
            Format::Xiaomi => Box::new(xiaomi::XiaomiTransport::connect(config)?),
            Format::LeRobot => Box::new(lerobot::LeRobotTransport::connect(config)?),
        };
        Ok(ServedPolicy::new(config.profile.clone(), config.policy_name(), transport))
    }

    /// A policy over any transport (tests use in-process ones).
    pub fn new(profile: Profile, name: String, transport: Box<dyn Transport>) -> ServedPolicy {
        ServedPolicy { profile, name, transport, queue: VecDeque::new(), episode_start: true, requests: 0 }
    }

    /// Requests sent so far.
    pub fn requests(&self) -> usize {
        self.requests
    }
}

impl Policy for ServedPolicy {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn reset(&mut self) -> Result<(), PolicyError> {
        self.queue.clear();
        self.episode_start = true;
        self.transport.reset()
    }

    /// Only when the queue is empty: the other steps play out the chunk.
    fn sees_images_next(&self) -> bool {
        self.queue.is_empty()
    }

    fn act(&mut self, obs: &Observation) -> Result<[f64; 7], PolicyError> {
        if self.queue.is_empty() {
            let input = ModelInput::new(&self.profile, obs, self.episode_start)?;
            self.requests += 1;
            let chunk = self.transport.infer(&input)?;
            self.episode_start = false;
            let executed = self.profile.executed(&chunk).filter(|rows| !rows.is_empty()).ok_or_else(|| {
                PolicyError::Malformed(format!(
                    "action chunk has {} rows, fewer than replan_steps = {}",
                    chunk.len(),
                    self.profile.used(chunk.len()).max(1)
                ))
            })?;
            let gripper = self.profile.gripper;
            self.queue.extend(executed.iter().map(|a| {
                let mut a = *a;
                a[6] = gripper.apply(a[6]);
                a
            }));
        }
        self.queue.pop_front().ok_or_else(|| PolicyError::Malformed("empty action chunk".into()))
    }
}

/// Rows of 7 from `values` laid out as `rows × cols` (the first 7 columns; `cols >= 7`),
/// checking every value is finite. `field` names the reply entry in errors.
pub fn rows7(values: &[f64], rows: usize, cols: usize, field: &str) -> Result<Vec<[f64; 7]>, PolicyError> {
    if cols < 7 || rows == 0 || values.len() != rows * cols {
        return Err(PolicyError::Malformed(format!(
            "`{field}` has {rows} rows of {cols}, expected at least 1 row of 7"
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(PolicyError::Malformed(format!("`{field}`[{}, {}] is {}", i / cols, i % cols, values[i])));
    }
    Ok(values.chunks_exact(cols).map(|r| [r[0], r[1], r[2], r[3], r[4], r[5], r[6]]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The servers a second client would disturb: Xiaomi's and LeRobot's, and the adapters
    /// that keep one episode's session for the whole server.
    #[test]
    fn servers_of_one_client_are_known_by_format_and_profile() {
        let one_client = |url: &str, profile: &str| {
            ServingConfig::new(url, None, Profile::named(profile)).unwrap().serves_one_client()
        };
        assert!(one_client("tcp://h:10086", "xiaomi") && one_client("grpc://h:8080?policy_type=act&pretrained=p", "molmoact2"));
        assert!(one_client("ws://h:8000", "instructvla") && one_client("ws://h:8000", "action-sketcher"));
        assert!(!one_client("ws://h:8000", "pi05") && !one_client("ws://h:10093", "internvla"));
        assert!(!one_client("http://h:8777/act", "openvla-oft"));
    }

    #[test]
    fn formats_follow_the_scheme() {
        let intern = Profile::named("internvla");
        assert_eq!(Format::resolve("ws://h:1", None, None).unwrap(), Format::Openpi);
        assert_eq!(Format::resolve("ws://h:1", None, intern).unwrap(), Format::InternVla);
        assert_eq!(Format::resolve("h:1", Some(Format::InternVla), None).unwrap(), Format::InternVla);
        assert_eq!(Format::resolve("http://h:8777/act", None, None).unwrap(), Format::OpenVlaOft);
        assert_eq!(Format::resolve("tcp://h:10086", None, intern).unwrap(), Format::Xiaomi);
        assert_eq!(Format::resolve("grpc://h:8080", None, None).unwrap(), Format::LeRobot);
        assert!(Format::resolve("tcp://h:1", Some(Format::Openpi), None).unwrap_err().to_string().contains("ws://"));
        assert!(Format::resolve("ftp://h:1", None, None).is_err());
        let c = ServingConfig::new("tcp://h:1", None, None).unwrap();
        assert_eq!(c.profile.name, "xiaomi");
    }

    /// A transport answering fixed chunks, to check the queue and the gripper conversion.
    struct Fixed(Vec<[f64; 7]>, Vec<bool>);

    impl Transport for Fixed {
        fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
            self.1.push(input.episode_start);
            Ok(self.0.clone())
        }
    }

    /// A small observation, for the transports' tests too.
    pub(super) fn observation() -> Observation {
        Observation {
            agentview: RgbImage::filled(8, 8, [1, 2, 3]).unwrap(),
            wrist: RgbImage::filled(8, 8, [4, 5, 6]).unwrap(),
            eef_pos: [0.0; 3],
            eef_quat_xyzw: [0.0, 0.0, 0.0, 1.0],
            gripper_qpos: [0.0; 2],
            joint_pos: [0.0; 7],
            instruction: "open the drawer".into(),
            step: 0,
        }
    }

    #[test]
    fn chunks_are_queued_and_grippers_converted() {
        let chunk: Vec<[f64; 7]> = (0..8).map(|i| [i as f64, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]).collect();
        let profile = Profile::named("openvla-oft").unwrap().clone();
        let mut p = ServedPolicy::new(profile, "t".into(), Box::new(Fixed(chunk, vec![])));
        p.reset().unwrap();
        let acts: Vec<[f64; 7]> = (0..10).map(|_| p.act(&observation()).unwrap()).collect();
        assert_eq!(p.requests(), 2);
        assert_eq!(acts[7][0], 7.0);
        assert_eq!(acts[8][0], 0.0);
        assert!(acts.iter().all(|a| a[6] == -1.0), "1 (open in RLDS) becomes -1 (open in LIBERO)");

        // A longer chunk: OpenVLA-OFT's loop keeps its last 8 (a `deque(maxlen=8)` extended
        // with it), openpi's its first 5.
        let long: Vec<[f64; 7]> = (0..10).map(|i| [i as f64, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]).collect();
        for (name, first, used) in [("openvla-oft", 2.0, 8), ("pi05", 0.0, 5)] {
            let profile = Profile::named(name).unwrap().clone();
            let mut p = ServedPolicy::new(profile, "t".into(), Box::new(Fixed(long.clone(), vec![])));
            let acts: Vec<[f64; 7]> = (0..used + 1).map(|_| p.act(&observation()).unwrap()).collect();
            assert_eq!((acts[0][0], acts[used - 1][0], acts[used][0], p.requests()), (first, first + used as f64 - 1.0, first, 2), "{name}");
        }

        let short = Profile::named("internvla").unwrap().clone();
        let mut p = ServedPolicy::new(short, "t".into(), Box::new(Fixed(vec![[0.0; 7]; 3], vec![])));
        let e = p.act(&observation()).unwrap_err();
        assert!(e.to_string().contains("3 rows, fewer than replan_steps = 8"), "{e}");
    }

    #[test]
    fn rows_name_the_field() {
        assert!(rows7(&[0.0; 14], 2, 7, "actions").is_ok());
        let e = rows7(&[0.0; 12], 2, 6, "actions").unwrap_err().to_string();
        assert!(e.contains("`actions` has 2 rows of 6"), "{e}");
        let mut v = vec![0.0; 16];
        v[9] = f64::NAN;
        assert!(rows7(&v, 2, 8, "data.actions").unwrap_err().to_string().contains("`data.actions`[1, 1] is NaN"));
    }
}
