//! The `vifo` program as a shell runs it.

use std::process::{Command, Stdio};

/// `vifo cues list --ids | head` is ordinary use: when the reader closes the pipe, `vifo` ends
/// quietly with the status a closed pipe gives C tools, not with a panic on standard error.
#[test]
fn a_closed_output_pipe_ends_vifo_quietly() {
    // The reading end is closed before vifo starts, so its first line meets a closed pipe
    // however the machine schedules the two (its whole listing would fit in a pipe's buffer).
    let (reader, writer) = std::io::pipe().expect("make a pipe");
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["cues", "list", "--ids", "--set", "full"])
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("run vifo");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(vifo::CLOSED_OUTPUT_STATUS), "stderr: {stderr}");
    assert!(stderr.is_empty(), "vifo printed on a closed pipe: {stderr}");
}

/// The ids `vifo cues list --ids` prints are the ones `vifo render --cue` takes, and a
/// mistyped one names what the task has.
#[test]
fn listed_ids_are_accepted_and_a_mistyped_one_names_the_tasks_ids() {
    let vifo = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_vifo")).args(args).output().expect("run vifo");
    let out = vifo(&["cues", "list", "--ids", "--task", "libero_goal/3", "--family", "F2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let ids: Vec<String> = String::from_utf8_lossy(&out.stdout).lines().map(str::to_string).collect();
    assert!(ids.len() >= 2 && ids.iter().all(|id| id.starts_with("libero_goal/3/F2/")), "{ids:?}");
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("cue.png");
    let out = vifo(&["render", "--builtin-look", "--size", "64", "--cue", &ids[0], "-o", png.to_str().unwrap()]);
    assert!(out.status.success() && png.is_file(), "{}", String::from_utf8_lossy(&out.stderr));
    let out = vifo(&["render", "--builtin-look", "--size", "64", "--cue", "libero_goal/3/F2/straight_arow_red", "-o", png.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains(&ids[0]["libero_goal/3/F2/".len()..]) && stderr.contains("vifo cues list --ids --task libero_goal/3"), "{stderr}");
}

/// `vifo render --model-profile` writes what that model receives: pi0.5's 224² image, the
/// frame mirrored, where a cue facing the model reads the right way; an unknown profile is
/// named with the known ones.
#[test]
fn render_shows_a_cue_as_a_model_receives_it() {
    let dir = tempfile::tempdir().unwrap();
    let render = |name: &str, extra: &[&str]| {
        let png = dir.path().join(name);
        let mut args = vec!["render", "--builtin-look", "--size", "64", "--cue", "libero_goal/0/F1/caption_bar", "-o", png.to_str().unwrap()];
        args.extend_from_slice(extra);
        let out = Command::new(env!("CARGO_BIN_EXE_vifo")).args(&args).output().expect("run vifo");
        (out.status.success().then(|| vifo_render::imageio::load_png(&png).unwrap()), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let (upright, _) = render("upright.png", &[]);
    let (seen, err) = render("seen.png", &["--model-profile", "pi05"]);
    let (faced, _) = render("faced.png", &["--model-profile", "pi05", "--cue-facing", "model"]);
    let (faced_upright, _) = render("faced_upright.png", &["--cue-facing", "model"]);
    let (upright, seen, faced, faced_upright) = (upright.unwrap(), seen.unwrap_or_else(|| panic!("{err}")), faced.unwrap(), faced_upright.unwrap());
    assert_eq!((upright.width, seen.width, seen.height), (64, 224, 224));
    assert!(seen != faced && upright != faced_upright);
    let (none, err) = render("none.png", &["--model-profile", "nope"]);
    assert!(none.is_none() && err.contains("unknown --model-profile \"nope\"") && err.contains("pi05"), "{err}");
}

/// What `vifo render` writes says what drew it once it leaves the console: its PNGs carry the
/// look and the scene as PNG text, its GIFs as a comment.
#[test]
fn rendered_files_record_their_look() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let contains = |bytes: &[u8], needle: &[u8]| bytes.windows(needle.len()).any(|w| w == needle);
    let (png, gif, frames) = (path("still.png"), path("roll.gif"), path("frames"));
    let args = ["render", "--builtin-look", "--task", "libero_spatial/0", "--size", "32", "--steps", "1", "-o", &png, "--gif", &gif, "--frames", &frames];
    let out = Command::new(env!("CARGO_BIN_EXE_vifo")).args(args).output().expect("run vifo");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // It says where the files went.
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains(&format!("-> {png}, {gif}, {frames}")), "{said}");
    assert!(said.contains("the task's goal did not hold within 1 steps"), "{said}");
    // An expert rollout says when the task was done, or that it needs more steps.
    for (steps, says) in [("300", "the task's goal held from step "), ("40", "did not hold within 40 steps: the expert may need more")] {
        let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
            .args(["render", "--builtin-look", "--task", "libero_goal/3", "--size", "16", "--expert", "--steps", steps, "--gif", &path("expert.gif")])
            .output()
            .expect("run vifo");
        let said = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && said.contains(says), "{said}");
    }
    for file in [png, format!("{frames}/frame_0001.png")] {
        let bytes = std::fs::read(&file).unwrap();
        assert!(contains(&bytes, b"tEXtlook\0built-in") && contains(&bytes, b"tEXtscene\0libero_spatial/0 init 0, agentview"), "{file}");
    }
    assert!(contains(&std::fs::read(&gif).unwrap(), b"look: built-in; scene: libero_spatial/0 init 0, agentview"));
    let cue = path("cue.png");
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        // `--output`, `--out` and `-o` name the output of every command.
        .args(["render", "--builtin-look", "--size", "32", "--cue", "libero_goal/0/F1/caption_bar", "--cue-facing", "model", "--output", &cue])
        .output()
        .expect("run vifo");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let bytes = std::fs::read(&cue).unwrap();
    assert!(contains(&bytes, b"tEXtlook\0built-in") && contains(&bytes, b"libero_goal/0/F1/caption_bar on libero_goal/0 (init 0) with agentview, cue facing the model"));
}

/// A selection that holds no episode is an error naming the option, not an empty table with a
/// success rate of "-0.0%" (nor a table header over the error).
#[test]
fn an_empty_expert_selection_is_an_error() {
    for (args, says) in [
        (&["--suite", "libero_goal", "--task", "11"][..], "--task 11: libero_goal has tasks 0 to 9"),
        (&["--suite", "libero_goal", "--task", "0", "--first", "60"][..], "--first 60: libero_goal/0 has initial states 0 to 49"),
        (&["--suite", "libero_goal", "--episodes", "0"][..], "'0' for '--episodes <EPISODES>': expected 1 or more"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_vifo")).arg("expert").args(args).output().expect("run vifo");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(says), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}: {}", String::from_utf8_lossy(&out.stdout));
    }
}

/// A run's folder whose results file holds no episode says so, not "give results files".
#[test]
fn an_empty_results_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("results-expert-cue.jsonl");
    std::fs::write(&file, "").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vifo")).arg("report").arg(dir.path()).output().expect("run vifo");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains(&format!("{} holds no episode records", file.display())), "{stderr}");
}

/// `vifo web serve` on a port another server holds says so and how to get a free one.
#[test]
fn a_taken_port_is_named_with_the_way_out() {
    let site = tempfile::tempdir().unwrap();
    std::fs::write(site.path().join("index.html"), "<html></html>").unwrap();
    let taken = std::net::TcpListener::bind(("127.0.0.1", 0)).unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let out = Command::new(env!("CARGO_BIN_EXE_vifo")).args(["web", "serve"]).arg(site.path()).args(["--port", &port]).output().expect("run vifo");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains(&format!("port {port} of 127.0.0.1 is taken")) && stderr.contains("--port 0"), "{stderr}");
}

