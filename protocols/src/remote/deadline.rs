//! A TCP stream whose every read and write ends by one deadline. A socket timeout limits each
//! read on its own, so a server that sends its reply a byte at a time could hold a request far
//! past the request timeout; here the whole exchange shares the time left.

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

pub struct DeadlineStream {
    stream: TcpStream,
    deadline: Instant,
}

impl DeadlineStream {
    /// `stream`, whose operations must end `within` from now.
    pub fn new(stream: TcpStream, within: Duration) -> DeadlineStream {
        DeadlineStream { stream, deadline: Instant::now() + within }
    }

    /// Operations from now on must end `within` from now.
    pub fn limit(&mut self, within: Duration) {
        self.deadline = Instant::now() + within;
    }

    pub fn get_ref(&self) -> &TcpStream {
        &self.stream
    }

    /// The time left as the socket's timeout for the next operation; `TimedOut` when none is.
    fn arm(&self, set: fn(&TcpStream, Option<Duration>) -> io::Result<()>) -> io::Result<()> {
        let left = self.deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        set(&self.stream, Some(left))
    }
}

impl Read for DeadlineStream {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.arm(TcpStream::set_read_timeout)?;
        self.stream.read(buf)
    }
}

impl Write for DeadlineStream {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.arm(TcpStream::set_write_timeout)?;
        self.stream.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.stream.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    /// A peer that sends one byte every 20 ms, each well within a socket timeout, cannot hold
    /// a read past the deadline.
    #[test]
    fn a_trickling_peer_cannot_outlast_the_deadline() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let peer = std::thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            for _ in 0..100 {
                if s.write_all(&[7]).is_err() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        let mut stream = DeadlineStream::new(TcpStream::connect(("127.0.0.1", port)).unwrap(), Duration::from_millis(300));
        let start = Instant::now();
        let mut buf = [0u8; 100];
        let e = stream.read_exact(&mut buf).unwrap_err();
        let took = start.elapsed();
        assert!(matches!(e.kind(), io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock), "{e}");
        // The 100 bytes take 2 s to arrive; the read ends near its 300 ms.
        assert!(took < Duration::from_millis(1500), "{took:?}");
        drop(stream);
        peer.join().unwrap();
    }
}
