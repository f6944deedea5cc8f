//! An OpenAI-compatible chat client (vLLM, SGLang, …) that answers the exported questions.
//!
//! Request (research note §4.1): `POST <base>/v1/chat/completions` with one user message
//! holding the image as a PNG data URL followed by the VLMEvalKit multiple-choice prompt
//! (§4.2), `temperature` 0, `seed` 0. The answer is `choices[0].message.content`, stored raw
//! (thinking included; [`super::extract`] removes it when scoring). Plain HTTP only: TLS is
//! not built in, so remote servers are reached through a local tunnel or proxy.
//!
//! Answers are appended to the predictions file one line at a time, and questions already
//! answered there are skipped, so an interrupted run continues where it stopped.

use std::collections::BTreeSet;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use base64::Engine;
use serde_json::{Value, json};

use super::files::{append_predictions, resume_predictions};
use super::{LETTERS, Prediction, Question, VqaError};
use crate::runner::{lock, Progress};

/// How to reach and use the server.
#[derive(Clone, Debug)]
pub struct ClientConfig {
    /// `http://host:port` (a trailing `/v1` is accepted).
    pub endpoint: String,
    /// Model id; `None` asks `GET /v1/models` and takes the first.
    pub model: Option<String>,
    /// Sent as `Authorization: Bearer <key>` when set.
    pub api_key: Option<String>,
    /// Requests in flight at once.
    pub concurrency: usize,
    /// Further attempts after a failed one (connection errors, timeouts, 429 and 5xx).
    pub retries: usize,
    /// Wait before the first retry; doubles each time (at most 60 s).
    pub backoff: Duration,
    /// Limit for one whole request.
    pub timeout: Duration,
    pub max_tokens: u32,
    /// No progress bar.
    pub quiet: bool,
}

impl ClientConfig {
    pub fn new(endpoint: &str) -> ClientConfig {
        ClientConfig {
            endpoint: endpoint.to_string(),
            model: None,
            api_key: None,
            concurrency: 4,
            retries: 3,
            backoff: Duration::from_secs(1),
            timeout: Duration::from_secs(120),
            max_tokens: 64,
            quiet: false,
        }
    }
}

/// What [`ChatClient::answer_all`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AnswerSummary {
    pub answered: usize,
    /// Already in the predictions file.
    pub skipped: usize,
    /// (question id, last error) of questions that still have no answer.
    pub failed: Vec<(String, String)>,
    /// Stopped early after [`GIVE_UP_AFTER`] failures in a row (server down or misconfigured);
    /// the questions not tried are in neither list.
    pub gave_up: bool,
}

/// Consecutive failed questions after which [`ChatClient::answer_all`] stops asking.
pub const GIVE_UP_AFTER: usize = 10;

/// A connection to one model on one server.
pub struct ChatClient {
    config: ClientConfig,
    agent: ureq::Agent,
    /// `http://host:port/v1`.
    base: String,
    model: String,
}

/// VLMEvalKit's `ImageMCQDataset.build_prompt` without a hint.
pub fn prompt(q: &Question) -> String {
    let mut p = format!("Question: {}\nOptions:\n", q.question);
    for (letter, option) in LETTERS.iter().zip(&q.options) {
        p += &format!("{letter}. {option}\n");
    }
    p + "Please select the correct answer from the options above. \n"
}

/// One failed attempt, and whether trying again may help.
struct Failure {
    message: String,
    retry: bool,
}

impl ChatClient {
    /// Checks the endpoint and, without a model id, asks the server for one.
    pub fn new(config: ClientConfig) -> Result<ChatClient, VqaError> {
        let base = api_base(&config.endpoint)?;
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .timeout_global(Some(config.timeout))
            .http_status_as_error(false)
            .build()
            .into();
        let mut client = ChatClient { config, agent, base, model: String::new() };
        client.model = match client.config.model.clone() {
            Some(m) => m,
            None => client.first_model()?,
        };
        Ok(client)
    }

    pub fn model(&self) -> &str {
        &self.model
    }

