//! Every fault of the misbehaving policy server, `--trials` times each (default 10), in closed
//! loop with the openpi client, the runner and `--resume` (see `vifo_tests::fault_trials`).
//! Prints per fault: faults injected, error records naming the fault, errors naming something
//! else, episodes wrongly scored as success or failure, crashes, episodes lost after the
//! resume, and earlier records overwritten; exits non-zero unless the last five are all 0.
//!
//! ```text
//! cargo run -p vifo-tests --example policy_faults --profile fast -- --trials 10
//! ```

use vifo_tests::fault_server::Fault;
use vifo_tests::fault_trials::run_faults;

fn main() {
    let mut trials = 10;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match (a.as_str(), args.next().map(|v| v.parse::<usize>())) {
            ("--trials", Some(Ok(n))) if n > 0 => trials = n,
            _ => {
                eprintln!("policy_faults: expected --trials N (N >= 1)");
                std::process::exit(2);
            }
        }
    }
    println!("{:<14} {:>6} {:>6} {:>8} {:>9} {:>14} {:>7} {:>5} {:>11}", "fault", "tried", "fired", "named", "unnamed", "wrongly scored", "crashes", "lost", "overwritten");
    let mut bad = 0;
    for fault in Fault::ALL {
        let dir = match tempfile::tempdir() {
            Ok(d) => d,
            Err(e) => {
                eprintln!("policy_faults: scratch folder: {e}");
                std::process::exit(1);
            }
        };
        match run_faults(&[fault], trials, dir.path()) {
            Ok(c) => {
                println!(
                    "{:<14} {:>6} {:>6} {:>8} {:>9} {:>14} {:>7} {:>5} {:>11}",
                    fault.name(),
                    trials,
                    c.fired,
                    c.errors_named,
                    c.errors_unnamed,
                    c.wrongly_scored,
                    c.crashes,
                    c.lost,
                    c.overwritten
                );
                for m in &c.unnamed {
                    println!("    unnamed: {m}");
                }
                bad += c.errors_unnamed + c.wrongly_scored + c.crashes + c.lost + c.overwritten + (trials - c.fired.min(trials));
            }
            Err(e) => {
                println!("{:<14} could not run: {e}", fault.name());
                bad += 1;
            }
        }
    }
    if bad > 0 {
        std::process::exit(1);
    }
}
