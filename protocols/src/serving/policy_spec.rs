//! A `--policy` string (`vifo run`, Python's `policy=`) resolved once into what a run needs:
//! the name its records carry, whether it looks at the images, whether its server holds one
//! client at a time, and how each worker gets its policy. `vifo run` and the Python package both
//! take policies through it, so the two name and reach a policy alike.

use std::sync::Mutex;
use std::time::Duration;

use super::{Format, Profile, ServedPolicy, ServingConfig};
use crate::policies::{self, builtin};
use crate::policy::{Policy, PolicyError};
use crate::remote::{RemoteConfig, RemotePolicy};

/// How a server named by a `--policy` string is talked to: `vifo run`'s `--model-profile`,
/// `--policy-format`, `--size`, `--policy-timeout` and `--policy-name`.
#[derive(Clone, Debug)]
pub struct ServingOptions<'a> {
    pub profile: Option<&'a Profile>,
    pub format: Option<Format>,
    /// Side of the rendered frames: what a profile without its own image size sends.
    pub frame_size: u32,
    /// One request's limit; `None`: the client's default.
    pub request_timeout: Option<Duration>,
    /// The name the server's records carry instead of `<profile>@<url>` (a built-in's records
    /// always carry its own).
    pub name: Option<String>,
}

/// A policy as a `--policy` string names it: a built-in, or a server.
#[derive(Clone, Debug)]
pub struct PolicySpec {
    /// The string as given.
    policy: String,
    reach: Reach,
}

#[derive(Clone, Debug)]
enum Reach {
    Builtin,
    /// Plain `ws://` without a profile or format: openpi's own LIBERO client (pi0.5's).
    Openpi(RemoteConfig),
    Served(ServingConfig),
}

impl PolicySpec {
    /// Resolves `policy`: a built-in name, or a server URL talked to as `serving` says.
    /// `serving` is asked for only where `policy` is a server, so that options which mean
    /// nothing to a built-in (a mistyped `--model-profile`) are the caller's to refuse.
    pub fn new<'a, E: From<PolicyError>>(
        policy: &str,
        serving: impl FnOnce() -> Result<ServingOptions<'a>, E>,
    ) -> Result<PolicySpec, E> {
        let reach = if builtin(policy).is_some() {
            Reach::Builtin
        } else if !policy.contains("://") {
            return Err(PolicyError::Other(format!(
                "unknown policy {policy:?}: expected one of {} or a server URL (ws://, http://, tcp://, grpc://)",
                policies::NAMES.join(", ")
            ))
            .into());
        } else {
            let o = serving()?;
            if policy.starts_with("ws://") && o.profile.is_none() && o.format.is_none() {
                crate::remote::parse_url(policy)?;
                let config = RemoteConfig::new(policy);
                Reach::Openpi(RemoteConfig {
                    request_timeout: o.request_timeout.unwrap_or(config.request_timeout),
                    name: o.name,
                    ..config
                })
            } else {
                let config = ServingConfig::new(policy, o.format, o.profile)?;
                Reach::Served(ServingConfig {
                    frame_size: o.frame_size,
                    request_timeout: o.request_timeout.unwrap_or(config.request_timeout),
                    name: o.name,
                    ..config
                })
            }
        };
        Ok(PolicySpec { policy: policy.to_string(), reach })
    }

    /// The string as given (a built-in's name or a server's URL).
    pub fn policy(&self) -> &str {
        &self.policy
    }

    /// The name its records carry, and a resumed file must hold: a built-in's own, or the
    /// given name, else `<profile>@<url>` (plain ws://: `openpi@<url>`).
    pub fn record_name(&self) -> String {
        match &self.reach {
            Reach::Builtin => self.policy.clone(),
            Reach::Openpi(c) => c.policy_name(),
            Reach::Served(c) => c.policy_name(),
        }
    }

    /// What its results file is named by (`vifo run`'s `results-<this, file-safe>.jsonl`): the
    /// given name, else the string as given (a server's URL, not its record name).
    pub fn results_label(&self) -> &str {
        let given = match &self.reach {
            Reach::Builtin => None,
            Reach::Openpi(c) => c.name.as_deref(),
            Reach::Served(c) => c.name.as_deref(),
        };
        given.unwrap_or(&self.policy)
    }

    pub fn is_builtin(&self) -> bool {
        matches!(self.reach, Reach::Builtin)
    }

    /// The format and profile of a server other than a plain ws:// openpi one.
    pub fn served(&self) -> Option<&ServingConfig> {
        match &self.reach {
            Reach::Served(c) => Some(c),
            _ => None,
        }
    }

    /// Whether it looks at the images (a built-in expert reads the simulator): where it does
    /// not, the cameras need not be drawn.
    pub fn uses_images(&self) -> bool {
        match self.reach {
            Reach::Builtin => builtin(&self.policy).is_some_and(|p| p.uses_images()),
            _ => true,
        }
    }

    /// Whether its server must be sent one episode at a time ([`ServingConfig::serves_one_client`]).
    pub fn serves_one_client(&self) -> bool {
        self.served().is_some_and(ServingConfig::serves_one_client)
    }

    /// A fresh policy: a new built-in, or a new connection to the server.
    pub fn connect(&self) -> Result<Box<dyn Policy>, PolicyError> {
        Ok(match &self.reach {
            Reach::Builtin => {
                builtin(&self.policy).ok_or_else(|| PolicyError::Other(format!("no built-in policy {}", self.policy)))?
            }
            Reach::Openpi(c) => Box::new(RemotePolicy::with_config(c.clone())?),
            Reach::Served(c) => Box::new(ServedPolicy::connect(c)?),
        })
    }

    /// The workers' policies, with a server's first connection made now, before any episode:
    /// a server that is not up is then one error up front instead of every episode's. The
    /// first worker gets that connection.
    pub fn workers(&self) -> Result<Workers<'_>, PolicyError> {
        let first = if self.is_builtin() { None } else { Some(self.connect()?) };
        Ok(Workers { spec: self, first: Mutex::new(first) })
    }
}