/// `vifo run --study --instance` with an id the study lacks names ids it has, before anything
/// is printed or run.
#[test]
fn an_unknown_study_instance_names_ones_the_study_has() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--study", "objects", "--instance", "libero_spatial/0/F1/no_such", "--policy", "zero", "--out"])
        .arg(dir.path().join("run"))
        .output()
        .expect("run vifo");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("such as libero_spatial/0/F1/caption_bar"), "{stderr}");
    assert!(out.stdout.is_empty(), "{}", String::from_utf8_lossy(&out.stdout));
    assert!(!dir.path().join("run").exists());
}

/// A run resumed with cues facing another way than its first episodes keeps both episodes but
/// writes no report mixing them, and exits with an error that says why.
#[test]
fn a_resumed_run_that_would_mix_looks_writes_no_report() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("run");
    let run = |episodes: &str, extra: &[&str]| {
        let mut args = vec!["run", "--suite", "libero_goal", "--protocol", "authorized", "--family", "F1", "--per-family", "1"];
        args.extend_from_slice(&["--policy", "zero", "--render-always", "--size", "32", "--builtin-look", "--quiet", "--threads", "1", "--episodes", episodes]);
        args.extend_from_slice(extra);
        Command::new(env!("CARGO_BIN_EXE_vifo")).args(&args).arg("--out").arg(&out_dir).output().expect("run vifo")
    };
    let first = run("1", &["--cue-facing", "model"]);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    std::fs::remove_dir_all(out_dir.join("report")).unwrap();
    let resumed = run("2", &["--resume"]);
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(!resumed.status.success() && stderr.contains("no report was written") && stderr.contains("built-in with cues facing the model (1 episode)"), "{stderr}");
    assert_eq!(std::fs::read_to_string(out_dir.join("results-zero.jsonl")).unwrap().lines().count(), 2);
    assert!(!out_dir.join("report").exists());
}

