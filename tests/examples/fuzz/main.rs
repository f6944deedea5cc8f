//! Fuzzing on the stable toolchain, in pure Rust: every input format the benchmark reads from
//! outside gets generated inputs and byte-level mutations of real ones, and this prints, per
//! target, the cases tried, how many the parser accepted (a fuzzer whose inputs all fail at the
//! first byte tests little), the panics, the hangs (a case over 1 s) and the slowest case.
//!
//! ```text
//! cargo run -p vifo-tests --example fuzz --profile fast -- --target all
//! cargo run -p vifo-tests --example fuzz --profile fast -- --target bddl --cases 20000 --seed 7
//! ```
//!
//! Without `--cases`, each target runs its gate: 1,000,000 cases for parsers, 100,000 for
//! whole-file decoders (`--smoke`, which `cargo test` runs, a five-hundredth of that). Inputs that panic or hang are
//! written to `target/fuzz/<target>/` for a regression test; the exit status is non-zero when
//! any target panicked, hung or missed its gate. Runs are deterministic: the same `--seed`
//! tries the same inputs.

mod mutate;
mod targets;

use std::panic::AssertUnwindSafe;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

use targets::{TARGETS, Target};

/// A case slower than this is a hang.
const HANG: Duration = Duration::from_secs(1);
/// A case still running after this is stuck: its input is saved and the process stops.
const STUCK: Duration = Duration::from_secs(30);

struct Args {
    target: String,
    cases: Option<u64>,
    smoke: bool,
    seed: u64,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { target: "all".into(), cases: None, smoke: false, seed: 0 };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or_else(|| format!("{name} needs a value"));
        match a.as_str() {
            "--target" => args.target = value("--target")?,
            "--cases" => args.cases = Some(value("--cases")?.parse().map_err(|e| format!("--cases: {e}"))?),
            "--seed" => args.seed = value("--seed")?.parse().map_err(|e| format!("--seed: {e}"))?,
            "--smoke" => args.smoke = true,
            other => return Err(format!("unknown argument {other:?} (--target NAME|all, --cases N, --seed S, --smoke)")),
        }
    }
    Ok(args)
}

/// What one target's run found.
struct Tally {
    cases: u64,
    accepted: u64,
    panics: u64,
    hangs: u64,
    slowest: Duration,
    slowest_len: usize,
}

fn main() {
    match parse_args().and_then(|args| run(&args)) {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("fuzz: {e}");
            std::process::exit(2);
        }
    }
}

/// Runs the chosen targets and prints a line per target; whether all passed: none panicked or
/// hung, and each ran to its gate unless `--cases` or `--smoke` said otherwise.
fn run(args: &Args) -> Result<bool, String> {
    let chosen: Vec<&Target> = TARGETS.iter().filter(|t| args.target == "all" || t.name == args.target).collect();
    if chosen.is_empty() {
        let names: Vec<&str> = TARGETS.iter().map(|t| t.name).collect();
        return Err(format!("unknown target {:?}; targets: {}", args.target, names.join(", ")));
    }
    // Panics are counted, not printed one by one.
    let last_panic: &'static Mutex<String> = Box::leak(Box::new(Mutex::new(String::new())));
    std::panic::set_hook(Box::new(move |info| {
        *last_panic.lock().unwrap_or_else(|p| p.into_inner()) = info.to_string();
    }));
    let watch = Watchdog::start();
    let mut failed = false;
    println!(
        "{:<14} {:>10} {:>6} {:>10} {:>7} {:>6} {:>11} {:>7}  gate",
        "target", "cases", "seeds", "accepted", "panics", "hangs", "slowest ms", "bytes"
    );
    for target in chosen {
        let cases = args.cases.unwrap_or(if args.smoke { target.kind.gate() / 500 } else { target.kind.gate() });
        let (tally, seeds) = fuzz(target, cases, args.seed, &watch, last_panic);
        let gate = target.kind.gate();
        let verdict = if tally.panics > 0 || tally.hangs > 0 {
            failed = true;
            "FAIL"
        } else if tally.cases >= gate {
            "met"
        } else {
            if args.cases.is_none() && !args.smoke {
                failed = true;
            }
            "not run to the gate"
        };
        println!(
            "{:<14} {:>10} {:>6} {:>10} {:>7} {:>6} {:>11.3} {:>7}  >= {gate}: {verdict}",
            target.name,
            tally.cases,
            seeds,
            tally.accepted,
            tally.panics,
            tally.hangs,
            tally.slowest.as_secs_f64() * 1e3,
            tally.slowest_len
        );
    }
    Ok(!failed)
}

