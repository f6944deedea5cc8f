//! `vifo vqa`: export the Part I-A question set (`questions.jsonl` + one image per instance),
//! answer it with a VLM server, score answers, and sanity-check it with the oracle and blind
//! baselines.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::Context;
use clap::{Args as ClapArgs, Subcommand};
use vifo_protocols::vqa::answerers::{self, Blind};
use vifo_protocols::vqa::client::{ChatClient, ClientConfig};
use vifo_protocols::vqa::files::{append_predictions, read_predictions, read_questions};
use vifo_protocols::benchmark;
use vifo_protocols::runner::results::file_safe;
use vifo_protocols::env::{Env, EnvConfig};
use vifo_protocols::vqa::{self, Prediction, VqaScores, score};
use vifo::look::{LookArgs, label};
use vifo_cues::SetName;
use vifo_protocols::{CueForm, Protocol};
use vifo_scenes::view::CameraName;

#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write the questions of every cue instance of the 40 tasks and one image per instance
    /// (agentview after settling from initial state 0, cue drawn).
    Export {
        /// Output folder (questions.jsonl + images/).
        #[arg(short, long, visible_alias = "output")]
        out: PathBuf,
        /// Image side in pixels.
        #[arg(long, default_value_t = 256, value_parser = super::image_side)]
        size: u32,
        /// Instance set: paper (1,347 instances, 5,388 questions) or full.
        #[arg(long, default_value = "paper", value_parser = super::parse_set)]
        set: SetName,
        /// overlay (every instance, drawn over the image) or object (the F1, F6 and F8
        /// instances standing in the scene, paper §4.2).
        #[arg(long, default_value = "overlay", value_parser = super::parse_form)]
        form: CueForm,
        #[command(flatten)]
        look: LookArgs,
    },
    /// Ask an OpenAI-compatible server (vLLM, SGLang) every question; resumable.
    Answer {
        /// Export folder (questions.jsonl + images/).
        dir: PathBuf,
        /// Server base address, plain HTTP: http://host:port.
        #[arg(long)]
        endpoint: String,
        /// Model id (default: the first one the server lists).
        #[arg(long)]
        model: Option<String>,
        /// Sent as "Authorization: Bearer KEY" (servers started with --api-key).
        #[arg(long)]
        api_key: Option<String>,
        /// Requests in flight at once.
        #[arg(long, default_value_t = 4, value_parser = super::thread_count)]
        concurrency: usize,
        /// Retries after connection errors, timeouts, 429 and 5xx replies (at most 100).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(0..=100))]
        retries: u64,
        /// Seconds per request.
        #[arg(long, default_value_t = 120.0)]
        timeout: f64,
        /// Most tokens the model may answer with (an answer is a letter or a short phrase).
        #[arg(long, default_value_t = 64)]
        max_tokens: u32,
        /// Predictions file to append to (default DIR/predictions-<model>.jsonl).
        #[arg(short, long, visible_alias = "output")]
        out: Option<PathBuf>,
        /// No progress line.
        #[arg(long)]
        quiet: bool,
    },
    /// Score a predictions file ({"id", "prediction"} lines) with VLMEvalKit's extraction.
    Score {
        /// Export folder (questions.jsonl: the answer key).
        dir: PathBuf,
        /// Predictions file, as `vifo vqa answer` writes it.
        predictions: PathBuf,
        /// Name of the model (the policy name in reports).
        #[arg(long, default_value = "model")]
        model: String,
        /// Write the scores as JSON (input of `vifo report --vqa`).
        #[arg(short, long, visible_alias = "output")]
        out: Option<PathBuf>,
    },
    /// Write the answer key as predictions (checks the scoring path: 100 %).
    Oracle {
        /// Export folder (questions.jsonl).
        dir: PathBuf,
        /// Predictions file to write (then `vifo vqa score DIR FILE`).
        #[arg(short, long, visible_alias = "output")]
        out: PathBuf,
    },
    /// Text-only baselines (no image): letter prior, longest/shortest option, word overlap
    /// (how much of the answer leaks through the text; the gate is <= 35 % per stage).
    Blind {
        /// Export folder; without it, the questions of `--set` are generated here (the
        /// baselines need no images).
        dir: Option<PathBuf>,
        /// The instance set whose questions are generated without DIR: paper or full (an
        /// export folder's questions are those of its own set).
        #[arg(long, default_value = "paper", value_parser = super::parse_set, conflicts_with = "dir")]
        set: SetName,
        /// Also write each strategy's predictions into this folder.
        #[arg(short, long, visible_alias = "output")]
        out: Option<PathBuf>,
    },
}

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        Command::Export { out, size, set, form, look } => export(&out, size, set, form, &look),
        Command::Answer { dir, endpoint, model, api_key, concurrency, retries, timeout, max_tokens, out, quiet } => {
            let timeout = Duration::try_from_secs_f64(timeout)
                .ok()
                .filter(|t| !t.is_zero())
                .with_context(|| format!("--timeout {timeout}: give a positive number of seconds a request may take (at most about 10^19)"))?;
            let questions = read_questions(&dir)?;
            let client = ChatClient::new(ClientConfig {
                model,
                api_key,
                concurrency,
                retries: retries as usize,
                timeout,
                max_tokens,
                quiet,
                ..ClientConfig::new(&endpoint)
            })?;
            let out = out.unwrap_or_else(|| dir.join(format!("predictions-{}.jsonl", file_safe(client.model()))));
            let summary = client.answer_all(&dir, &questions, &out)?;
            println!(
                "{}: {} answered, {} already there, {} failed -> {}",
                client.model(),
                summary.answered,
                summary.skipped,
                summary.failed.len(),
                out.display()
            );
            for (id, error) in summary.failed.iter().take(10) {
                println!("  {id}: {error}");
            }
            if summary.gave_up {
                anyhow::bail!(
                    "gave up after {} failures in a row; is the server up at {endpoint}?",
                    summary.failed.len()
                );
            }
            anyhow::ensure!(
                summary.failed.is_empty(),
                "{} questions unanswered; run again to retry them",
                summary.failed.len()
            );
            Ok(())
        }
        Command::Score { dir, predictions: predictions_path, model, out } => {
            let questions = read_questions(&dir)?;
            let (predictions, cut) = read_predictions(&predictions_path)?;
            if cut > 0 {
                eprintln!("note: ignored a cut-off last line ({cut} bytes)");
            }
            let (form, set) = export_form_and_set(&dir)?;
            let scores = VqaScores { look: export_look(&dir)?, form, set, ..score(&model, &questions, &predictions) };
            // Scores of no answer would read as a model that got everything wrong.
            anyhow::ensure!(
                scores.unanswered < questions.len(),
                "{}: none of its {} predictions answers a question of {} ({} questions): wrong folder or file?",
                predictions_path.display(),
                predictions.len(),
                dir.display(),
                questions.len()
            );
            print!("{}", scores.markdown());
            if scores.unanswered > 0 {
                eprintln!("note: {} of {} questions have no prediction and count as wrong", scores.unanswered, questions.len());
            }
            if let Some(out) = out {
                write(&out, &(serde_json::to_string_pretty(&scores)? + "\n"))?;
            }
            Ok(())
        }
        Command::Oracle { dir, out } => {
            // A model's answers (`vqa answer` appends to its file) must not be replaced by the key.
            anyhow::ensure!(
                std::fs::metadata(&out).map_or(true, |m| m.len() == 0),
                "{}: already holds predictions; the answer key goes to a new file (name another --out)",
                out.display()
            );
            let questions = read_questions(&dir)?;
            write(&out, "")?;
            append_predictions(&out, &answerers::oracle(&questions))?;
            println!("{} answers -> {}", questions.len(), out.display());
            Ok(())
        }
        Command::Blind { dir, set, out } => {
            let questions = match dir {
                Some(dir) => read_questions(&dir)?,
                None => {
                    let qs = vqa::generate(benchmark::instances::all(set), &benchmark::instances::vqa_scenes())?;
                    println!("{} questions of the {set} set", qs.len());
                    qs
                }
            };
            print!("{}", answerers::blind(&questions).markdown());
            if let Some(out) = out {
                vifo_protocols::runner::create_folder(&out)?;
                for strategy in Blind::ALL {
                    let path = out.join(format!("blind-{}.jsonl", strategy.name()));
                    write(&path, "")?;
                    let predictions: Vec<Prediction> = answerers::blind_predictions(&questions, strategy);
                    append_predictions(&path, &predictions)?;
                }
            }
            Ok(())
        }
    }
}

