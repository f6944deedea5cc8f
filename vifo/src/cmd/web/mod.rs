//! `vifo web`: the browser demo (`web/`): build the static site, serve it on 127.0.0.1, and run
//! the page's episode natively to check its state hash.

mod build;
mod episode;
mod serve;

use clap::{Args as ClapArgs, Subcommand};

#[derive(ClapArgs)]
pub struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build the WebAssembly module and write the whole site (HTML, JS, wasm) to OUT.
    Build(build::Args),
    /// Serve a built site over plain HTTP on 127.0.0.1.
    Serve(serve::Args),
    /// Run the page's episode natively (same code, same seed) and print its state hash.
    Episode(episode::Args),
}

pub fn run(args: Args) -> anyhow::Result<()> {
    match args.command {
        Command::Build(a) => build::run(&a),
        Command::Serve(a) => serve::run(&a),
        Command::Episode(a) => episode::run(&a),
    }
}
