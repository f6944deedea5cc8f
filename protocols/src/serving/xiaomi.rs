//! Xiaomi-Robotics-0's TCP server (`deploy/server.py`, client `deploy/client.py`, LIBERO loop
//! `eval_libero/main.py`): every message is a 4-byte big-endian length and a pickle.
//!
//! Request (a dict, keys in the script's order): `task_id` `"libero_all"`, `state` (numpy
//! `<f8` (32,): the 8-D LIBERO state and 24 zeros), `base` and `wrist_left` (`PIL.Image` RGB
//! 256×256 of the rotated frames), `language` (`task.capitalize() + "."`) and `seed`: the
//! script's `hash_data_to_seed` of the other entries (before the period is added): SHA-256 of
//! their canonical JSON (sorted keys, no spaces; arrays as dtype, shape and hex data, images
//! as mode, size and the MD5 of their bytes), modulo 2³².
//! Reply: `pickle.dumps(action.cpu())`, a torch tensor (1, T, D); the client keeps
//! `[0, :, :-1]` and of each row the first 7 values.
//!
//! The server accepts one connection at a time (`Format::serves_one_client`): `vifo run`
//! sends it one episode at a time.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

use md5::{Digest, Md5};
use sha2::Sha256;

use super::pickle::{self, Writer};
use super::{ModelInput, ServingConfig, Transport, rows7};
use crate::policy::PolicyError;
use crate::remote::Address;
use crate::remote::deadline::DeadlineStream;

/// Replies above this size are refused (a LIBERO chunk is a few kB).
const MAX_REPLY: usize = 64 << 20;

pub struct XiaomiTransport {
    address: Address,
    connect_timeout: Duration,
    request_timeout: Duration,
    conn: Option<DeadlineStream>,
}

impl XiaomiTransport {
    pub fn connect(config: &ServingConfig) -> Result<XiaomiTransport, PolicyError> {
        let mut t = XiaomiTransport {
            address: address(&config.url)?,
            connect_timeout: config.connect_timeout,
            request_timeout: config.request_timeout,
            conn: None,
        };
        t.open()?;
        Ok(t)
    }

    fn open(&mut self) -> Result<(), PolicyError> {
        let s = self.address.connect(&format!("tcp://{}", self.address), self.connect_timeout)?;
        self.conn = Some(DeadlineStream::new(s, self.request_timeout));
        Ok(())
    }

    fn exchange(&mut self, request: &[u8]) -> Result<Vec<u8>, PolicyError> {
        let timeout = self.request_timeout;
        let conn = self.conn.as_mut().ok_or_else(|| PolicyError::Connection("not connected".into()))?;
        let io = |e: std::io::Error, what: &str| match e.kind() {
            std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut => {
                PolicyError::Timeout(timeout.as_secs_f64())
            }
            _ => PolicyError::Connection(format!("{what}: {e}")),
        };
        nothing_waiting(conn.get_ref())?;
        conn.limit(timeout);
        let len = u32::try_from(request.len()).map_err(|_| PolicyError::Other("request over 4 GiB".into()))?;
        conn.write_all(&len.to_be_bytes())
            .and_then(|()| conn.write_all(request))
            .map_err(|e| io(e, "sending the observation"))?;
        let mut prefix = [0u8; 4];
        conn.read_exact(&mut prefix)
            .map_err(|e| io(e, "waiting for the reply (the server closes the connection when the model raises)"))?;
        let n = u32::from_be_bytes(prefix) as usize;
        if n > MAX_REPLY {
            return Err(PolicyError::Malformed(format!("reply length prefix says {n} bytes, more than {MAX_REPLY}")));
        }
        let mut body = vec![0u8; n];
        conn.read_exact(&mut body).map_err(|e| io(e, "reading the reply"))?;
        Ok(body)
    }
}

/// The server's address: `tcp://host:port`.
pub fn address(url: &str) -> Result<Address, PolicyError> {
    if !url.starts_with("tcp://") {
        return Err(PolicyError::Connection(format!("{url}: expected tcp://host:port")));
    }
    Address::parse(url, None)
}

/// Checks that the server sent nothing since its last reply: a reply nobody asked for would
/// put every later chunk one request behind.
fn nothing_waiting(conn: &TcpStream) -> Result<(), PolicyError> {
    let peeked = conn.set_nonblocking(true).and_then(|()| conn.peek(&mut [0u8; 1]));
    conn.set_nonblocking(false).map_err(|e| PolicyError::Connection(format!("socket: {e}")))?;
    match peeked {
        Ok(0) => Err(PolicyError::Connection("the server closed the connection since its last reply".into())),
        Ok(_) => Err(PolicyError::Malformed(
            "the server sent data before this request (a second reply to an earlier one?)".into(),
        )),
        Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Ok(()),
        Err(e) => Err(PolicyError::Connection(format!("socket: {e}"))),
    }
}