    fn first_model(&self) -> Result<String, VqaError> {
        let url = format!("{}/models", self.base);
        let mut request = self.agent.get(&url);
        if let Some(key) = &self.config.api_key {
            request = request.header("Authorization", format!("Bearer {key}"));
        }
        let text = read_body(request.call(), &url).map_err(|f| VqaError::Client(f.message))?;
        let body: Value =
            serde_json::from_str(&text).map_err(|e| VqaError::Client(format!("{url}: reply is not JSON: {e}")))?;
        body.pointer("/data/0/id")
            .and_then(Value::as_str)
            .map(str::to_string)
            .ok_or_else(|| VqaError::Client(format!("{url}: no model listed under data[0].id; pass a model id")))
    }

    /// Asks one question about one PNG image, retrying transient failures.
    pub fn ask(&self, png: &[u8], prompt: &str) -> Result<String, String> {
        let url = format!("{}/chat/completions", self.base);
        let image = format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(png));
        let body = json!({
            "model": self.model,
            "messages": [{"role": "user", "content": [
                {"type": "image_url", "image_url": {"url": image}},
                {"type": "text", "text": prompt},
            ]}],
            "temperature": 0,
            "max_tokens": self.config.max_tokens,
            "seed": 0,
        });
        let mut wait = self.config.backoff;
        let mut attempt = 0;
        loop {
            let mut request = self.agent.post(&url);
            if let Some(key) = &self.config.api_key {
                request = request.header("Authorization", format!("Bearer {key}"));
            }
            let failure = match read_body(request.send_json(&body), &url) {
                Ok(text) => match chat_answer(&text) {
                    Ok(answer) => return Ok(answer),
                    Err(why) => Failure { message: format!("{url}: {why}"), retry: false },
                },
                Err(f) => f,
            };
            if !failure.retry || attempt >= self.config.retries {
                return Err(failure.message);
            }
            attempt += 1;
            std::thread::sleep(wait);
            wait = (wait * 2).min(Duration::from_secs(60));
        }
    }

    /// Answers every question of an export folder not yet in `out`, appending as it goes.
    pub fn answer_all(&self, dir: &Path, questions: &[Question], out: &Path) -> Result<AnswerSummary, VqaError> {
        let done: BTreeSet<String> =
            if out.exists() { resume_predictions(out)?.into_keys().collect() } else { BTreeSet::new() };
        let todo: Vec<&Question> = questions.iter().filter(|q| !done.contains(&q.id)).collect();
        let summary = Mutex::new(AnswerSummary { skipped: questions.len() - todo.len(), ..AnswerSummary::default() });
        let write_error: Mutex<Option<VqaError>> = Mutex::new(None);
        let next = AtomicUsize::new(0);
        let failures_in_a_row = AtomicUsize::new(0);
        let bar = Progress::stderr(todo.len() as u64, "questions", self.config.quiet);
        std::thread::scope(|scope| {
            for _ in 0..self.config.concurrency.clamp(1, todo.len().max(1)) {
                scope.spawn(|| {
                    while let Some(q) = todo.get(next.fetch_add(1, Ordering::Relaxed)) {
                        if lock(&write_error).is_some() || failures_in_a_row.load(Ordering::Relaxed) >= GIVE_UP_AFTER {
                            return;
                        }
                        let result = std::fs::read(dir.join(&q.image))
                            .map_err(|e| format!("{}: {e}", dir.join(&q.image).display()))
                            .and_then(|png| self.ask(&png, &prompt(q)));
                        match result {
                            Ok(text) => {
                                failures_in_a_row.store(0, Ordering::Relaxed);
                                let line = Prediction { id: q.id.clone(), prediction: text };
                                if let Err(e) = append_predictions(out, std::slice::from_ref(&line)) {
                                    lock(&write_error).get_or_insert(e);
                                }
                                lock(&summary).answered += 1;
                            }
                            Err(message) => {
                                failures_in_a_row.fetch_add(1, Ordering::Relaxed);
                                lock(&summary).failed.push((q.id.clone(), message));
                            }
                        }
                        bar.inc();
                    }
                });
            }
        });
        bar.finish();
        if let Some(e) = write_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(e);
        }
        let mut summary = summary.into_inner().unwrap_or_else(|p| p.into_inner());
        summary.gave_up = failures_in_a_row.into_inner() >= GIVE_UP_AFTER;
        summary.failed.sort();
        Ok(summary)
    }
}