/// Runs `cases` inputs through `target`: a quarter generated, the rest mutated seeds.
fn fuzz(target: &Target, cases: u64, seed: u64, watch: &Watchdog, last_panic: &Mutex<String>) -> (Tally, usize) {
    let seeds = (target.seeds)();
    let mut rng = Pcg64::seed_from_u64(seed ^ vifo_protocols::runner::fnv1a64(target.name.as_bytes()));
    let mut tally = Tally { cases: 0, accepted: 0, panics: 0, hangs: 0, slowest: Duration::ZERO, slowest_len: 0 };
    let out_dir = vifo_tests::workspace_root().join("target").join("fuzz").join(target.name);
    for case in 0..cases {
        let input = if seeds.is_empty() || rng.random_range(0..4) == 0 {
            (target.generate)(&mut rng)
        } else {
            let base = &seeds[rng.random_range(0..seeds.len())];
            let other = &seeds[rng.random_range(0..seeds.len())];
            mutate::mutate(&mut rng, base, other, target.dictionary)
        };
        watch.begin(&input, &out_dir.join(format!("stuck-{case}.bin")));
        let start = Instant::now();
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
        let took = start.elapsed();
        watch.end();
        tally.cases += 1;
        if took > tally.slowest {
            (tally.slowest, tally.slowest_len) = (took, input.len());
        }
        let problem = match (result, took > HANG) {
            (Ok(accepted), false) => {
                tally.accepted += accepted as u64;
                None
            }
            (Err(_), _) => {
                tally.panics += 1;
                Some(("panic", last_panic.lock().unwrap_or_else(|p| p.into_inner()).clone()))
            }
            (Ok(_), true) => {
                tally.hangs += 1;
                Some(("hang", format!("took {:.2} s", took.as_secs_f64())))
            }
        };
        if let Some((kind, why)) = problem {
            let path = out_dir.join(format!("{kind}-{case}.bin"));
            let saved = std::fs::create_dir_all(&out_dir).and_then(|()| std::fs::write(&path, &input));
            let at = saved.map_or_else(|e| format!("(not saved: {e})"), |()| path.display().to_string());
            eprintln!("{}: case {case}: {kind}: {why}\n  input ({} bytes): {at}", target.name, input.len());
        }
    }
    (tally, seeds.len())
}

/// A thread that saves the input of a case stuck past [`STUCK`] and ends the process, since a
/// case that never returns cannot be counted from inside.
struct Watchdog {
    /// Start of the running case in ms since `epoch`, or 0 between cases.
    started: &'static AtomicU64,
    current: &'static Mutex<(Vec<u8>, std::path::PathBuf)>,
    epoch: Instant,
}

impl Watchdog {
    fn start() -> Watchdog {
        let started: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(0)));
        let current: &'static Mutex<(Vec<u8>, std::path::PathBuf)> = Box::leak(Box::new(Mutex::new(Default::default())));
        let epoch = Instant::now();
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(500));
                let s = started.load(Ordering::Relaxed);
                if s != 0 && epoch.elapsed().as_millis() as u64 > s + STUCK.as_millis() as u64 {
                    let (input, path) = &*current.lock().unwrap_or_else(|p| p.into_inner());
                    if let Some(dir) = path.parent() {
                        let _ = std::fs::create_dir_all(dir);
                    }
                    let _ = std::fs::write(path, input);
                    eprintln!("fuzz: a case ran past {} s (a hang); input saved to {}", STUCK.as_secs(), path.display());
                    std::process::exit(1);
                }
            }
        });
        Watchdog { started, current, epoch }
    }

    fn begin(&self, input: &[u8], path: &std::path::Path) {
        let mut c = self.current.lock().unwrap_or_else(|p| p.into_inner());
        c.0.clear();
        c.0.extend_from_slice(input);
        c.1 = path.to_path_buf();
        self.started.store(self.epoch.elapsed().as_millis() as u64 + 1, Ordering::Relaxed);
    }

    fn end(&self) {
        self.started.store(0, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `cargo test` builds this example as a test too (`test = true` in Cargo.toml), so the
    /// README's test command runs every target's smoke.
    #[test]
    fn every_target_survives_its_smoke() {
        let args = Args { target: "all".into(), cases: None, smoke: true, seed: 0 };
        assert_eq!(run(&args), Ok(true), "a target panicked or hung (the table above; inputs in target/fuzz/)");
    }
}