/// The look an export's images were drawn with, as records store it (empty: built-in), from
/// its `look.txt`; exports written before it existed drew the built-in look.
fn export_look(dir: &Path) -> anyhow::Result<String> {
    let look = export_note(dir, "look.txt")?.unwrap_or_default();
    Ok(if look == vifo_scenes::look::BUILT_IN { String::new() } else { look })
}

/// The trimmed text of one of an export folder's notes (`look.txt`, `form.txt`, `set.txt`);
/// `None` where the file is absent (a folder exported before it was written).
fn export_note(dir: &Path, name: &str) -> anyhow::Result<Option<String>> {
    let path = dir.join(name);
    match std::fs::read_to_string(&path) {
        Ok(text) => Ok(Some(text.trim().to_string())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e).with_context(|| path.display().to_string()),
    }
}

/// The cue form and instance set an export folder records (`form.txt`, `set.txt`); `None`
/// where a file is absent (a folder exported before they were written).
fn export_form_and_set(dir: &Path) -> anyhow::Result<(Option<CueForm>, Option<SetName>)> {
    let read = |name: &str| export_note(dir, name);
    let form = read("form.txt")?.map(|f| super::parse_form(&f).map_err(|e| anyhow::anyhow!("{}: {e}", dir.join("form.txt").display()))).transpose()?;
    let set = read("set.txt")?.map(|s| s.parse::<SetName>().map_err(|e| anyhow::anyhow!("{}: {e}", dir.join("set.txt").display()))).transpose()?;
    Ok((form, set))
}