/// A run whose policy server is not up stops before its first episode, naming the server and
/// writing nothing: before, every episode became an error record and the report a table of
/// dashes.
#[test]
fn a_run_whose_server_is_not_up_stops_before_any_episode() {
    let dir = tempfile::tempdir().unwrap();
    // A port that was free a moment ago: nothing listens there.
    let port = std::net::TcpListener::bind(("127.0.0.1", 0)).unwrap().local_addr().unwrap().port();
    for url in [format!("ws://127.0.0.1:{port}"), format!("http://127.0.0.1:{port}/act"), format!("tcp://127.0.0.1:{port}")] {
        let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
            .args(["run", "--builtin-look", "--quiet", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1"])
            .args(["--policy", &url, "--out"])
            .arg(dir.path())
            .output()
            .expect("run vifo");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && stderr.contains(&format!("cannot connect to {url}")) && stderr.contains("is the server up?"), "{url}: {stderr}");
        let written: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).filter(|n| n.to_string_lossy().ends_with(".jsonl")).collect();
        assert!(written.is_empty(), "{url}: {written:?}");
    }
    // A profile meant for another server's format was taken without a word.
    let url = format!("http://127.0.0.1:{port}/act");
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--builtin-look", "--quiet", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1"])
        .args(["--policy", &url, "--model-profile", "pi05", "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("profile pi05 is made for its model's openpi server (ws://)"), "{stdout}");
}

/// The request timeout was fixed at 180 s: a server that took a connection and never answered
/// cost three minutes per episode, and a slow first compile could not be waited for longer.
/// Such a run keeps its error records and writes its report, under the name given to the
/// model, but exits with an error, so that a script does not take it for a result.
#[test]
fn a_server_that_never_answers_times_out_after_policy_timeout() {
    let dir = tempfile::tempdir().unwrap();
    // Connections queue in the listener's backlog; nothing ever reads or answers them.
    let listener = std::net::TcpListener::bind(("127.0.0.1", 0)).unwrap();
    let url = format!("http://127.0.0.1:{}/act", listener.local_addr().unwrap().port());
    let start = std::time::Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--builtin-look", "--quiet", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1"])
        .args(["--threads", "1", "--policy", &url, "--policy-timeout", "0.5", "--policy-name", "oft-libero-goal", "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stdout.contains("timed out after 0.5 s"), "{stdout}");
    assert!(stderr.contains("10 episodes ended in errors") && stderr.contains("--resume"), "{stderr}");
    assert!(start.elapsed().as_secs() < 120, "{:?}", start.elapsed());
    let results = std::fs::read_to_string(dir.path().join("results-oft-libero-goal.jsonl")).unwrap();
    assert_eq!(results.lines().count(), 10, "{results}");
    assert!(results.lines().all(|l| l.contains("\"policy\":\"oft-libero-goal\"")), "{results}");
    let table = std::fs::read_to_string(dir.path().join("report").join("table1.md")).unwrap();
    assert!(table.contains("| oft-libero-goal |"), "{table}");
    drop(listener);
}

/// The same episodes in two results files (a copy, overlapping shards) or twice in one are counted once, and
/// the report says so: before, the order of the files decided silently which outcome counted.
#[test]
fn episodes_repeated_across_results_files_are_noted() {
    let dir = tempfile::tempdir().unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--builtin-look", "--quiet", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1", "--sample", "1"])
        .args(["--policy", "zero", "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let first = dir.path().join("results-zero.jsonl");
    let copy = dir.path().join("copy.jsonl");
    std::fs::copy(&first, &copy).unwrap();
    let report = |files: &[&std::path::Path]| {
        let out = Command::new(env!("CARGO_BIN_EXE_vifo")).arg("report").args(files).arg("--out").arg(dir.path().join("r")).output().unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let noted = report(&[&first, &copy]);
    assert!(noted.contains("completed episodes recorded more than once: 1 (the first: zero libero_goal/") && noted.contains(", 2 times in "), "{noted}");
    assert!(!report(&[&first]).contains("more than once"));
    // Twice in one file (a hand-merged file) is noted too: before, the later line won unseen.
    let text = std::fs::read_to_string(&first).unwrap();
    std::fs::write(&copy, format!("{text}{text}")).unwrap();
    assert!(report(&[&copy]).contains("recorded more than once: 1"));
}

/// Counts and selections that would run nothing, server options given to built-in policies
/// and an unknown gallery task are refused before anything is written (each once ran nothing,
/// ignored the option or drew another task, and exited 0).
#[test]
fn nothing_to_run_and_options_that_would_be_ignored_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out_arg = out.to_str().unwrap();
    let goal_zero = ["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "zero", "--out", out_arg];
    let cue_ppm = dir.path().join("cue.ppm");
    let cue_ppm = cue_ppm.to_str().unwrap();
    let answers = dir.path().join("pred-model.jsonl");
    std::fs::write(&answers, "{\"id\": \"q1\", \"prediction\": \"A\"}\n").unwrap();
    let answers = answers.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        ([&goal_zero[..], &["--episodes", "0"]].concat(), "'--episodes <EPISODES>': expected 1 or more"),
        ([&goal_zero[..], &["--sample", "0"]].concat(), "'--sample <SAMPLE>': expected 1 or more"),
        (vec!["run", "--protocol", "authorized", "--policy", "zero", "--per-family", "0", "--out", out_arg], "'--per-family <PER_FAMILY>': expected 1 or more"),
        (vec!["run", "--study", "objects", "--protocol", "original", "--policy", "zero", "--out", out_arg], "the selection has no episodes"),
        (vec!["run", "--suite", "libero_nope", "--out", out_arg], "unknown suite \"libero_nope\""),
        ([&goal_zero[..], &["--model-profile", "pi05"]].concat(), "say how to talk to a policy server; zero is built-in"),
        (vec!["bench", "physics", "--steps", "0"], "expected 1 or more"),
        (vec!["bench", "scaling", "--threads", "0,2", "--scratch", out_arg], "'--threads <THREADS>': expected 1 or more"),
        (vec!["init-states", "generate", "--suite", "libero_goal", "--states", "0", "--out", out_arg], "expected 1 or more"),
        (vec!["cues", "gallery", "--task", "libero_goal/99", "-o", out_arg], "task 'libero_goal/99': no such task"),
        // A huge count or tile was allocated before it was checked (a 120 GB sheet, a list of
        // 10^12 episodes).
        (vec!["cues", "gallery", "--size", "100000", "-o", out_arg], "'--size <SIZE>': 100000 pixels: expected 16 to 4096"),
        // Every --size is checked the same way, before a look is loaded (render's was checked by
        // the camera after loading the assets).
        (vec!["render", "--task", "libero_goal/0", "--size", "0", "-o", "x.png"], "'--size <SIZE>': 0 pixels: expected 16 to 4096"),
        ([&goal_zero[..], &["--size", "8"]].concat(), "'--size <SIZE>': 8 pixels: expected 16 to 4096"),
        (vec!["cues", "render", "caption_bar", "put the bowl on the plate", "--size", "99999", "--out", cue_ppm], "'--size <SIZE>': 99999 pixels"),
        (vec!["vqa", "export", "-o", out_arg, "--size", "abc"], "'--size <SIZE>': invalid digit"),
        ([&goal_zero[..], &["--episodes", "1000000000000"]].concat(), "at most 10000 episodes per instance"),
        (vec!["expert", "--episodes", "20000"], "at most 10000 episodes per instance"),
        // Huge counts ran for ever, panicked with a capacity overflow or started a billion
        // threads for four questions.
        (vec!["init-states", "generate", "--suite", "libero_goal", "--states", "18446744073709551615", "--out", out_arg], "at most 10000 states per task"),
        (vec!["render", "--task", "libero_goal/0", "--gif", "g.gif", "--steps", "18446744073709551615"], "at most 5000 control steps"),
        (vec!["bench", "scaling", "--max-threads", "100000", "--scratch", out_arg], "at most 1024 threads"),
        (vec!["bench", "cues", "--task", "vifo_piper/0"], "have no cue instance of F1, F2"),
        (vec!["web", "episode", "--task", "libero_goal/0", "--cue", "libero_goal/0/F1/caption_bar", "--condition", "original"], "--condition original shows no cue"),
        // The cue object's picture showed state 49 labelled 99999.
        (vec!["render", "--cue", "libero_goal/0/F1/caption_bar", "--as-object", "--init", "99999", "-o", "x.png"], "--init 99999: the tasks have 50 shipped initial states"),
        (vec!["bench", "scaling", "--threads", "1,100000", "--scratch", out_arg], "at most 1024 threads"),
        (vec!["vqa", "answer", out_arg, "--endpoint", "http://127.0.0.1:1", "--concurrency", "1000000000"], "at most 1024 threads"),
        (vec!["vqa", "answer", out_arg, "--endpoint", "http://127.0.0.1:1", "--retries", "18446744073709551615"], "--retries"),
        (vec!["cues", "render", "caption_bar", "put the bowl on the plate", "--source", "nan,1", "--out", cue_ppm], "NaN is not a finite number"),
        (vec!["cues", "render", "caption_bar", "put the bowl on the plate", "--out", "cue.png"], "as PPM: give a name ending in .ppm"),
        (vec!["vqa", "blind", out_arg, "--set", "full"], "cannot be used with"),
        // A trial count overwrote the shipped states.
        (vec!["init-states", "generate", "--suite", "libero_goal", "--states", "5"], "--states 5: the shipped files hold 50 states per task"),
        // The answer key replaced a model's answers.
        (vec!["vqa", "oracle", out_arg, "--out", answers], "already holds predictions"),
        // A timeout too long for a duration panicked.
        (vec!["vqa", "answer", out_arg, "--endpoint", "http://127.0.0.1:1", "--model", "m", "--timeout", "1e30"], "--timeout 1000000000000000000000000000000: give a positive number"),
        (vec!["vqa", "answer", out_arg, "--endpoint", "http://127.0.0.1:1", "--model", "m", "--timeout", "0"], "--timeout 0: give a positive number"),
        ([&goal_zero[..], &["--policy-timeout", "0"]].concat(), "0: give a number of seconds above 0"),
        ([&goal_zero[..], &["--policy-timeout", "1e30"]].concat(), "at most 86400"),
        // A JPEG's name held PNG bytes.
        (vec!["render", "--task", "libero_spatial/0", "-o", "frame.jpg"], "as PNG: give a name ending in .png"),
        (vec!["render", "--task", "libero_spatial/0", "--gif", "rollout.png"], "as GIF: give a name ending in .gif"),
        // Server addresses are checked before any episode runs: a port that is not one was
        // quietly sent to port 80, a missing one gave an error per episode.
        (vec!["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "ws://127.0.0.1:99999", "--out", out_arg], "port \"99999\" is not a number"),
        (vec!["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "http://127.0.0.1:notaport/act", "--out", out_arg], "port \"notaport\""),
        (vec!["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "tcp://127.0.0.1", "--out", out_arg], "no port"),
        (vec!["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "ws://:8000", "--out", out_arg], "no host"),
        (vec!["run", "--suite", "libero_goal", "--protocol", "original", "--policy", "grpc://127.0.0.1:1", "--out", out_arg], "add ?policy_type="),
        // A name is for one served model: on a built-in it would pass for another policy.
        ([&goal_zero[..], &["--policy-name", "mine"]].concat(), "--policy-name \"mine\" names one policy server"),
        (vec!["run", "--suite", "libero_goal", "--policy", "ws://127.0.0.1:1", "--policy-name", "expert-cue", "--out", out_arg], "a built-in policy's name"),
    ];
    for (args, says) in cases {
        let run = Command::new(env!("CARGO_BIN_EXE_vifo")).args(&args).output().expect("run vifo");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && stderr.contains(says), "{args:?}: {stderr}");
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

/// A policy named twice runs once: twice, its second run found the first one's results file
/// and the run ended in an error without a report.
#[test]
fn a_policy_named_twice_runs_once() {
    let dir = tempfile::tempdir().unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1", "--sample", "1"])
        .args(["--policy", "zero", "--policy", "zero", "--quiet", "--clips", "none", "--builtin-look", "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}{stdout}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.contains("1 policy ->") && dir.path().join("report").is_dir(), "{stdout}");
    // The run's lock file went with it.
    let locks: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).filter(|n| n.to_string_lossy().ends_with(".lock")).collect();
    assert!(locks.is_empty(), "{locks:?}");

    // `vifo report` refuses records of another results version (their fields may mean
    // something else) and a device given as a results file, naming each.
    let results = dir.path().join("results-zero.jsonl");
    let text = std::fs::read_to_string(&results).unwrap();
    assert!(text.contains("\"version\":1,"), "{text}");
    let other = dir.path().join("other.jsonl");
    std::fs::write(&other, text.replace("\"version\":1,", "\"version\":99,")).unwrap();
    for (file, says) in [(other.as_path(), "holds records of results version 99"), (std::path::Path::new("/dev/zero"), "not a plain file")] {
        let report = Command::new(env!("CARGO_BIN_EXE_vifo")).arg("report").arg(file).arg("--out").arg(dir.path().join("r2")).output().unwrap();
        let stderr = String::from_utf8_lossy(&report.stderr);
        assert!(!report.status.success() && stderr.contains(says), "{stderr}");
    }

    // The zero policy's file renamed to the random policy's is not resumed as random's: its
    // episodes would be skipped as done and its rows read as zero's.
    std::fs::rename(&results, dir.path().join("results-random.jsonl")).unwrap();
    let resumed = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1", "--sample", "1"])
        .args(["--policy", "random", "--resume", "--quiet", "--clips", "none", "--builtin-look", "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(!resumed.status.success() && stderr.contains("holds completed episodes of the policy zero, not of random"), "{stderr}");
}

/// `--resume` without selection options continues the quick default, not the run the folder
/// holds: it says so, naming how many of the file's episodes lie outside.
#[test]
fn a_resume_outside_the_files_selection_says_what_it_continues() {
    let dir = tempfile::tempdir().unwrap();
    let vifo = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_vifo"))
            .args(["run", "--policy", "zero", "--quiet", "--builtin-look", "--clips", "none", "--out"])
            .arg(dir.path())
            .args(args)
            .output()
            .expect("run vifo")
    };
    let first = vifo(&["--suite", "libero_goal", "--protocol", "original", "--episodes", "1"]);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let resumed = vifo(&["--resume"]);
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{stderr}");
    // The quick default holds 2 of the 10 libero_goal tasks without a cue.
    assert!(stderr.contains("holds 8 episodes outside this selection") && stderr.contains("the quick default"), "{stderr}");
}

/// Scoring a predictions file none of whose ids is a question of the folder is an error, not
/// a table of zeros that reads as a model that got everything wrong.
#[test]
fn vqa_scores_of_no_matching_prediction_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let question = r#"{"id":"libero_spatial/0/F1/caption_bar/detection","instance_id":"libero_spatial/0/F1/caption_bar","family":"F1","stage":"detection","image":"images/x.png","question":"Which kind of visual cue appears in the image?","options":["a QR code","a hand","a banner","ghosts"],"answer":"C"}"#;
    std::fs::write(dir.path().join("questions.jsonl"), format!("{question}\n")).unwrap();
    let score = |predictions: &str| {
        let file = dir.path().join("predictions.jsonl");
        std::fs::write(&file, predictions).unwrap();
        Command::new(env!("CARGO_BIN_EXE_vifo")).args(["vqa", "score"]).arg(dir.path()).arg(&file).args(["--model", "m"]).output().expect("run vifo")
    };
    let out = score("{\"id\":\"libero_goal/1/F2/x/semantic\",\"prediction\":\"A\"}\n");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("none of its 1 predictions answers a question"), "{stderr}");
    let out = score("{\"id\":\"libero_spatial/0/F1/caption_bar/detection\",\"prediction\":\"C\"}\n");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

/// `vifo assets` says where the look's disk cache is and what it did: a second run reads what
/// the first made, and a cache folder that cannot be written is said, and costs nothing else.
#[test]
fn vifo_assets_says_what_the_looks_cache_did() {
    let tree = tempfile::tempdir().unwrap();
    let floor = tree.path().join("textures/light-gray-floor-tile.png");
    std::fs::create_dir_all(floor.parent().unwrap()).unwrap();
    // An asset tree (its marker folder) and a robot folder without meshes.
    std::fs::create_dir(tree.path().join("scenes")).unwrap();
    std::fs::create_dir_all(tree.path().join("robots/panda/meshes")).unwrap();
    std::fs::write(&floor, vifo_render::imageio::encode_png(&vifo_render::RgbImage::filled(4, 4, [90, 90, 90])).unwrap()).unwrap();
    let cache = tempfile::tempdir().unwrap();
    let assets = |cache: &std::path::Path| {
        let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
            .args(["assets", "--assets", tree.path().to_str().unwrap(), "--robot-assets", tree.path().to_str().unwrap()])
            .env("VIFO_LOOK_CACHE", cache)
            // Only this tree: no `VIFO_LIBERO_ASSETS`, and no `python3` to name installed wheels.
            .env_remove("VIFO_LIBERO_ASSETS")
            .env("PATH", "")
            .output()
            .expect("run vifo");
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
        stdout.lines().find(|l| l.starts_with("cache: ")).unwrap_or_else(|| panic!("no cache line: {stdout}")).to_string()
    };
    let made = assets(cache.path());
    assert!(made.contains(" (entries read from it: 0, made from the files: 1)") && made.contains(&cache.path().display().to_string()), "{made}");
    assert!(assets(cache.path()).contains(" (entries read from it: 1, made from the files: 0)"));
    let file = cache.path().join("a-file");
    std::fs::write(&file, b"x").unwrap();
    let refused = assets(&file);
    assert!(refused.contains("entries read from it: 0, made from the files: 1; not kept: cannot create") && refused.contains("a-file"), "{refused}");
}

/// A LeRobot policy server holds one client at a time: two workers would get each other's
/// action chunks (the scripted server refuses a timestep that goes back). `vifo run` sends such
/// a server one episode at a time, says so, and the episodes run without errors. Skips, saying
/// why, where `python3` lacks grpcio and numpy (`.ci/run` installs them).
#[test]
fn a_server_that_holds_one_client_gets_one_episode_at_a_time() {
    use std::io::{BufRead, BufReader};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let ready = Command::new("python3").args(["-c", "import grpc, numpy"]).output();
    if !ready.is_ok_and(|o| o.status.success()) {
        // Straight to stderr, which the harness does not capture, so a plain `cargo test` shows it.
        let why = "SKIPPED a_server_that_holds_one_client_gets_one_episode_at_a_time: python3 with grpcio and numpy is needed\n";
        let _ = std::io::Write::write_all(&mut std::io::stderr(), why.as_bytes());
        return;
    }
    let mut server = Command::new("python3")
        .arg(root.join("tests/python/format_servers.py"))
        .args(["lerobot", "--chunk", "10", "--lifetime", "600"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the scripted LeRobot server");
    let mut line = String::new();
    BufReader::new(server.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let port = line.strip_prefix("PORT ").map(str::trim).unwrap_or_else(|| panic!("server said {line:?}")).to_string();
    let dir = tempfile::tempdir().unwrap();
    let url = format!("grpc://127.0.0.1:{port}?policy_type=act&pretrained=stand-in&device=cpu");
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["run", "--builtin-look", "--quiet", "--suite", "libero_goal", "--protocol", "original", "--episodes", "1"])
        .args(["--sample", "2", "--threads", "2", "--model-profile", "molmoact2", "--policy", &url, "--out"])
        .arg(dir.path())
        .output()
        .expect("run vifo");
    let _ = server.kill();
    let mut log = String::new();
    let _ = std::io::Read::read_to_string(&mut server.stderr.take().unwrap(), &mut log);
    let _ = server.wait();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let said = format!("{stdout}{}\nserver: {log}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && stdout.contains("holds one client at a time: its episodes run on one worker"), "{said}");
    assert!(stdout.contains("2 run (0 errors)") && !log.contains("CHECK FAILED"), "{said}");
}

/// `vifo web episode` prints the state and frame hashes of the page's `Demo` run natively, the
/// figures the browser test compares with the page's.
#[test]
fn web_episode_prints_the_demos_hashes() {
    let (task, cue) = ("libero_goal/0", "libero_goal/0/F1/caption_bar");
    let out = Command::new(env!("CARGO_BIN_EXE_vifo"))
        .args(["web", "episode", "--task", task, "--cue", cue, "--size", "32", "--steps", "2", "--json"])
        .output()
        .expect("run vifo");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let mut demo = vifo_web::Demo::new(32, true).unwrap();
    demo.reset(task, 0, Some(cue), "authorized", None).unwrap();
    let status = (0..2).map(|_| demo.step().unwrap()).last().unwrap();
    assert_eq!(printed["steps"], 2);
    assert_eq!(printed["state_hash"], status.state_hash.as_str());
    assert_eq!(printed["frame_hash"], demo.frame_hash().unwrap().as_str());
}
