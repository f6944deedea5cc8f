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
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
    };
    if let Err(err) = result {
        eprintln!("error: {err:#}");
        std::process::exit(1);
    }
}