/// Makes each worker's policy ([`PolicySpec::workers`]).
pub struct Workers<'a> {
    spec: &'a PolicySpec,
    first: Mutex<Option<Box<dyn Policy>>>,
}

impl Workers<'_> {
    /// One worker's policy, as `env::rollout::run_episodes` asks for it.
    pub fn make(&self) -> Result<Box<dyn Policy>, String> {
        match self.first.lock().unwrap_or_else(|p| p.into_inner()).take() {
            Some(policy) => Ok(policy),
            None => self.spec.connect().map_err(|e| e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(policy: &str, profile: Option<&str>, name: Option<&str>) -> Result<PolicySpec, PolicyError> {
        PolicySpec::new(policy, || {
            Ok::<_, PolicyError>(ServingOptions {
                profile: profile.and_then(Profile::named),
                format: None,
                frame_size: 256,
                request_timeout: None,
                name: name.map(str::to_string),
            })
        })
    }

    /// Record names and results file names as `vifo run` has always given them.
    #[test]
    fn policies_are_named_as_vifo_run_names_them() {
        let named = |p: &str, profile, name| {
            let s = spec(p, profile, name).unwrap();
            (s.record_name(), s.results_label().to_string(), s.serves_one_client(), s.uses_images())
        };
        let s = |x: &str| x.to_string();
        assert_eq!(named("expert-cue", None, None), (s("expert-cue"), s("expert-cue"), false, false));
        assert_eq!(named("ws://h:8000", None, None), (s("openpi@ws://h:8000"), s("ws://h:8000"), false, true));
        assert_eq!(named("ws://h:8000", Some("pi05"), None), (s("pi05@ws://h:8000"), s("ws://h:8000"), false, true));
        assert_eq!(named("tcp://h:10086", None, Some("x0")), (s("x0"), s("x0"), true, true));
        assert_eq!(named("ws://h:8000", None, Some("pi")), (s("pi"), s("pi"), false, true));
        assert!(spec("ws://h:8000", None, None).unwrap().served().is_none());
    }

    /// A built-in never asks for the serving options (a mistyped profile beside it is the
    /// caller's to name); a bad name or URL is refused before anything connects.
    #[test]
    fn builtins_ask_for_no_serving_options_and_bad_policies_are_refused() {
        let refused = || Err::<ServingOptions, _>(PolicyError::Other("asked".into()));
        assert!(PolicySpec::new("zero", refused).unwrap().is_builtin());
        assert_eq!(PolicySpec::new("ws://h:1", refused).unwrap_err().to_string(), "asked");
        let e = spec("h:8000", None, None).unwrap_err().to_string();
        assert!(e.starts_with("unknown policy \"h:8000\": expected one of expert-cue,"), "{e}");
        assert!(spec("tcp://h", None, None).unwrap_err().to_string().contains("no port"));
    }

    /// A server that is not up is one error before any episode.
    #[test]
    fn workers_of_a_server_that_is_not_up_are_refused_up_front() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let url = format!("ws://{}", listener.local_addr().unwrap());
        drop(listener);
        let e = spec(&url, None, None).unwrap().workers().err().expect("nothing listens").to_string();
        assert!(e.contains("cannot connect"), "{e}");
        let zero = spec("zero", None, None).unwrap();
        let workers = zero.workers().unwrap();
        assert_eq!(workers.make().unwrap().name(), "zero");
    }
}
