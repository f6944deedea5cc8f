//! The OpenAI-compatible client against a tiny local server that answers like vLLM:
//! request format, model discovery, retries, timeouts, resuming, and scoring of the answers.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use base64::Engine;
use serde_json::{Value, json};
use vifo_cues::{CueSpec, RgbImage, parse, variants};
use vifo_protocols::vqa::client::{ChatClient, ClientConfig, GIVE_UP_AFTER, prompt};
use vifo_protocols::vqa::files::{export, read_predictions};
use vifo_protocols::vqa::{Question, Scene, SceneEntity, Stage, generate, score};

/// How the fake server treats one prompt.
#[derive(Clone, Copy, PartialEq)]
enum Behaviour {
    /// Answer with this letter (inside a thinking block and some prose).
    Answer(char),
    /// HTTP 503 on the first attempt, then answer.
    FlakyThen(char),
    /// Always HTTP 500.
    Broken,
    /// Answer only after this many milliseconds.
    Slow(u64),
}

struct FakeVlm {
    port: u16,
    requests: Arc<AtomicUsize>,
    problems: Arc<Mutex<Vec<String>>>,
}

impl FakeVlm {
    fn start(script: BTreeMap<String, Behaviour>) -> FakeVlm {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let requests = Arc::new(AtomicUsize::new(0));
        let problems = Arc::new(Mutex::new(Vec::new()));
        let seen: Arc<Mutex<BTreeMap<String, usize>>> = Arc::default();
        let script = Arc::new(script);
        let (r, p) = (requests.clone(), problems.clone());
        std::thread::spawn(move || {
            for stream in listener.incoming().flatten() {
                let (r, p, seen, script) = (r.clone(), p.clone(), seen.clone(), script.clone());
                std::thread::spawn(move || serve(stream, &r, &p, &seen, &script));
            }
        });
        FakeVlm { port, requests, problems }
    }

    fn endpoint(&self) -> String {
        format!("http://127.0.0.1:{}", self.port)
    }
}

fn serve(
    mut stream: TcpStream,
    requests: &AtomicUsize,
    problems: &Mutex<Vec<String>>,
    seen: &Mutex<BTreeMap<String, usize>>,
    script: &BTreeMap<String, Behaviour>,
) {
    let mut reader = BufReader::new(stream.try_clone().unwrap());
    let mut request_line = String::new();
    if reader.read_line(&mut request_line).is_err() {
        return;
    }
    let mut length = 0;
    loop {
        let mut line = String::new();
        reader.read_line(&mut line).unwrap();
        if line.trim().is_empty() {
            break;
        }
        if let Some((k, v)) = line.split_once(':')
            && k.eq_ignore_ascii_case("content-length")
        {
            length = v.trim().parse().unwrap();
        }
    }
    let mut body = vec![0; length];
    reader.read_exact(&mut body).unwrap();
    let mut reply = |status: &str, body: Value| {
        let text = body.to_string();
        let _ = write!(
            stream,
            "HTTP/1.1 {status}\r\ncontent-type: application/json\r\ncontent-length: {}\r\nconnection: close\r\n\r\n{text}",
            text.len()
        );
    };
    if request_line.starts_with("GET /v1/models ") {
        return reply("200 OK", json!({"object": "list", "data": [{"id": "fake-vlm", "object": "model"}]}));
    }
    if !request_line.starts_with("POST /v1/chat/completions ") {
        return reply("404 Not Found", json!({"error": request_line}));
    }
    requests.fetch_add(1, Ordering::SeqCst);
    let req: Value = serde_json::from_slice(&body).unwrap();
    let problem = |m: String| problems.lock().unwrap().push(m);
    if req["model"] != "fake-vlm" || req["temperature"] != 0 || req["seed"] != 0 {
        problem(format!("request settings: {req}"));
    }
    let content = &req["messages"][0]["content"];
    let url = content[0]["image_url"]["url"].as_str().unwrap_or_default();
    let png = url
        .strip_prefix("data:image/png;base64,")
        .and_then(|b| base64::engine::general_purpose::STANDARD.decode(b).ok())
        .unwrap_or_default();
    if content[0]["type"] != "image_url" || !png.starts_with(b"\x89PNG") {
        problem("first content part is not a PNG data URL".into());
    }
    let text = content[1]["text"].as_str().unwrap_or_default().to_string();
    if content[1]["type"] != "text" || !text.ends_with("Please select the correct answer from the options above. \n") {
        problem(format!("prompt: {text:?}"));
    }
    let attempt = {
        let mut s = seen.lock().unwrap();
        let n = s.entry(text.clone()).or_default();
        *n += 1;
        *n
    };
    let answer = |letter: char| {
        json!({"id": "chatcmpl-1", "object": "chat.completion", "model": "fake-vlm",
               "choices": [{"index": 0, "finish_reason": "stop",
                            "message": {"role": "assistant", "content": format!("<think>A or B?</think>The answer is ({letter}).")}}],
               "usage": {"prompt_tokens": 10, "completion_tokens": 5, "total_tokens": 15}})
    };
    match script.get(&text).copied().unwrap_or(Behaviour::Answer('A')) {
        Behaviour::Answer(l) => reply("200 OK", answer(l)),
        Behaviour::FlakyThen(l) if attempt > 1 => reply("200 OK", answer(l)),
        Behaviour::FlakyThen(_) => reply("503 Service Unavailable", json!({"error": "warming up"})),
        Behaviour::Broken => reply("500 Internal Server Error", json!({"error": "boom"})),
        Behaviour::Slow(ms) => {
            std::thread::sleep(Duration::from_millis(ms));
            reply("200 OK", answer('A'))
        }
    }
}

