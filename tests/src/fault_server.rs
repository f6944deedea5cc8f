//! A misbehaving openpi policy server, for the fault tests and `examples/policy_faults.rs`.
//!
//! It speaks openpi's websocket protocol (metadata message, then one msgpack reply per
//! request: an action chunk of zeros) on 127.0.0.1 only, one thread per connection, and
//! injects the faults of its schedule in order, each at the chosen request of a connection (at
//! the handshake for [`Fault::BadHandshake`]); once the schedule is spent it serves normally.
//! Every wait it makes is bounded, and dropping the server stops it.

use std::io::Write;
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use rmpv::Value;
use tungstenite::{Message, WebSocket};
use vifo_protocols::remote::ndarray;

/// What the server does wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// Closes the TCP connection mid-episode, without a websocket close.
    Drop,
    /// Answers only after the client's request timeout.
    Stall,
    /// A binary frame that is not msgpack.
    Garbage,
    /// A text frame (openpi sends its traceback so).
    TextError,
    /// A frame header announcing 1 TiB.
    Oversize,
    /// Actions of shape (H, 8).
    WrongShape,
    /// A NaN among the actions.
    NanActions,
    /// An infinity among the actions.
    InfActions,
    /// A metadata message that is not msgpack.
    BadHandshake,
    /// A good reply sent a byte at a time, each byte well within the client's timeout, the
    /// whole past it.
    Trickle,
    /// A good reply, then a second one nobody asked for.
    TwoReplies,
}

impl Fault {
    pub const ALL: [Fault; 11] = [
        Fault::Drop,
        Fault::Stall,
        Fault::Garbage,
        Fault::TextError,
        Fault::Oversize,
        Fault::WrongShape,
        Fault::NanActions,
        Fault::InfActions,
        Fault::BadHandshake,
        Fault::Trickle,
        Fault::TwoReplies,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Fault::Drop => "drop",
            Fault::Stall => "stall",
            Fault::Garbage => "garbage",
            Fault::TextError => "text-error",
            Fault::Oversize => "oversize",
            Fault::WrongShape => "wrong-shape",
            Fault::NanActions => "nan-actions",
            Fault::InfActions => "inf-actions",
            Fault::BadHandshake => "bad-handshake",
            Fault::Trickle => "trickle",
            Fault::TwoReplies => "two-replies",
        }
    }

    /// Words one of which the client's error must contain: the fault, named.
    pub fn named_by(self) -> &'static [&'static str] {
        match self {
            Fault::Drop => &["reset", "closed", "Connection"],
            Fault::Stall => &["timed out", "timeout"],
            Fault::Garbage => &["malformed reply", "not a msgpack"],
            Fault::TextError => &["reported an error"],
            Fault::Oversize => &["too large", "too long"],
            Fault::WrongShape => &["shape"],
            Fault::NanActions => &["NaN"],
            Fault::InfActions => &["inf"],
            Fault::BadHandshake => &["metadata"],
            Fault::Trickle => &["timed out"],
            Fault::TwoReplies => &["second reply"],
        }
    }
}

/// How long a stalled reply waits: past the client timeout the tests use ([`CLIENT_TIMEOUT`]).
const STALL: Duration = Duration::from_millis(2500);
/// The request timeout a client of this server should use (long enough that a loaded machine
/// does not time out a healthy reply).
pub const CLIENT_TIMEOUT: Duration = Duration::from_millis(1000);
/// No wait of a connection thread is longer than this.
const IO_LIMIT: Duration = Duration::from_secs(10);

struct Shared {
    schedule: Vec<Fault>,
    /// The request (1-based, per connection) a fault hits.
    at_request: usize,
    /// Faults injected (the next one is `schedule[fired]`).
    fired: AtomicUsize,
    /// Requests answered normally (counted as the answer is sent).
    served: AtomicUsize,
    /// Connections the client ended with a websocket close.
    closed: AtomicUsize,
    stop: AtomicBool,
}

/// A running server; stops when dropped.
pub struct FaultServer {
    port: u16,
    shared: Arc<Shared>,
    accept: Option<JoinHandle<()>>,
}

impl FaultServer {
    /// Starts a server that injects the faults of `schedule` in order, each at request
    /// `at_request` of a connection (at the handshake for [`Fault::BadHandshake`]).
    pub fn start(schedule: Vec<Fault>, at_request: usize) -> std::io::Result<FaultServer> {
        let listener = TcpListener::bind("127.0.0.1:0")?;
        listener.set_nonblocking(true)?;
        let port = listener.local_addr()?.port();
        let shared = Arc::new(Shared {
            schedule,
            at_request: at_request.max(1),
            fired: AtomicUsize::new(0),
            served: AtomicUsize::new(0),
            closed: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
        });
        let s = shared.clone();
        let accept = std::thread::spawn(move || {
            while !s.stop.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((stream, _)) => {
                        let s = s.clone();
                        std::thread::spawn(move || serve(stream, &s));
                    }
                    Err(_) => std::thread::sleep(Duration::from_millis(5)),
                }
            }
        });
        Ok(FaultServer { port, shared, accept: Some(accept) })
    }

    pub fn url(&self) -> String {
        format!("ws://127.0.0.1:{}", self.port)
    }

    /// Faults injected so far.
    pub fn fired(&self) -> usize {
        self.shared.fired.load(Ordering::Relaxed)
    }

    /// Requests answered normally so far.
    pub fn served(&self) -> usize {
        self.shared.served.load(Ordering::Relaxed)
    }

    /// Connections the client has ended with a websocket close so far.
    pub fn closed(&self) -> usize {
        self.shared.closed.load(Ordering::Relaxed)
    }
}