/// `http://host:port[/v1][/]` → `http://host:port/v1`.
fn api_base(endpoint: &str) -> Result<String, VqaError> {
    let e = endpoint.trim().trim_end_matches('/');
    if e.starts_with("https://") {
        return Err(VqaError::Client(format!(
            "{endpoint}: TLS is not built in (plain HTTP only); reach the server through a local \
             proxy or tunnel, e.g. ssh -L 8000:localhost:8000 host and --endpoint http://localhost:8000"
        )));
    }
    let Some(rest) = e.strip_prefix("http://") else {
        return Err(VqaError::Client(format!("{endpoint}: expected an http://host:port endpoint")));
    };
    if rest.is_empty() {
        return Err(VqaError::Client(format!("{endpoint}: no host")));
    }
    // A port that is not one must not become port 80, nor a broken address "is the server up?".
    crate::remote::Address::parse(e, Some(80)).map_err(|err| VqaError::Client(err.to_string()))?;
    Ok(if e.ends_with("/v1") { e.to_string() } else { format!("{e}/v1") })
}

/// The answer in the body of an OpenAI-compatible chat completion: the text of
/// `choices[0].message.content`, empty when it is null. A reply cut at the token limit
/// (`finish_reason` `length`) is an error, not an answer: stored, it would be scored as wrong
/// and never asked again, where a larger `--max-tokens` would have let the model answer.
pub fn chat_answer(body: &str) -> Result<String, String> {
    let reply: Value = serde_json::from_str(body).map_err(|e| format!("reply is not JSON: {e}"))?;
    if reply.pointer("/choices/0/finish_reason").and_then(Value::as_str) == Some("length") {
        return Err("the reply was cut at the token limit (finish_reason \"length\"): raise --max-tokens".to_string());
    }
    match reply.pointer("/choices/0/message/content") {
        Some(Value::String(text)) => Ok(text.clone()),
        Some(Value::Null) => Ok(String::new()),
        _ => Err("reply without choices[0].message.content".to_string()),
    }
}

/// The body of a 2xx reply; anything else as a failure saying whether to retry.
fn read_body(result: Result<ureq::http::Response<ureq::Body>, ureq::Error>, url: &str) -> Result<String, Failure> {
    let mut response = result.map_err(|e| Failure {
        retry: !matches!(e, ureq::Error::BadUri(_) | ureq::Error::Json(_) | ureq::Error::TlsRequired),
        message: format!("{url}: {e}"),
    })?;
    let status = response.status().as_u16();
    let text =
        response.body_mut().read_to_string().map_err(|e| Failure { message: format!("{url}: {e}"), retry: true })?;
    if !(200..300).contains(&status) {
        let snippet: String = text.chars().take(300).collect();
        return Err(Failure {
            message: format!("{url}: HTTP {status}: {snippet}"),
            retry: status == 429 || status >= 500,
        });
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reply_cut_at_the_token_limit_is_no_answer() {
        let reply = |content: &str, finish: &str| format!(r#"{{"choices": [{{"message": {{"content": {content}}}, "finish_reason": "{finish}"}}]}}"#);
        assert_eq!(chat_answer(&reply("\"B\"", "stop")).unwrap(), "B");
        assert_eq!(chat_answer(&reply("null", "stop")).unwrap(), "");
        for content in ["null", "\"Let me think about the\""] {
            let err = chat_answer(&reply(content, "length")).unwrap_err();
            assert!(err.contains("--max-tokens"), "{err}");
        }
    }

    #[test]
    fn endpoints() {
        assert_eq!(api_base("http://localhost:8000").unwrap(), "http://localhost:8000/v1");
        assert_eq!(api_base("http://h:1/v1/").unwrap(), "http://h:1/v1");
        let tls = api_base("https://api.example.com").unwrap_err().to_string();
        assert!(tls.contains("TLS is not built in") && tls.contains("tunnel"), "{tls}");
        assert!(api_base("localhost:8000").is_err());
        for bad in ["http://127.0.0.1:99999", "http://[::1", "http://h:port/v1"] {
            assert!(api_base(bad).is_err(), "{bad}");
        }
    }
}
