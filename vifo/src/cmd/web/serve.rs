//! `vifo web serve`: a tiny static file server for the built site. Plain HTTP/1.1, GET and HEAD,
//! one thread per connection, bound to 127.0.0.1 by default; paths cannot leave the folder.
//! Text and WebAssembly go gzipped to clients that accept it, as static hosts send them (the
//! module is 8.7 MB raw, about 3.2 MB gzipped).
//! Enough for the demo and its browser test; put the folder on any static host for real use.

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Component, Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use flate2::Compression;
use flate2::write::GzEncoder;

#[derive(ClapArgs)]
pub struct Args {
    /// The folder `vifo web build` wrote.
    #[arg(default_value = "vifo-web")]
    dir: PathBuf,
    /// Port (0: any free port; the URL is printed).
    #[arg(long, default_value_t = 8000)]
    port: u16,
    /// Address to bind; the default keeps the server on this machine.
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    if !args.dir.join("index.html").is_file() {
        bail!("{} has no index.html; build the site first: vifo web build {}", args.dir.display(), args.dir.display());
    }
    let listener = TcpListener::bind((args.host.as_str(), args.port)).map_err(|e| match e.kind() {
        std::io::ErrorKind::AddrInUse => anyhow::anyhow!("port {} of {} is taken by another server; --port 0 picks a free one", args.port, args.host),
        _ => anyhow::Error::new(e).context(format!("bind {}:{}", args.host, args.port)),
    })?;
    let root = args.dir.canonicalize().with_context(|| args.dir.display().to_string())?;
    println!("serving {} at http://{}/", root.display(), listener.local_addr()?);
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        let root = root.clone();
        std::thread::spawn(move || {
            // A client that goes away mid-request is its own problem, not the server's.
            let _ = answer(stream, &root);
        });
    }
    Ok(())
}

fn answer(stream: TcpStream, root: &Path) -> std::io::Result<()> {
    stream.set_read_timeout(Some(Duration::from_secs(10)))?;
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request = String::new();
    reader.read_line(&mut request)?;
    // Of the headers only Accept-Encoding counts (no ranges, no keep-alive).
    let mut line = String::new();
    let mut gzip = false;
    while reader.read_line(&mut line)? > 2 {
        gzip |= accepts_gzip(&line);
        line.clear();
    }
    let mut parts = request.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or(""));
    let mut out = stream;
    if method != "GET" && method != "HEAD" {
        return reply(&mut out, "405 Method Not Allowed", "text/plain", b"only GET and HEAD\n", true);
    }
    let Some(path) = resolve(root, target) else {
        return reply(&mut out, "404 Not Found", "text/plain", b"not found\n", true);
    };
    match std::fs::read(&path) {
        Ok(body) => {
            let kind = content_type(&path);
            if gzip && compressible(kind) {
                let mut encoder = GzEncoder::new(Vec::new(), Compression::default());
                encoder.write_all(&body)?;
                return reply_encoded(&mut out, "200 OK", kind, &encoder.finish()?, method == "GET", Some("gzip"));
            }
            reply(&mut out, "200 OK", kind, &body, method == "GET")
        }
        Err(_) => reply(&mut out, "404 Not Found", "text/plain", b"not found\n", true),
    }
}

/// Whether a request header line says the client takes gzip.
fn accepts_gzip(header: &str) -> bool {
    let Some((name, value)) = header.split_once(':') else { return false };
    name.trim().eq_ignore_ascii_case("accept-encoding") && value.split(',').any(|v| v.split(';').next().is_some_and(|e| e.trim().eq_ignore_ascii_case("gzip")))
}

/// Types worth compressing (images are compressed already).
fn compressible(kind: &str) -> bool {
    kind.starts_with("text/") || kind == "application/wasm" || kind == "application/json" || kind == "image/svg+xml"
}

fn reply(out: &mut TcpStream, status: &str, kind: &str, body: &[u8], with_body: bool) -> std::io::Result<()> {
    reply_encoded(out, status, kind, body, with_body, None)
}

fn reply_encoded(out: &mut TcpStream, status: &str, kind: &str, body: &[u8], with_body: bool, encoding: Option<&str>) -> std::io::Result<()> {
    let encoding = encoding.map_or(String::new(), |e| format!("Content-Encoding: {e}\r\nVary: Accept-Encoding\r\n"));
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {kind}\r\n{encoding}Content-Length: {}\r\nCache-Control: no-cache\r\nConnection: close\r\n\r\n",
        body.len()
    );
    out.write_all(head.as_bytes())?;
    if with_body {
        out.write_all(body)?;
    }
    out.flush()
}

/// The file a request target names under `root` (`/` is `index.html`); `None` for targets that
/// would leave the folder or are not plain relative paths.
fn resolve(root: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next()?;
    let path = percent_decode(path.strip_prefix('/')?)?;
    let relative = Path::new(&path);
    if !relative.components().all(|c| matches!(c, Component::Normal(_))) {
        return None;
    }
    let file = root.join(relative);
    Some(if path.is_empty() || file.is_dir() { file.join("index.html") } else { file })
}

fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The MIME type browsers need (`application/wasm` lets them compile while downloading).
fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js" | "mjs") => "text/javascript; charset=utf-8",
        Some("wasm") => "application/wasm",
        Some("css") => "text/css; charset=utf-8",
        Some("json") => "application/json",
        Some("png") => "image/png",
        Some("svg") => "image/svg+xml",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_stay_in_the_folder() {
        let root = Path::new("/site");
        assert_eq!(resolve(root, "/"), Some(PathBuf::from("/site/index.html")));
        assert_eq!(resolve(root, "/vifo_web.js?v=1"), Some(PathBuf::from("/site/vifo_web.js")));
        assert_eq!(resolve(root, "/a%20b.png"), Some(PathBuf::from("/site/a b.png")));
        assert_eq!(resolve(root, "/../etc/passwd"), None);
        assert_eq!(resolve(root, "/%2e%2e/etc/passwd"), None);
        assert_eq!(resolve(root, "//etc/passwd"), None);
        assert_eq!(resolve(root, "http://x/"), None);
        assert_eq!(resolve(root, "/%zz"), None);
        assert_eq!(content_type(Path::new("m.wasm")), "application/wasm");
    }

    #[test]
    fn gzip_goes_to_clients_that_accept_it() {
        assert!(accepts_gzip("Accept-Encoding: gzip, deflate, br\r\n"));
        assert!(accepts_gzip("accept-encoding: br;q=1.0, gzip;q=0.8\r\n"));
        assert!(!accepts_gzip("Accept-Encoding: br\r\n") && !accepts_gzip("X-Gzip: gzip\r\n"));
        assert!(compressible("application/wasm") && compressible("text/javascript; charset=utf-8") && !compressible("image/png"));
    }
}
