//! A policy server's host and port, read from its URL before anything connects: a mistyped port
//! must be refused up front, never quietly become port 80, and a missing host or port must not
//! wait to become one error per episode.

use std::fmt;
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::Duration;

use crate::policy::PolicyError;

/// Host and port of `scheme://host[:port][/path][?query]` (an IPv6 host in brackets).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Address {
    /// Without the brackets of an IPv6 literal.
    pub host: String,
    pub port: u16,
}

impl Address {
    /// The address of `url`; `default_port` where its scheme has one (ws://, http://: 80),
    /// `None` where the port must be given.
    pub fn parse(url: &str, default_port: Option<u16>) -> Result<Address, PolicyError> {
        let bad = |m: String| PolicyError::Connection(format!("{url}: {m}"));
        let rest = url.split_once("://").map_or(url, |(_, r)| r);
        let authority = &rest[..rest.find(['/', '?', '#']).unwrap_or(rest.len())];
        if authority.contains('@') {
            return Err(bad("user names in server addresses are not supported".into()));
        }
        let (host, port) = match authority.strip_prefix('[') {
            Some(v6) => {
                let (host, after) = v6.split_once(']').ok_or_else(|| bad("the IPv6 host's `]` is missing".into()))?;
                let port = match after {
                    "" => None,
                    p => Some(p.strip_prefix(':').ok_or_else(|| bad(format!("{p:?} after the IPv6 host")))?),
                };
                (host, port)
            }
            None => match authority.rsplit_once(':') {
                Some((host, port)) => (host, Some(port)),
                None => (authority, None),
            },
        };
        if host.is_empty() {
            return Err(bad("no host (expected host:port)".into()));
        }
        let port = match port {
            Some(p) => p
                .parse::<u16>()
                .ok()
                .filter(|&p| p > 0)
                .ok_or_else(|| bad(format!("port {p:?} is not a number from 1 to 65535")))?,
            None => default_port.ok_or_else(|| bad("no port (expected host:port)".into()))?,
        };
        Ok(Address { host: host.to_string(), port })
    }

    /// The socket addresses the host resolves to.
    pub fn resolve(&self) -> Result<Vec<SocketAddr>, PolicyError> {
        (self.host.as_str(), self.port)
            .to_socket_addrs()
            .map(Iterator::collect)
            .map_err(|e| PolicyError::Connection(format!("cannot resolve {self}: {e}")))
    }

    /// A TCP connection to the first of its socket addresses that answers within `timeout`;
    /// the error names `url` and why the last one failed.
    pub fn connect(&self, url: &str, timeout: Duration) -> Result<TcpStream, PolicyError> {
        let mut last = None;
        for addr in &self.resolve()? {
            match TcpStream::connect_timeout(addr, timeout) {
                Ok(s) => {
                    s.set_nodelay(true).ok();
                    return Ok(s);
                }
                Err(e) => last = Some(e),
            }
        }
        let why = last.map_or("no address".to_string(), |e| e.to_string());
        Err(PolicyError::Connection(format!("cannot connect to {url}: {why}")))
    }
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.host.contains(':') {
            write!(f, "[{}]:{}", self.host, self.port)
        } else {
            write!(f, "{}:{}", self.host, self.port)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(url: &str, default_port: Option<u16>) -> Result<(String, u16), String> {
        Address::parse(url, default_port).map(|a| (a.host, a.port)).map_err(|e| e.to_string())
    }

    #[test]
    fn host_and_port_come_from_the_authority() {
        let ok = |h: &str, p| Ok((h.to_string(), p));
        assert_eq!(parse("ws://127.0.0.1:8000", Some(80)), ok("127.0.0.1", 8000));
        assert_eq!(parse("http://gpu-box:8777/act", Some(80)), ok("gpu-box", 8777));
        assert_eq!(parse("grpc://h:8080?policy_type=a&pretrained=b:c", None), ok("h", 8080));
        assert_eq!(parse("ws://[::1]:9000/x", Some(80)), ok("::1", 9000));
        assert_eq!(parse("ws://policy-host", Some(80)), ok("policy-host", 80));
        assert_eq!(parse("http://h/act", Some(80)), ok("h", 80));
        assert_eq!(Address::parse("ws://[::1]:9000", None).unwrap().to_string(), "[::1]:9000");
    }

    #[test]
    fn a_bad_port_or_a_missing_part_is_named() {
        for (url, default_port, says) in [
            ("ws://127.0.0.1:99999", Some(80), "port \"99999\""),
            ("http://127.0.0.1:notaport/act", Some(80), "port \"notaport\""),
            ("tcp://127.0.0.1:0", None, "port \"0\""),
            ("ws://h:", Some(80), "port \"\""),
            ("tcp://127.0.0.1", None, "no port"),
            ("grpc://h?policy_type=a&pretrained=b", None, "no port"),
            ("ws://:8000", Some(80), "no host"),
            ("http:///act", Some(80), "no host"),
            ("ws://[::1:8000", Some(80), "`]` is missing"),
            ("ws://[::1]8000", Some(80), "after the IPv6 host"),
            ("ws://me@h:1", Some(80), "user names"),
        ] {
            let e = parse(url, default_port).unwrap_err();
            assert!(e.contains(url) && e.contains(says), "{url}: {e}");
        }
    }
}