/// The canonical JSON the script hashes into the seed.
pub fn seed_json(input: &ModelInput, task_id: &str, language: &str) -> String {
    let image = |img: &vifo_cues::RgbImage| {
        let hash: String = Md5::digest(&img.data).iter().map(|b| format!("{b:02x}")).collect();
        format!(
            r#"{{"__type__":"PIL.Image","content_hash":"{hash}","mode":"RGB","size":[{},{}]}}"#,
            img.width, img.height
        )
    };
    let data: String = input.state.iter().flat_map(|v| v.to_le_bytes()).map(|b| format!("{b:02x}")).collect();
    let state = format!(r#"{{"__type__":"numpy","data":"{data}","dtype":"float64","shape":[{}]}}"#, input.state.len());
    let text = |s: &str| serde_json::to_string(s).expect("strings serialise");
    format!(
        r#"{{"base":{},"language":{},"state":{state},"task_id":{},"wrist_left":{}}}"#,
        image(&input.image),
        text(language),
        text(task_id),
        image(&input.wrist)
    )
}

/// `hash_data_to_seed`: SHA-256 of [`seed_json`] modulo 2³².
pub fn seed(json: &str) -> u32 {
    let d = Sha256::digest(json.as_bytes());
    u32::from_be_bytes([d[28], d[29], d[30], d[31]])
}

/// The pickled request.
pub fn encode(input: &ModelInput) -> Vec<u8> {
    const TASK_ID: &str = "libero_all";
    // The profile's instruction ends with the period the script adds after hashing.
    let language = input.instruction.strip_suffix('.').unwrap_or(&input.instruction);
    let seed = seed(&seed_json(input, TASK_ID, language));
    let mut w = Writer::default();
    w.begin_dict();
    w.str("task_id");
    w.str(TASK_ID);
    w.str("state");
    let state: Vec<u8> = input.state.iter().flat_map(|v| v.to_le_bytes()).collect();
    w.ndarray("<f8", &[input.state.len()], &state);
    for (key, img) in [("base", &input.image), ("wrist_left", &input.wrist)] {
        w.str(key);
        w.pil_rgb(img.width, img.height, &img.data);
    }
    w.str("language");
    w.str(&input.instruction);
    w.str("seed");
    w.int(i64::from(seed));
    w.end_dict();
    w.finish()
}

/// Checks and decodes one reply: `tensor[0, :, :-1]`, first 7 columns.
pub fn parse(body: &[u8]) -> Result<Vec<[f64; 7]>, PolicyError> {
    let bad = |m: String| PolicyError::Malformed(m);
    let v = pickle::read_all(body).map_err(|e| bad(format!("reply is not a pickle: {e}")))?;
    let t = pickle::tensor(&v).map_err(|e| bad(format!("reply `action`: {e}")))?;
    let [b, rows, d] = t.shape[..] else {
        return Err(bad(format!("reply `action` has shape {:?}, expected (1, T, D)", t.shape)));
    };
    if b == 0 || rows == 0 || d < 8 {
        return Err(bad(format!("reply `action` has shape {:?}, expected (1, T >= 1, D >= 8)", t.shape)));
    }
    // [0, :, :-1]: the first batch entry, without the last column.
    let first: Vec<f64> = t.values[..rows * d].chunks_exact(d).flat_map(|r| r[..d - 1].to_vec()).collect();
    rows7(&first, rows, d - 1, "action[0]")
}

impl Transport for XiaomiTransport {
    fn infer(&mut self, input: &ModelInput) -> Result<Vec<[f64; 7]>, PolicyError> {
        if self.conn.is_none() {
            self.open()?;
        }
        let result = self.exchange(&encode(input));
        if result.is_err() {
            // The stream may be mid-message: never reuse it.
            self.conn = None;
        }
        parse(&result?)
    }

    /// Reconnects where the server closed the connection since the last episode, or left
    /// something unread on it.
    fn reset(&mut self) -> Result<(), PolicyError> {
        if self.conn.as_ref().is_some_and(|c| nothing_waiting(c.get_ref()).is_err()) {
            self.conn = None;
        }
        if self.conn.is_none() { self.open() } else { Ok(()) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vifo_cues::RgbImage;

    /// A reply sent before its request, and a connection closed since the last reply, are
    /// found before the next request is sent; a quiet connection passes.
    #[test]
    fn what_arrived_between_requests_is_named() {
        use std::io::Write;
        use std::net::TcpListener;
        use std::time::{Duration, Instant};
        // The check once it sees what the server did (local delivery takes a moment).
        let settled = |conn: &TcpStream| {
            let start = Instant::now();
            loop {
                match nothing_waiting(conn) {
                    Ok(()) if start.elapsed() < Duration::from_secs(5) => std::thread::sleep(Duration::from_millis(5)),
                    other => return other,
                }
            }
        };
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (mut server, _) = listener.accept().unwrap();
        assert!(nothing_waiting(&client).is_ok());
        server.write_all(b"stale").unwrap();
        let err = settled(&client).unwrap_err().to_string();
        assert!(err.contains("a second reply to an earlier one"), "{err}");

        let client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        drop(listener.accept().unwrap());
        let err = settled(&client).unwrap_err().to_string();
        assert!(err.contains("closed the connection since its last reply"), "{err}");
    }

    #[test]
    fn the_seed_json_is_canonical() {
        let input = ModelInput {
            image: RgbImage::filled(2, 1, [1, 2, 3]).unwrap(),
            wrist: RgbImage::filled(2, 1, [0, 0, 0]).unwrap(),
            state: vec![1.0, 0.0],
            instruction: "Pick \"it\" up.".into(),
            episode_start: true,
            step: 0,
        };
        let j = seed_json(&input, "libero_all", "Pick \"it\" up");
        assert_eq!(
            j,
            concat!(
                r#"{"base":{"__type__":"PIL.Image","content_hash":"e634c05f3435d8abe31f8e2d46173ad5","mode":"RGB","size":[2,1]},"#,
                r#""language":"Pick \"it\" up","#,
                r#""state":{"__type__":"numpy","data":"000000000000f03f0000000000000000","dtype":"float64","shape":[2]},"#,
                r#""task_id":"libero_all","#,
                r#""wrist_left":{"__type__":"PIL.Image","content_hash":"7319468847d7b1aee40dbf5dd963c999","mode":"RGB","size":[2,1]}}"#
            )
        );
        // hash_data_to_seed of the same dict, computed by Python.
        assert_eq!(seed(&j), 3_165_390_640);
    }
}
