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
    /// Print the build's version and the crates it is made of.
    About,
    /// Visual cues: task parser, variant catalogue, instance set, quick rendering.
    Cues(cmd::cues::Args),
}

fn main() {
    let cli = Cli::parse();
    let result: anyhow::Result<()> = match cli.command {
        Command::About => {
            println!("vifo {} (LIBERO-VIFO in pure Rust)", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Command::Cues(args) => cmd::cues::run(args),
    };
    if let Err(err) = result {
        eprintln!("error: {err:#}");
        std::process::exit(1);
    }
}
