//! `vifo web episode`: the browser demo's episode run natively through the same `Demo` the
//! page runs, printing the state hash the page shows and the hash of the last frames (same
//! bits expected: rapier's enhanced determinism and `libm` make wasm and native agree).

use anyhow::anyhow;
use clap::Args as ClapArgs;
use vifo_web::Demo;

#[derive(ClapArgs)]
pub struct Args {
    /// Task, `suite/index` (`libero_goal/0`).
    #[arg(long)]
    task: String,
    /// Shipped initial state (0..50).
    #[arg(long, default_value_t = 0)]
    init: usize,
    /// Cue instance id (`libero_goal/0/F1/caption_bar`; `vifo cues list --ids` lists them):
    /// needed by every condition but `original`.
    #[arg(long)]
    cue: Option<String>,
    /// Language condition: original, authorized, conflict or no_language.
    #[arg(long, default_value = "authorized")]
    condition: String,
    /// Episode seed (default: the benchmark's seed of the episode, as the page).
    #[arg(long)]
    seed: Option<u64>,
    /// Built-in policy: expert-cue, expert-language, expert-authorized, random, zero.
    #[arg(long, default_value = vifo_web::demo::DEFAULT_POLICY)]
    policy: String,
    /// Frame side in pixels (the page's default is 128; physics does not depend on it).
    #[arg(long, default_value_t = 128)]
    size: u32,
    /// Render agentview only.
    #[arg(long)]
    no_wrist: bool,
    /// Stop after this many steps even if the episode is not over.
    #[arg(long)]
    steps: Option<usize>,
    /// Print the final status as JSON.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    // The browser keeps a chosen cue while its condition is switched to `original`; here a cue
    // given with it would be dropped unseen.
    anyhow::ensure!(args.condition != "original" || args.cue.is_none(), "--condition original shows no cue: leave --cue out");
    let mut demo = Demo::new(args.size, !args.no_wrist).map_err(|e| anyhow!(e))?;
    demo.set_policy(&args.policy).map_err(|e| anyhow!(e))?;
    let mut status = demo.reset(&args.task, args.init, args.cue.as_deref(), &args.condition, args.seed).map_err(|e| anyhow!(e))?;
    while !status.done && args.steps.is_none_or(|n| status.steps < n) {
        status = demo.step().map_err(|e| anyhow!("step {}: {e}", status.steps + 1))?;
    }
    let frame_hash = demo.frame_hash().map_err(|e| anyhow!(e))?;
    if args.json {
        let mut value = serde_json::to_value(&status)?;
        value["frame_hash"] = frame_hash.into();
        println!("{value}");
    } else {
        let flag = |f: Option<bool>| f.map_or("-", |b| if b { "yes" } else { "no" });
        println!(
            "{} {} {} init {} seed {}: {} steps, done {}, language success {}, cue success {}, state hash {}, frame hash {}",
            status.task,
            status.condition,
            status.instance.as_deref().unwrap_or("(no cue)"),
            status.init,
            status.seed,
            status.steps,
            status.done,
            flag(status.language_success),
            flag(status.cue_success),
            status.state_hash,
            frame_hash
        );
    }
    Ok(())
}
