//! `vifo`: the LIBERO-VIFO command-line program.
//!
//! Each subcommand lives in its own module under `cmd/` and exposes `Args` plus `run`.

mod cmd;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "vifo", version, about = "LIBERO-VIFO: visual cue following benchmark for VLA policies, in pure Rust")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Where LIBERO's asset files were found and which parts are drawn from them.
    Assets(cmd::assets::AssetsArgs),
    /// Measure speed (physics, render, replay, scaling, cues).
    Bench(cmd::bench::BenchArgs),
    /// Run the scripted expert on LIBERO tasks and print success rates.
    Expert(cmd::expert::ExpertArgs),
    /// Cross-validate against MuJoCo reference recordings.
    Xval(cmd::xval::XvalArgs),
    /// Parse LIBERO BDDL files and print their tasks (text or --json).
    Bddl(cmd::bddl::Args),
    /// Visual cues: task parser, variant catalogue, instance set, quick rendering.
    Cues(cmd::cues::Args),
    /// Part I-A questions: answer with a VLM server, score, oracle and blind baselines.
    Vqa(cmd::vqa::Args),
    /// The paper's Tables 1 and 2 (and the same per suite and task, each rate with its 95 % interval, and every two
    /// policies compared on the episodes both ran) from results files and VQA scores.
    Report(cmd::report::Args),
    /// Render a task through agentview or the wrist camera (PNG, GIF or frames).
    Render(cmd::render::RenderArgs),
    /// Closed-loop episodes of built-in or remote policies, then the report (a quick default sample without --suite, --protocol, --family, --per-family, --episodes or --study).
    Run(cmd::run::Args),
    /// The shipped initial states: regenerate them or check them.
    InitStates(cmd::init_states::Args),
    /// The browser demo: build the site, serve it, run its episode natively.
    Web(cmd::web::Args),
}

fn main() {
    vifo::exit_quietly_when_output_closes();
    let cli = Cli::parse();
    let result: anyhow::Result<()> = match cli.command {
        Command::Assets(args) => cmd::assets::run(&args),
        Command::Bench(args) => cmd::bench::run(&args),
        Command::Expert(args) => cmd::expert::run(&args),
        Command::Xval(args) => cmd::xval::run(&args),
        Command::Bddl(args) => cmd::bddl::run(args),
        Command::Cues(args) => cmd::cues::run(args),
        Command::Vqa(args) => cmd::vqa::run(args),
        Command::Report(args) => cmd::report::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Run(args) => cmd::run::run(args),
        Command::InitStates(args) => cmd::init_states::run(args),
        Command::Web(args) => cmd::web::run(args),
    };
    if let Err(err) = result {
        eprintln!("error: {}", vifo::error_message(&err));
        std::process::exit(1);
    }
}