impl Drop for FaultServer {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.accept.take() {
            let _ = h.join();
        }
    }
}

/// Takes the next fault of the schedule if `wanted` says it is injected here.
fn take_fault(s: &Shared, wanted: impl Fn(Fault) -> bool) -> Option<Fault> {
    let mut taken = None;
    let _ = s.fired.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| {
        taken = s.schedule.get(n).copied().filter(|&f| wanted(f));
        taken.map(|_| n + 1)
    });
    taken
}

fn pack(v: &Value) -> Vec<u8> {
    let mut b = Vec::new();
    rmpv::encode::write_value(&mut b, v).expect("encode to memory");
    b
}

/// An action chunk of `rows` × `cols` values, all zero except `[0][0] = first`.
fn chunk(rows: usize, cols: usize, first: f64) -> Vec<u8> {
    let mut values = vec![0.0; rows * cols];
    values[0] = first;
    pack(&Value::Map(vec![(Value::from("actions"), ndarray::encode_f64(&[rows, cols], &values))]))
}

fn serve(stream: TcpStream, s: &Shared) {
    let _ = stream.set_nonblocking(false);
    let _ = stream.set_read_timeout(Some(IO_LIMIT));
    let _ = stream.set_write_timeout(Some(IO_LIMIT));
    let Ok(mut ws) = tungstenite::accept(stream) else { return };
    let metadata = if take_fault(s, |f| f == Fault::BadHandshake).is_some() {
        vec![0xc1, 0xc1, 0xc1]
    } else {
        pack(&Value::Map(vec![]))
    };
    if ws.send(Message::binary(metadata)).is_err() {
        return;
    }
    let mut requests = 0;
    while !s.stop.load(Ordering::Relaxed) {
        match ws.read() {
            Ok(Message::Binary(_)) => {}
            Ok(Message::Close(_)) => {
                // Our answer to the close, queued by `read`.
                let _ = ws.flush();
                s.closed.fetch_add(1, Ordering::Relaxed);
                return;
            }
            Err(_) => return,
            Ok(_) => continue,
        }
        requests += 1;
        if requests == s.at_request
            && let Some(fault) = take_fault(s, |f| f != Fault::BadHandshake)
        {
            if !inject(&mut ws, fault) {
                return;
            }
            continue;
        }
        // Counted before it is sent, so a client holding the answer already sees the count.
        s.served.fetch_add(1, Ordering::Relaxed);
        if ws.send(Message::binary(chunk(10, 7, 0.0))).is_err() {
            return;
        }
    }
}

/// Misbehaves once; returns whether the connection is still usable.
fn inject(ws: &mut WebSocket<TcpStream>, fault: Fault) -> bool {
    let sent = match fault {
        Fault::Drop => {
            let _ = ws.get_mut().shutdown(Shutdown::Both);
            return false;
        }
        Fault::Stall => {
            std::thread::sleep(STALL);
            ws.send(Message::binary(chunk(10, 7, 0.0)))
        }
        Fault::Garbage => ws.send(Message::binary(vec![0xc1, 0x00, 0xff, 0x13, 0x37])),
        Fault::TextError => ws.send(Message::text("Traceback (most recent call last):\nRuntimeError: injected fault")),
        Fault::Oversize => {
            // A binary frame header announcing 2^40 bytes, then a little of it.
            let mut frame = vec![0x82, 0x7f];
            frame.extend_from_slice(&(1u64 << 40).to_be_bytes());
            frame.extend_from_slice(&[0; 64]);
            let _ = ws.get_mut().write_all(&frame);
            return false;
        }
        Fault::WrongShape => ws.send(Message::binary(chunk(10, 8, 0.0))),
        Fault::NanActions => ws.send(Message::binary(chunk(10, 7, f64::NAN))),
        Fault::InfActions => ws.send(Message::binary(chunk(10, 7, f64::INFINITY))),
        // Injected at the handshake instead; a request is answered normally.
        Fault::BadHandshake => ws.send(Message::binary(chunk(10, 7, 0.0))),
        Fault::Trickle => {
            let reply = chunk(10, 7, 0.0);
            let mut frame = vec![0x82, 126];
            frame.extend_from_slice(&(reply.len() as u16).to_be_bytes());
            frame.extend_from_slice(&reply);
            let gap = STALL / frame.len() as u32;
            for byte in frame {
                if ws.get_mut().write_all(&[byte]).is_err() {
                    return false;
                }
                std::thread::sleep(gap);
            }
            Ok(())
        }
        // Both in one flush, so the second is there before the client's next request.
        Fault::TwoReplies => ws
            .write(Message::binary(chunk(10, 7, 0.0)))
            .and_then(|()| ws.write(Message::binary(chunk(10, 7, 0.5))))
            .and_then(|()| ws.flush()),
    };
    sent.is_ok()
}
