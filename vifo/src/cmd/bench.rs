//! `vifo bench physics|...`: speed figures.

use anyhow::Result;
use clap::{Args, Subcommand};
use vifo::bench;

#[derive(Args)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
    /// Print JSON instead of a table.
    #[arg(long, global = true)]
    pub json: bool,
}

#[derive(Subcommand)]
pub enum BenchWhat {
    /// Control steps per second (20 Hz steps of 25 physics substeps), one thread.
    Physics {
        /// Control steps to time per configuration.
        #[arg(long, default_value_t = 400)]
        steps: usize,
    },
}

pub fn run(args: &BenchArgs) -> Result<()> {
    match &args.what {
        BenchWhat::Physics { steps } => {
            let results = bench::physics::run(*steps);
            if args.json {
                println!("{}", serde_json::to_string_pretty(&results)?);
            } else {
                println!("{:<30} {:>14} {:>16}", "scene", "steps/s", "ms/control step");
                for r in &results {
                    println!("{:<30} {:>14.1} {:>16.3}", r.scene, r.control_steps_per_second, r.ms_per_control_step);
                }
            }
        }
    }
    Ok(())
}
