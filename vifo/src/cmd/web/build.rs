//! `vifo web build OUT`: the static site of the browser demo. Builds `web/` for
//! `wasm32-unknown-unknown`, generates its JavaScript bindings with `wasm-bindgen` (the CLI of
//! exactly the version `Cargo.lock` pins, installed once under `target/tools` with
//! `cargo install` when missing), copies `web/www/`, and prints every file's size raw and
//! gzipped (the download gate). No npm; nothing is fetched when the page runs.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use flate2::Compression;
use flate2::write::GzEncoder;

#[derive(ClapArgs)]
pub struct Args {
    /// Output folder (created; files of the same names are replaced).
    #[arg(default_value = "vifo-web")]
    out: PathBuf,
    /// Cargo profile of the wasm build (`fast`: release code without the fat-LTO link;
    /// `release` for a smaller, slower-to-build module).
    #[arg(long, default_value = "fast")]
    profile: String,
    /// The workspace to build from (default: the one this program was built from).
    #[arg(long)]
    workspace: Option<PathBuf>,
}

const TARGET: &str = "wasm32-unknown-unknown";

pub fn run(args: &Args) -> anyhow::Result<()> {
    let root = match &args.workspace {
        Some(dir) => dir.clone(),
        None => Path::new(env!("CARGO_MANIFEST_DIR")).join(".."),
    };
    let www = root.join("web/www");
    if !www.join("index.html").is_file() {
        bail!("{} has no web/www/index.html; pass --workspace with the LIBERO-VIFO checkout", root.display());
    }
    // Before the minutes of the build, so a bad output folder is reported at once.
    vifo_protocols::runner::create_folder(&args.out)?;
    let version = wasm_bindgen_version(&root.join("Cargo.lock"))?;
    let bindgen = wasm_bindgen_cli(&root, &version)?;
    eprintln!("building vifo-web for {TARGET} (profile {})", args.profile);
    let status = Command::new(cargo())
        .current_dir(&root)
        .args(["build", "-p", "vifo-web", "--lib", "--target", TARGET, "--profile", &args.profile])
        .status()
        .context("running cargo")?;
    if !status.success() {
        bail!("cargo build of vifo-web for {TARGET} failed ({status}); is the target installed? rustup target add {TARGET}");
    }
    let dir = if args.profile == "dev" { "debug" } else { args.profile.as_str() };
    let wasm = root.join("target").join(TARGET).join(dir).join("vifo_web.wasm");
    let status = Command::new(&bindgen)
        .args(["--target", "web", "--no-typescript", "--out-dir"])
        .arg(&args.out)
        .arg(&wasm)
        .status()
        .with_context(|| format!("running {}", bindgen.display()))?;
    if !status.success() {
        bail!("wasm-bindgen failed on {} ({status})", wasm.display());
    }
    for entry in std::fs::read_dir(&www).with_context(|| www.display().to_string())? {
        let path = entry?.path();
        if path.is_file() {
            let to = args.out.join(path.file_name().context("file name")?);
            std::fs::copy(&path, &to).with_context(|| format!("{} -> {}", path.display(), to.display()))?;
        }
    }
    print_sizes(&args.out)
}

/// The `wasm-bindgen` crate's version in the lock file; the CLI must match it exactly.
fn wasm_bindgen_version(lock: &Path) -> anyhow::Result<String> {
    let text = std::fs::read_to_string(lock).with_context(|| lock.display().to_string())?;
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        if line == "name = \"wasm-bindgen\"" {
            let version = lines.next().and_then(|l| l.strip_prefix("version = \"")).and_then(|v| v.strip_suffix('"'));
            return version.map(str::to_string).with_context(|| format!("{}: wasm-bindgen has no version line", lock.display()));
        }
    }
    bail!("{} does not lock wasm-bindgen", lock.display())
}

/// `wasm-bindgen` of `version`: on PATH or under `target/tools`, else installed there.
fn wasm_bindgen_cli(root: &Path, version: &str) -> anyhow::Result<PathBuf> {
    let tools = root.join("target/tools");
    let local = tools.join("bin/wasm-bindgen");
    let wanted = format!("wasm-bindgen {version}");
    let matches = |cli: &Path| {
        Command::new(cli).arg("--version").output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == wanted)
    };
    if matches(&local) {
        return Ok(local);
    }
    if matches(Path::new("wasm-bindgen")) {
        return Ok(PathBuf::from("wasm-bindgen"));
    }
    eprintln!("installing wasm-bindgen-cli {version} into {} (once)", tools.display());
    // With the CLI's own lock file first; a registry mirror that lacks one of its pins (seen:
    // webpki-roots 1.0.11) gets a fresh resolution of the same CLI version.
    for locked in [true, false] {
        let mut install = Command::new(cargo());
        install.args(["install", "wasm-bindgen-cli", "--version", &format!("={version}"), "--root"]).arg(&tools);
        if locked {
            install.arg("--locked");
        }
        if install.status().context("running cargo install")?.success() && matches(&local) {
            return Ok(local);
        }
    }
    bail!("could not install wasm-bindgen-cli {version} (cargo install wasm-bindgen-cli --version ={version} --root {})", tools.display())
}

fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

/// Every file of the site, raw and gzipped (level 6, what static hosts typically serve), and the
/// totals.
fn print_sizes(out: &Path) -> anyhow::Result<()> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(out)?.filter_map(|e| Some(e.ok()?.path())).filter(|p| p.is_file()).collect();
    files.sort();
    let (mut raw, mut gz) = (0, 0);
    println!("{:<28} {:>12} {:>12}", "file", "bytes", "gzip bytes");
    for file in &files {
        let bytes = std::fs::read(file)?;
        let mut encoder = GzEncoder::new(Vec::new(), Compression::new(6));
        encoder.write_all(&bytes)?;
        let zipped = encoder.finish()?.len();
        println!("{:<28} {:>12} {:>12}", file.file_name().unwrap_or_default().to_string_lossy(), bytes.len(), zipped);
        raw += bytes.len();
        gz += zipped;
    }
    println!("{:<28} {:>12} {:>12}", "total", raw, gz);
    println!("GATE web download: {:.2} MB gzipped (goal <= 6 MB), {:.2} MB raw, site in {}", gz as f64 / 1e6, raw as f64 / 1e6, out.display());
    Ok(())
}