fn question_set(name: &str) -> (PathBuf, Vec<Question>) {
    let task = parse("put the black bowl on the plate").unwrap();
    let instances: Vec<CueSpec> = ["straight_arrow_red", "caption_bar", "glow_halo", "qr_json"]
        .iter()
        .map(|v| CueSpec::new("libero_x/0", &task, 0, variants::find(v).unwrap()).unwrap())
        .collect();
    let scene = Scene {
        objects: ["black bowl", "plate", "ketchup", "cream cheese", "butter"]
            .iter()
            .map(|n| SceneEntity::new(&n.replace(' ', "_"), n))
            .collect(),
        fixtures: vec![SceneEntity::new("main_table", "table"), SceneEntity::new("flat_stove_1", "stove")],
    };
    let qs = generate(&instances, &BTreeMap::from([("libero_x/0".to_string(), scene)])).unwrap();
    let dir = std::env::temp_dir().join(format!("vifo-vqa-client-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    export(&dir, &qs, |_| RgbImage::filled(32, 32, [90, 90, 90]).map_err(|e| e.to_string())).unwrap();
    (dir, qs)
}

fn config(endpoint: &str) -> ClientConfig {
    ClientConfig {
        retries: 2,
        backoff: Duration::from_millis(10),
        timeout: Duration::from_millis(1500),
        concurrency: 3,
        quiet: true,
        ..ClientConfig::new(endpoint)
    }
}

#[test]
fn answers_are_fetched_retried_resumed_and_scored() {
    let (dir, qs) = question_set("answers");
    let letter = |q: &Question| q.answer.chars().next().unwrap();
    let mut script: BTreeMap<String, Behaviour> =
        qs.iter().map(|q| (prompt(q), Behaviour::Answer(letter(q)))).collect();
    let flaky = &qs[0];
    let broken = &qs[1];
    let slow = &qs[2];
    let wrong = &qs[3];
    script.insert(prompt(flaky), Behaviour::FlakyThen(letter(flaky)));
    script.insert(prompt(broken), Behaviour::Broken);
    script.insert(prompt(slow), Behaviour::Slow(2500));
    let other = if letter(wrong) == 'A' { 'B' } else { 'A' };
    script.insert(prompt(wrong), Behaviour::Answer(other));
    let server = FakeVlm::start(script);

    let client = ChatClient::new(config(&server.endpoint())).unwrap();
    assert_eq!(client.model(), "fake-vlm", "discovered through /v1/models");
    let out = dir.join("predictions.jsonl");
    let summary = client.answer_all(&dir, &qs, &out).unwrap();
    assert!(server.problems.lock().unwrap().is_empty(), "{:?}", server.problems.lock().unwrap());
    assert_eq!(summary.answered, qs.len() - 2);
    let failed: Vec<&str> = summary.failed.iter().map(|(id, _)| id.as_str()).collect();
    let mut expected = vec![broken.id.as_str(), slow.id.as_str()];
    expected.sort();
    assert_eq!(failed, expected);
    let broken_error = &summary.failed.iter().find(|(id, _)| *id == broken.id).unwrap().1;
    assert!(broken_error.contains("HTTP 500"), "{broken_error}");
    // Broken: 1 + 2 retries; slow: 3 attempts; flaky: 2; the rest once.
    assert_eq!(server.requests.load(Ordering::SeqCst), qs.len() - 3 + 3 + 3 + 2);

    let (predictions, cut) = read_predictions(&out).unwrap();
    assert_eq!((predictions.len(), cut), (qs.len() - 2, 0));
    let s = score("fake-vlm", &qs, &predictions);
    assert_eq!((s.overall.correct, s.overall.total, s.unanswered), (qs.len() - 3, qs.len(), 2));
    // The four misbehaving prompts all belong to the first instance.
    assert_eq!((s.fca.correct, s.fca.total), (3, 4));
    assert_eq!(s.stages[&Stage::Detection].total, 4);

    // A second run asks only what is still missing: the two that failed, and the last answer,
    // whose line a kill cut off mid-write. Its new lines start on a line of their own (they
    // were once glued to the cut bytes, which broke the file for every later reader).
    let text = std::fs::read_to_string(&out).unwrap();
    std::fs::write(&out, &text[..text.len() - 10]).unwrap();
    let before = server.requests.load(Ordering::SeqCst);
    let again = ChatClient::new(ClientConfig { model: Some("fake-vlm".into()), ..config(&server.endpoint()) }).unwrap();
    let summary = again.answer_all(&dir, &qs, &out).unwrap();
    assert_eq!((summary.skipped, summary.answered), (qs.len() - 3, 1));
    assert_eq!(server.requests.load(Ordering::SeqCst) - before, 1 + 3 + 3);
    let (predictions, cut) = read_predictions(&out).unwrap();
    assert_eq!((predictions.len(), cut), (qs.len() - 2, 0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unreachable_and_tls_endpoints_fail_clearly() {
    let err = ChatClient::new(config("https://api.example.com")).err().unwrap().to_string();
    assert!(err.contains("TLS is not built in"), "{err}");
    let closed = TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let client =
        ChatClient::new(ClientConfig { model: Some("m".into()), ..config(&format!("http://127.0.0.1:{closed}")) })
            .unwrap();
    let err = client.ask(b"\x89PNG", "Question: ?").unwrap_err();
    assert!(err.contains("127.0.0.1"), "{err}");
    // A dead server: the run stops after a few failures in a row instead of trying everything.
    let (dir, qs) = question_set("dead");
    let summary = client.answer_all(&dir, &qs, &dir.join("p.jsonl")).unwrap();
    assert!(summary.gave_up && summary.answered == 0);
    assert!(summary.failed.len() >= GIVE_UP_AFTER && summary.failed.len() < qs.len(), "{}", summary.failed.len());
    let _ = std::fs::remove_dir_all(&dir);
}