/// Questions for every instance of a set, each instance's image from its scene after the
/// settle steps. The set's name goes to `set.txt` beside the questions, the look the images
/// were drawn with to `look.txt`.
fn export(out: &Path, size: u32, set: SetName, form: CueForm, look: &LookArgs) -> anyhow::Result<()> {
    let look = look.look()?;
    vifo_protocols::env::scenes::use_look(look.clone())?;
    let questions = benchmark::instances::questions(set, form)?;
    let images = questions.iter().map(|q| q.instance_id.as_str()).collect::<std::collections::BTreeSet<_>>().len();
    let mut env = Env::new(EnvConfig { size, cameras: vec![CameraName::AgentView], ..EnvConfig::default() });
    // The notes first: the questions, written last, are what makes the folder an export.
    vifo_protocols::runner::create_folder(out)?;
    write(&out.join("set.txt"), &format!("{set}\n"))?;
    write(&out.join("form.txt"), &format!("{}\n", form.name()))?;
    write(&out.join("look.txt"), &format!("{}\n", label(look.as_deref())))?;
    let mut done = 0;
    let written = vqa::files::export(out, &questions, |id| {
        done += 1;
        if done % 100 == 0 {
            eprintln!("{done}/{images} images");
        }
        let cue = benchmark::instances::find(id).map_err(|e| e.to_string())?;
        let task = benchmark::instances::task_of(cue).map_err(|e| e.to_string())?;
        let spec = benchmark::specs::spec(&task, Protocol::Authorized, Some(id), 0, 0).map_err(|e| e.to_string())?;
        let spec = vifo_protocols::EpisodeSpec { cue_form: form, ..spec };
        Ok(env.reset(&spec).map_err(|e| e.to_string())?.agentview.clone())
    })?;
    println!("{} questions ({set} set), {written} images -> {}", questions.len(), out.display());
    Ok(())
}

/// `--form overlay|object`.
fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

