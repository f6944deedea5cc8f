//! The fuzz targets: each input format the benchmark reads from outside, with seeds (real
//! inputs: the project's own files, inputs made from the built-in tasks, and LIBERO's files
//! from `../shared` when present, read at run time) and a generator of new inputs in the
//! format's vocabulary.

use std::path::Path;

use rand::{Rng, RngExt};
use rmpv::Value as Mp;
use serde_json::{Value as Js, json};
use vifo_cues::instances::{InstanceSet, TaskDescription};
use vifo_protocols::remote::{ndarray, parse_reply};
use vifo_protocols::runner::{final_records, parse_records};
use vifo_protocols::scene_cues::tasks::describe;
use vifo_protocols::spec::{EpisodeRecord, Outcome, RESULTS_VERSION};
use vifo_protocols::vqa::client::chat_answer;
use vifo_protocols::vqa::extract::extract;
use vifo_scenes::Task;

/// What a target parses, which sets its gate.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A parser of short texts or messages: gate 1,000,000 cases.
    Parser,
    /// A decoder of whole files: gate 100,000 cases.
    File,
}

impl Kind {
    pub fn gate(self) -> u64 {
        match self {
            Kind::Parser => 1_000_000,
            Kind::File => 100_000,
        }
    }
}

pub struct Target {
    pub name: &'static str,
    pub kind: Kind,
    pub seeds: fn() -> Vec<Vec<u8>>,
    pub generate: fn(&mut dyn Rng) -> Vec<u8>,
    /// Tokens of the format, inserted by the mutator.
    pub dictionary: &'static [&'static [u8]],
    /// Feeds one input to the code under test and says whether it was accepted as valid; any
    /// result is fine, a panic or a hang is not.
    pub run: fn(&[u8]) -> bool,
}

pub const TARGETS: &[Target] = &[
    Target { name: "bddl", kind: Kind::Parser, seeds: bddl_seeds, generate: bddl_generate, dictionary: BDDL_WORDS, run: bddl_run },
    Target {
        name: "init-pickle",
        kind: Kind::File,
        seeds: pickle_seeds,
        generate: pickle_generate,
        dictionary: PICKLE_OPS,
        run: pickle_run,
    },
    Target { name: "init-json", kind: Kind::File, seeds: init_json_seeds, generate: init_json_generate, dictionary: JSON_TOKENS, run: init_json_run },
    Target { name: "task-json", kind: Kind::File, seeds: task_json_seeds, generate: task_json_generate, dictionary: JSON_TOKENS, run: task_json_run },
    Target {
        name: "cue-instances",
        kind: Kind::File,
        seeds: instances_seeds,
        generate: instances_generate,
        dictionary: JSON_TOKENS,
        run: instances_run,
    },
    Target { name: "cue-text", kind: Kind::Parser, seeds: text_seeds, generate: text_generate, dictionary: TEXT_WORDS, run: text_run },
    Target { name: "msgpack", kind: Kind::Parser, seeds: msgpack_seeds, generate: msgpack_generate, dictionary: MSGPACK_TOKENS, run: msgpack_run },
    Target { name: "results", kind: Kind::File, seeds: results_seeds, generate: results_generate, dictionary: JSON_TOKENS, run: results_run },
    Target { name: "vqa", kind: Kind::Parser, seeds: vqa_seeds, generate: vqa_generate, dictionary: VQA_WORDS, run: vqa_run },
    Target { name: "mesh-files", kind: Kind::File, seeds: mesh_seeds, generate: mesh_generate, dictionary: MESH_TOKENS, run: mesh_run },
    Target { name: "look-cache", kind: Kind::File, seeds: packed_seeds, generate: packed_generate, dictionary: PACKED_TOKENS, run: packed_run },
    Target {
        name: "served-replies",
        kind: Kind::Parser,
        seeds: served_seeds,
        generate: served_generate,
        dictionary: PICKLE_OPS,
        run: served_run,
    },
];

fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}

fn shared_files(dir: &str, ext: &str) -> Vec<Vec<u8>> {
    let root = vifo_tests::workspace_root().join("..").join("shared").join(dir);
    let mut out = Vec::new();
    let mut stack = vec![root];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        let mut paths: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths {
            if p.is_dir() {
                stack.push(p);
            } else if p.to_string_lossy().ends_with(ext)
                && let Ok(b) = std::fs::read(&p)
            {
                out.push(b);
            }
        }
    }
    out
}

fn pick<T: Copy>(rng: &mut dyn Rng, items: &[T]) -> T {
    items[rng.random_range(0..items.len())]
}

/// A number as a generator writes it: mostly ordinary, sometimes on an edge.
fn number(rng: &mut dyn Rng) -> String {
    match rng.random_range(0..8) {
        0 => pick(rng, &["0", "-0", "1e309", "-1e400", "NaN", "1e-320", "18446744073709551616", "-9223372036854775809"]).to_string(),
        1 => rng.random_range(0..100u32).to_string(),
        _ => format!("{:.3}", rng.random_range(-2.0..2.0)),
    }
}

// ---------------------------------------------------------------- BDDL

const BDDL_WORDS: &[&[u8]] = &[
    b"(define", b"(problem", b"(:domain robosuite)", b"(:language", b"(:regions", b"(:fixtures", b"(:objects",
    b"(:obj_of_interest", b"(:init", b"(:goal", b"(And", b"(Or", b"(Not", b"(On", b"(In", b"(Open", b"(Close",
    b"(Turnon", b"(Turnoff", b"(:target", b"(:ranges", b"(:yaw_rotation", b"(:rgba", b" - ", b"(", b")", b";",
    b"main_table", b"kitchen_table", b"_region", b"\n",
];

/// A BDDL text of a built-in task, in the language's general form.
fn bddl_of(task: &Task) -> String {
    let mut s = format!("(define (problem {})\n  (:domain robosuite)\n  (:language {})\n  (:regions\n", task.problem.name(), task.language);
    for r in &task.regions {
        s += &format!("    ({}\n      (:target {})\n", r.name, r.target);
        if !r.ranges.is_empty() {
            let ranges: Vec<String> = r.ranges.iter().map(|q| format!("({} {} {} {})", q[0], q[1], q[2], q[3])).collect();
            s += &format!("      (:ranges ({}))\n", ranges.join(" "));
        }
        if let Some([a, b]) = r.yaw_rotation {
            s += &format!("      (:yaw_rotation (({a} {b})))\n");
        }
        if let Some([r0, g, b, a]) = r.rgba {
            s += &format!("      (:rgba ({r0} {g} {b} {a}))\n");
        }
        s += "    )\n";
    }
    s += "  )\n  (:fixtures\n";
    for e in &task.fixtures {
        s += &format!("    {} - {}\n", e.name, e.category);
    }
    s += "  )\n  (:objects\n";
    for e in &task.objects {
        s += &format!("    {} - {}\n", e.name, e.category);
    }
    s += &format!("  )\n  (:obj_of_interest {})\n  (:init\n", task.obj_of_interest.join(" "));
    let atom = |a: &vifo_scenes::task::Atom| format!("({} {})", a.predicate, a.args.join(" "));
    for a in &task.init {
        s += &format!("    {}\n", atom(a));
    }
    let goal: Vec<String> = task.goal.iter().map(atom).collect();
    s += &format!("  )\n  (:goal (And {}))\n)\n", goal.join(" "));
    s
}

fn bddl_seeds() -> Vec<Vec<u8>> {
    let mut seeds: Vec<Vec<u8>> = vifo_scenes::all_tasks().map(|t| bddl_of(t).into_bytes()).collect();
    seeds.extend(shared_files("libero", ".bddl"));
    seeds
}

fn bddl_generate(rng: &mut dyn Rng) -> Vec<u8> {
    fn sexpr(rng: &mut dyn Rng, depth: usize, out: &mut String) {
        if depth == 0 || rng.random_range(0..3) == 0 {
            match rng.random_range(0..4) {
                0 => out.push_str(&number(rng)),
                1 => out.push_str(&text(pick(rng, BDDL_WORDS)).replace('(', "")),
                _ => out.push_str(pick(rng, &["bowl_1", "plate_1", "main_table", "flat_stove_1", "-", "kitchen_table_init_region", ":target"])),
            }
            return;
        }
        out.push('(');
        out.push_str(pick(rng, &[":regions", ":init", ":goal", "And", "On", "In", ":ranges", ":target", "define", "problem", ":objects", ":fixtures", ""]));
        for _ in 0..rng.random_range(0..5) {
            out.push(' ');
            sexpr(rng, depth - 1, out);
        }
        if rng.random_range(0..20) != 0 {
            out.push(')');
        }
    }
    let mut out = String::from("(define (problem LIBERO_Tabletop_Manipulation) (:domain robosuite) ");
    for _ in 0..rng.random_range(1..8) {
        sexpr(rng, 5, &mut out);
        out.push('\n');
    }
    out.push(')');
    out.into_bytes()
}

fn bddl_run(bytes: &[u8]) -> bool {
    vifo_scenes::bddl::parse(&text(bytes), Path::new("fuzz_case.bddl")).is_ok()
}

// ---------------------------------------------------------------- init-state pickles

const PICKLE_OPS: &[&[u8]] = &[
    b"\x80\x02", b"\x80\x04", b"cnumpy.core.multiarray\n_reconstruct\n", b"cnumpy\nndarray\n", b"cnumpy\ndtype\n",
    b"K\x00", b"K\x32", b"J\xff\xff\xff\xff", b"M\xff\xff", b"X\x02\x00\x00\x00f8", b"X\x01\x00\x00\x00<", b"C\x01b",
    b"B\xff\xff\xff\x7f", b"(", b"t", b"\x85", b"\x86", b"\x87", b"R", b"b", b"N", b"\x88", b"\x89", b"\x93", b"\x94",
    b"q\x00", b"h\x00", b"]", b"e", b"}", b"s", b".", b"\x95\x00\x00\x00\x00\x00\x00\x00\x00", b"PK\x03\x04", b"PK\x05\x06",
    b"data.pkl",
];

/// Inputs of this target start with a mode byte: odd, the rest is a pickle, wrapped in a
/// valid archive before reading (so mutations reach the pickle reader instead of failing the
/// archive's checksum); even, the rest is the file as is (the archive reader).
fn pickle_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for file in shared_files("libero", ".pruned_init") {
        if let Some(pickle) = stored_entry(&file) {
            seeds.push([&[1], pickle].concat());
        }
        seeds.push([&[0], &file[..]].concat());
    }
    // Without LIBERO's files: generated inputs only.
    let mut rng = rand_pcg::Pcg64::new(1, 1);
    seeds.extend((0..4).map(|_| pickle_generate(&mut rng)));
    seeds
}

/// The data of the first entry of a zip archive when it is stored uncompressed (as
/// `torch.save` writes `data.pkl`; its size is in the central directory, since torch streams
/// the entry with a data descriptor).
fn stored_entry(zip: &[u8]) -> Option<&[u8]> {
    let u16_at = |i: usize| Some(u16::from_le_bytes(zip.get(i..i + 2)?.try_into().ok()?) as usize);
    let u32_at = |i: usize| Some(u32::from_le_bytes(zip.get(i..i + 4)?.try_into().ok()?) as usize);
    let end = zip.windows(4).rposition(|w| w == b"PK\x05\x06")?;
    let central = u32_at(end + 16)?;
    if zip.get(central..central + 4)? != b"PK\x01\x02" || u16_at(central + 10)? != 0 {
        return None;
    }
    let (size, local) = (u32_at(central + 20)?, u32_at(central + 42)?);
    let start = local + 30 + u16_at(local + 26)? + u16_at(local + 28)?;
    zip.get(start..start + size)
}

fn pickle_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let mut pickle = vec![1];
    for _ in 0..rng.random_range(1..40) {
        pickle.extend_from_slice(pick(rng, PICKLE_OPS));
    }
    if rng.random_range(0..2) == 0 {
        // The tail of a real array pickle: raw float64 bytes, then STOP.
        let n = rng.random_range(0..64) * 8;
        pickle.extend((0..n).map(|_| rng.random_range(0..=255u8)));
        pickle.push(b'.');
    }
    pickle
}

/// A one-entry zip archive with the entry stored (as `torch.save` writes them).
fn stored_zip(name: &str, data: &[u8]) -> Vec<u8> {
    let crc = crc32(data);
    let (n, len) = (name.len() as u16, data.len() as u32);
    let mut z = Vec::new();
    let header = |z: &mut Vec<u8>, central: bool| {
        z.extend_from_slice(if central { b"PK\x01\x02\x14\x00" } else { b"PK\x03\x04" });
        z.extend_from_slice(&[0x14, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
        z.extend_from_slice(&crc.to_le_bytes());
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&n.to_le_bytes());
        z.extend_from_slice(&0u16.to_le_bytes());
        if central {
            // Comment length, disk, internal and external attributes, then the local header's offset.
            z.extend_from_slice(&[0; 10]);
            z.extend_from_slice(&0u32.to_le_bytes());
        }
        z.extend_from_slice(name.as_bytes());
    };
    header(&mut z, false);
    z.extend_from_slice(data);
    let central_at = z.len() as u32;
    header(&mut z, true);
    let central_len = z.len() as u32 - central_at;
    z.extend_from_slice(b"PK\x05\x06\0\0\0\0\x01\0\x01\0");
    z.extend_from_slice(&central_len.to_le_bytes());
    z.extend_from_slice(&central_at.to_le_bytes());
    z.extend_from_slice(&0u16.to_le_bytes());
    z
}

fn crc32(data: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in data {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 != 0 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

fn pickle_run(bytes: &[u8]) -> bool {
    let Some((&mode, rest)) = bytes.split_first() else { return false };
    let file = if mode % 2 == 1 { stored_zip("archive/data.pkl", rest) } else { rest.to_vec() };
    vifo_scenes::init_file::read(&file, "fuzz_case.pruned_init").is_ok()
}

// ---------------------------------------------------------------- JSON inputs

const JSON_TOKENS: &[&[u8]] = &[
    b"{", b"}", b"[", b"]", b",", b":", b"\"", b"null", b"true", b"false", b"\\u0000", b"\\ud800", b"[[[[[[[[", b"\"index\"",
    b"\"name\"", b"\"states\"", b"\"spec\"", b"\"outcome\"", b"\"status\"", b"\"instances\"", b"\"instruction\"",
];

/// A random JSON value whose object keys come mostly from `keys`.
fn json_value(rng: &mut dyn Rng, depth: usize, keys: &[&str]) -> Js {
    let leaf = depth == 0 || rng.random_range(0..3) == 0;
    match rng.random_range(0..if leaf { 4 } else { 6 }) {
        0 => Js::Null,
        1 => serde_json::from_str(&number(rng)).unwrap_or(Js::from(rng.random_range(-5i64..5))),
        2 => Js::from(pick(rng, &["", "libero_goal", "libero_goal/3", "F2", "completed", "error", "original", "On", "put the bowl on the plate"]).to_string()),
        3 => Js::Bool(rng.random_range(0..2) == 0),
        4 => Js::Array((0..rng.random_range(0..6)).map(|_| json_value(rng, depth - 1, keys)).collect()),
        _ => {
            let mut map = serde_json::Map::new();
            for _ in 0..rng.random_range(0..8) {
                let key = if rng.random_range(0..6) == 0 { "unexpected".to_string() } else { pick(rng, keys).to_string() };
                map.insert(key, json_value(rng, depth - 1, keys));
            }
            Js::Object(map)
        }
    }
}

fn read_workspace(dir: &str) -> Vec<Vec<u8>> {
    let root = vifo_tests::workspace_root().join(dir);
    let mut paths: Vec<_> = std::fs::read_dir(&root).map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect()).unwrap_or_default();
    paths.sort();
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

const INIT_KEYS: &[&str] = &["format", "suite", "tasks", "index", "name", "objects", "joints", "fixtures", "states", "arm", "gripper"];

fn init_json_seeds() -> Vec<Vec<u8>> {
    let files = read_workspace("scenes/init_states");
    // Each task alone as a small file too, so most mutations land in a file parsed quickly.
    let mut seeds = Vec::new();
    for f in &files {
        let Ok(suite) = vifo_scenes::init_states::parse(&text(f), "seed") else { continue };
        for task in &suite.tasks {
            let one = vifo_scenes::init_states::SuiteStates { suite: suite.suite.clone(), tasks: vec![task.clone()] };
            seeds.push(vifo_scenes::init_states::write(&one).into_bytes());
        }
    }
    seeds.extend(files);
    seeds
}

fn init_json_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let mut v = json_value(rng, 6, INIT_KEYS);
    if rng.random_range(0..2) == 0 {
        v = json!({"format": vifo_scenes::init_states::FORMAT, "suite": "libero_goal", "tasks": [v]});
    }
    v.to_string().into_bytes()
}

fn init_json_run(bytes: &[u8]) -> bool {
    vifo_scenes::init_states::parse(&text(bytes), "fuzz_case.json").is_ok()
}

const TASK_KEYS: &[&str] = &[
    "suite", "index", "instruction", "goals", "objects", "fixtures", "predicate", "args", "name", "language", "problem", "regions",
    "obj_of_interest", "init", "goal", "key", "target", "ranges", "yaw_rotation", "rgba", "category", "max_steps", "tasks",
];

fn task_json_seeds() -> Vec<Vec<u8>> {
    let tasks: Vec<TaskDescription> = vifo_scenes::all_tasks().map(describe).collect();
    let mut seeds = vec![serde_json::to_vec(&tasks).expect("task descriptions serialize")];
    seeds.extend(tasks.chunks(4).map(|c| serde_json::to_vec(c).expect("serialize")));
    seeds.extend(vifo_scenes::all_tasks().map(|t| serde_json::to_vec(t).expect("tasks serialize")));
    seeds.extend(read_workspace("scenes/tasks"));
    seeds
}

fn task_json_generate(rng: &mut dyn Rng) -> Vec<u8> {
    json_value(rng, 6, TASK_KEYS).to_string().into_bytes()
}

/// The three task forms read from JSON: `vifo cues instances` task lists (built into an
/// instance set), tasks and suites.
fn task_json_run(bytes: &[u8]) -> bool {
    let list = serde_json::from_slice::<Vec<TaskDescription>>(bytes).is_ok_and(|tasks| InstanceSet::build(&tasks).is_ok());
    let task = serde_json::from_slice::<Task>(bytes).is_ok();
    let suite = serde_json::from_slice::<vifo_scenes::Suite>(bytes).is_ok();
    list || task || suite
}

const CUE_KEYS: &[&str] = &[
    "instances", "task", "family", "variant", "step", "source", "target", "relation", "color", "text", "instruction", "qualifier",
    "source_id", "target_id", "params", "style",
];

fn instances_seeds() -> Vec<Vec<u8>> {
    let set = vifo_protocols::scene_cues::builtin_instances().expect("built-in instance set");
    set.instances
        .chunks(40)
        .map(|c| serde_json::to_vec(&InstanceSet { instances: c.to_vec() }).expect("serialize"))
        .collect()
}

fn instances_generate(rng: &mut dyn Rng) -> Vec<u8> {
    json!({"instances": [json_value(rng, 5, CUE_KEYS), json_value(rng, 5, CUE_KEYS)]}).to_string().into_bytes()
}

fn instances_run(bytes: &[u8]) -> bool {
    let Ok(set) = serde_json::from_slice::<InstanceSet>(bytes) else { return false };
    for spec in &set.instances {
        let _ = spec.id();
    }
    let _ = set.composition();
    true
}

// ---------------------------------------------------------------- cue instruction text

const TEXT_WORDS: &[&[u8]] = &[
    b"put", b"the", b"on", b"in", b"into", b"and", b"then", b"open", b"close", b"turn on", b"turn off", b"pick up", b"place",
    b"push", b"to the front of", b"of the", b"top", b"middle", b"bottom", b"drawer", b"cabinet", b"bowl", b"plate", b"stove",
    b"basket", b"it", b"both", b"left", b"right", b"next to", b"between", b"  ", b",", b".",
];

fn text_seeds() -> Vec<Vec<u8>> {
    vifo_scenes::all_tasks().map(|t| t.instruction.clone().into_bytes()).collect()
}

fn text_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let mut out = Vec::new();
    for i in 0..rng.random_range(0..16) {
        if i > 0 {
            out.push(b' ');
        }
        out.extend_from_slice(pick(rng, TEXT_WORDS));
    }
    out
}

fn text_run(bytes: &[u8]) -> bool {
    vifo_cues::parse(&text(bytes)).is_ok()
}

// ---------------------------------------------------------------- msgpack / openpi replies

const MSGPACK_TOKENS: &[&[u8]] = &[
    b"\xc4\x0b__ndarray__", b"\xc4\x04data", b"\xc4\x05dtype", b"\xc4\x05shape", b"\xa7actions", b"\xa3<f4", b"\xa3<f8",
    b"\xa3|u1", b"\xa3>f8", b"\xa3<i8", b"\x92\x05\x07", b"\x92\x00\x07", b"\x93\x01\x07\x01", b"\xc3", b"\xc2", b"\xc0",
    b"\x81", b"\x84", b"\xde\xff\xff", b"\xdc\xff\xff", b"\xc5\xff\xff", b"\xcf\xff\xff\xff\xff\xff\xff\xff\xff",
];

fn reply(entries: Vec<(Mp, Mp)>) -> Vec<u8> {
    let mut b = Vec::new();
    rmpv::encode::write_value(&mut b, &Mp::Map(entries)).expect("encode to memory");
    b
}

fn msgpack_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for (dtype, width) in [("<f4", 4), ("<f8", 8)] {
        for h in [1, 5, 10, 50] {
            let data: Vec<u8> = (0..h * 7 * width).map(|i| (i * 37 % 251) as u8).collect();
            seeds.push(reply(vec![
                (Mp::from("actions"), ndarray::encode(dtype, &[h, 7], data)),
                (Mp::from("policy_timing"), Mp::Map(vec![(Mp::from("infer_ms"), Mp::F64(12.5))])),
            ]));
        }
    }
    seeds.push(reply(vec![]));
    seeds
}

fn msgpack_value(rng: &mut dyn Rng, depth: usize) -> Mp {
    let leaf = depth == 0 || rng.random_range(0..3) == 0;
    match rng.random_range(0..if leaf { 5 } else { 8 }) {
        0 => Mp::Nil,
        1 => Mp::from(rng.random_range(-3i64..100)),
        2 => Mp::F64(pick(rng, &[0.0, -0.0, f64::NAN, f64::INFINITY, 1e300, 0.5])),
        3 => Mp::from(pick(rng, &["actions", "<f4", "<f8", "|u1", ">f8", "<c16", "O", ""])),
        4 => Mp::Binary((0..rng.random_range(0..64)).map(|_| rng.random_range(0..=255u8)).collect()),
        5 => Mp::Array((0..rng.random_range(0..5)).map(|_| msgpack_value(rng, depth - 1)).collect()),
        6 => {
            let dims: Vec<usize> = (0..rng.random_range(0..4)).map(|_| pick(rng, &[0, 1, 5, 7, 8, usize::MAX / 2])).collect();
            let n = rng.random_range(0..300);
            ndarray::encode(pick(rng, &["<f4", "<f8", "|u1", ">f8", "<i4", "<f2"]), &dims, (0..n).map(|_| rng.random_range(0..=255u8)).collect())
        }
        _ => Mp::Map((0..rng.random_range(0..5)).map(|_| (msgpack_value(rng, 0), msgpack_value(rng, depth - 1))).collect()),
    }
}

fn msgpack_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let mut entries = vec![(Mp::from("actions"), msgpack_value(rng, 3))];
    for _ in 0..rng.random_range(0..3) {
        entries.push((msgpack_value(rng, 0), msgpack_value(rng, 2)));
    }
    reply(entries)
}

/// A reply as the openpi client reads it, and the same bytes as a metadata message.
fn msgpack_run(bytes: &[u8]) -> bool {
    let _ = rmpv::decode::read_value(&mut &bytes[..]);
    parse_reply(bytes).is_ok()
}

// ---------------------------------------------------------------- results files

const RECORD_KEYS: &[&str] = &[
    "version", "set", "spec", "policy", "outcome", "wall_ms", "look", "task", "suite", "index", "protocol", "instance", "init", "episode",
    "instruction", "language_task", "cue_task", "seed", "status", "language_success", "cue_success", "steps", "message",
];

fn results_seeds() -> Vec<Vec<u8>> {
    let specs = vifo_protocols::benchmark::specs::specs(&vifo_protocols::benchmark::specs::Selection::quick()).expect("quick selection");
    let record = |i: usize, spec: &vifo_protocols::EpisodeSpec| EpisodeRecord {
        version: RESULTS_VERSION,
        set: vifo_cues::SetName::Full,
        spec: spec.clone(),
        policy: "zero".into(),
        outcome: if i % 5 == 4 {
            Outcome::Error { message: "policy zero: connection dropped".into() }
        } else {
            Outcome::Completed { language_success: Some(i.is_multiple_of(2)), cue_success: None, steps: 220 + i }
        },
        wall_ms: 10.0 * i as f64,
        look: String::new(),
    };
    let lines: Vec<Vec<u8>> = specs.iter().enumerate().map(|(i, s)| serde_json::to_vec(&record(i, s)).expect("serialize")).collect();
    lines.chunks(8).map(|c| c.iter().flat_map(|l| l.iter().copied().chain([b'\n'])).collect()).collect()
}

fn results_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let mut out = Vec::new();
    for _ in 0..rng.random_range(0..6) {
        out.extend(json_value(rng, 4, RECORD_KEYS).to_string().into_bytes());
        out.push(b'\n');
    }
    out
}

fn results_run(bytes: &[u8]) -> bool {
    let Ok(loaded) = parse_records(bytes, Path::new("fuzz_case.jsonl")) else { return false };
    let _ = final_records(loaded.records);
    true
}

// ---------------------------------------------------------------- VQA replies

const VQA_WORDS: &[&[u8]] = &[
    b"A", b"B", b"C", b"D", b"Z", b"(A)", b"<think>", b"</think>", b"Answer:", b"\"content\"", b"\"choices\"", b"\"message\"",
    b"null", b"Cannot determine the answer", b"Failed to obtain answer via API", b"\\n", b"\\u00e9",
];

fn completion(content: Js) -> Vec<u8> {
    json!({"id": "x", "object": "chat.completion", "choices": [{"index": 0, "message": {"role": "assistant", "content": content}}]})
        .to_string()
        .into_bytes()
}

fn vqa_seeds() -> Vec<Vec<u8>> {
    ["A", "The answer is (B).", "<think>maybe A or B</think>C", "Cannot determine the answer", "the red bowl", ""]
        .into_iter()
        .map(|a| completion(Js::from(a)))
        .chain([completion(Js::Null), b"{\"choices\": []}".to_vec()])
        .collect()
}

fn vqa_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let words: Vec<String> = (0..rng.random_range(0..10)).map(|_| text(pick(rng, VQA_WORDS)).into_owned()).collect();
    if rng.random_range(0..4) == 0 {
        return json_value(rng, 5, &["choices", "message", "content", "role", "index"]).to_string().into_bytes();
    }
    completion(Js::from(words.join(" ")))
}

const OPTIONS: [&str; 4] = ["the red bowl", "the plate", "A", "put the bowl on the plate"];

/// The body as the client reads it, then the answer as the scorer extracts it (and the body
/// itself as a raw answer, since the extractor sees whatever the model wrote).
fn vqa_run(bytes: &[u8]) -> bool {
    let options: Vec<String> = OPTIONS.iter().map(|s| s.to_string()).collect();
    let body = text(bytes);
    let _ = extract(&body, &options);
    let Ok(answer) = chat_answer(&body) else { return false };
    let _ = extract(&answer, &options);
    true
}

// ---------------------------------------------------------------- replies of served models

/// A random pickle built from the objects the serving clients meet: arrays, dicts, lists,
/// objects, strings, numbers (with shapes and sizes that do not fit).
fn served_pickle(rng: &mut dyn Rng) -> Vec<u8> {
    use vifo_protocols::serving::pickle::Writer;
    fn value(rng: &mut dyn Rng, w: &mut Writer, depth: usize) {
        match rng.random_range(0..if depth == 0 { 5 } else { 8 }) {
            0 => w.int(rng.random_range(-3i64..1 << 40)),
            1 => w.float(pick(rng, &[0.0, f64::NAN, f64::INFINITY, 0.5])),
            2 => w.str(pick(rng, &["action", "timestep", "actions", "<f4", ""])),
            3 => w.none(),
            4 => {
                let dims: Vec<usize> = (0..rng.random_range(0..4)).map(|_| pick(rng, &[0, 1, 7, 8, 10])).collect();
                let n = rng.random_range(0..400);
                let data: Vec<u8> = (0..n).map(|_| rng.random_range(0..=255u8)).collect();
                w.ndarray(pick(rng, &["<f4", "<f8", "|u1", ">f8", "<f2"]), &dims, &data);
            }
            5 => {
                w.begin_list();
                for _ in 0..rng.random_range(0..4) {
                    value(rng, w, depth - 1);
                }
                w.end_list();
            }
            6 => {
                w.begin_dict();
                for _ in 0..rng.random_range(0..4) {
                    w.str(pick(rng, &["action", "timestep", "timestamp", "x"]));
                    value(rng, w, depth - 1);
                }
                w.end_dict();
            }
            _ => {
                w.global(pick(rng, &["lerobot.async_inference.helpers", "torch._utils"]), "TimedAction");
                w.empty_tuple();
                w.newobj();
                value(rng, w, depth - 1);
                w.build();
            }
        }
    }
    let mut w = Writer::default();
    value(rng, &mut w, 3);
    w.finish()
}

fn served_seeds() -> Vec<Vec<u8>> {
    use vifo_protocols::serving::pickle::Writer;
    let mut rng = rand_pcg::Pcg64::new(3, 3);
    let mut seeds: Vec<Vec<u8>> = (0..8).map(|_| served_pickle(&mut rng)).collect();
    // One valid reply of each format, so that mutations start from inputs the parsers accept.
    let row = |i: usize| -> Vec<u8> { (0..8).flat_map(|j| ((i * 8 + j) as f32 * 0.01).to_le_bytes()).collect() };
    let mut xiaomi = Writer::default();
    xiaomi.ndarray("<f4", &[1, 2, 8], &[row(0), row(1)].concat());
    seeds.push(xiaomi.finish());
    let mut lerobot = Writer::default();
    lerobot.begin_list();
    for t in 0..2 {
        lerobot.global("lerobot.async_inference.helpers", "TimedAction");
        lerobot.empty_tuple();
        lerobot.newobj();
        lerobot.begin_dict();
        lerobot.str("timestamp");
        lerobot.float(0.5);
        lerobot.str("timestep");
        lerobot.int(t);
        lerobot.str("action");
        lerobot.ndarray("<f4", &[7], &row(t as usize)[..28]);
        lerobot.end_dict();
        lerobot.build();
    }
    lerobot.end_list();
    seeds.push(lerobot.finish());
    let actions = ndarray::encode("<f4", &[1, 2, 7], [&row(0)[..28], &row(1)[..28]].concat());
    seeds.push(reply(vec![
        (Mp::from("ok"), Mp::Boolean(true)),
        (Mp::from("data"), Mp::Map(vec![(Mp::from("actions"), actions)])),
    ]));
    seeds.push(b"[[0.1, 0.0, -0.2, 0.0, 0.0, 0.05, -1.0], [0.1, 0.0, -0.2, 0.0, 0.0, 0.05, 1.0]]".to_vec());
    seeds.push(br#"[{"__numpy__": "AAAAAAAAAAA=", "dtype": "<f4", "shape": [2]}]"#.to_vec());
    seeds.push(b"\"error\"".to_vec());
    seeds
}

fn served_generate(rng: &mut dyn Rng) -> Vec<u8> {
    served_pickle(rng)
}

/// The reply parsers of every served format, and the pickle reader under them.
fn served_run(bytes: &[u8]) -> bool {
    use vifo_protocols::serving::{internvla, lerobot, openvla_oft, pickle, xiaomi};
    let pickled = pickle::read_all(bytes).is_ok_and(|v| pickle::tensor(&v).is_ok());
    let xiaomi = xiaomi::parse(bytes).is_ok();
    let lerobot = lerobot::parse(bytes, 0).is_ok();
    let internvla = internvla::parse(bytes).is_ok();
    let oft = openvla_oft::parse(&text(bytes)).is_ok();
    pickled || xiaomi || lerobot || internvla || oft
}

// Mesh files of LIBERO's look (`.msh`, `.obj`, `.stl`): a damaged one must give an error naming
// it, never a panic or a giant allocation.

const MESH_TOKENS: &[&[u8]] = &[
    b"v ", b"vt ", b"vn ", b"f ", b"/", b"//", b" -1", b" 0", b" 4294967295", b" 1e38", b" nan", b" inf", b"\n", b"o ", b"g ", b"mtllib x\n",
    b"solid ", b"facet normal ", b"outer loop\n", b"vertex ", b"endloop\n", b"endfacet\n", b"endsolid",
    b"\xff\xff\xff\x7f", b"\x00\x00\x00\x80", b"\x00\x00\xc0\x7f", b"\x03\x00\x00\x00", b"\x01\x00\x00\x00",
];

/// The smallest few mesh files of each format in `../shared` (when present), and generated ones.
fn mesh_seeds() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for ext in [".msh", ".obj", ".stl"] {
        let mut files: Vec<Vec<u8>> = shared_files("libero", ext).into_iter().filter(|f| f.len() <= 64 * 1024).collect();
        files.sort_by_key(Vec::len);
        seeds.extend(files.into_iter().take(4));
    }
    let mut rng = rand_pcg::Pcg64::new(5, 5);
    seeds.extend((0..6).map(|_| mesh_generate(&mut rng)));
    seeds
}

/// A small mesh in one of the three formats: a few triangles with indices that may point past
/// the vertices, and counts that may disagree with the data.
fn mesh_generate(rng: &mut dyn Rng) -> Vec<u8> {
    let (nv, nf) = (rng.random_range(0..8u32), rng.random_range(0..6u32));
    let coord = |rng: &mut dyn Rng| [0.0f32, 1.0, -0.5, 1e30, f32::NAN][rng.random_range(0..5)];
    let index = |rng: &mut dyn Rng| rng.random_range(0..nv + 2);
    match rng.random_range(0..4) {
        0 => {
            let mut out = Vec::new();
            let claimed = |rng: &mut dyn Rng, n: u32| if rng.random_range(0..4) == 0 { rng.random_range(0..=u32::MAX) } else { n };
            for n in [nv, if rng.random_range(0..2) == 0 { nv } else { 0 }, 0, nf] {
                out.extend(claimed(rng, n).to_le_bytes());
            }
            for _ in 0..3 * nv {
                out.extend(coord(rng).to_le_bytes());
            }
            for _ in 0..3 * nf {
                out.extend(index(rng).to_le_bytes());
            }
            out
        }
        1 => {
            let mut out = String::new();
            for _ in 0..nv {
                out += &format!("v {} {} {}\n", coord(rng), coord(rng), coord(rng));
            }
            for _ in 0..nf {
                let corners = rng.random_range(2..6);
                out += "f";
                for _ in 0..corners {
                    out += &format!(" {}", index(rng) as i64 - 1);
                }
                out += "\n";
            }
            out.into_bytes()
        }
        2 => {
            let mut out = String::from("solid fuzz\n");
            for _ in 0..nf {
                out += "facet normal 0 0 1\nouter loop\n";
                for _ in 0..3 {
                    out += &format!("vertex {} {} {}\n", coord(rng), coord(rng), coord(rng));
                }
                out += "endloop\nendfacet\n";
            }
            (out + "endsolid fuzz\n").into_bytes()
        }
        _ => {
            let mut out = vec![0u8; 80];
            out.extend(nf.to_le_bytes());
            for _ in 0..nf {
                for _ in 0..12 {
                    out.extend(coord(rng).to_le_bytes());
                }
                out.extend([0, 0]);
            }
            out
        }
    }
}

/// The three mesh readers the look uses, on the same bytes.
fn mesh_run(bytes: &[u8]) -> bool {
    use vifo_render::assets::{parse_msh, parse_obj, parse_stl};
    let msh = parse_msh(bytes, "fuzz.msh").is_ok();
    let obj = parse_obj(bytes, "fuzz.obj").is_ok();
    let stl = parse_stl(bytes, "fuzz.stl").is_ok();
    msh || obj || stl
}

// ---------------------------------------------------------------- the look's cache entries

const PACKED_TOKENS: &[&[u8]] = &[
    b"\0\0\0\0", b"\x01\0\0\0", b"\xff\xff\xff\xff", b"\0\0\xc0\x7f", b"\0\0\x80\x7f", b"\0\0\0\0\0\0\0\0",
    b"\x03\0\0\0\0\0\0\0", b"\xff\xff\xff\xff\xff\xff\xff\x7f",
];

/// Packed meshes and textures as the look's cache keeps them: procedural meshes, clustered and
/// simplified ones, small textures.
fn packed_seeds() -> Vec<Vec<u8>> {
    use vifo_render::pack::Packer;
    use vifo_render::{Mesh, Texture};
    let sphere = Mesh::sphere(0.05, 12).clustered();
    let coarse = Mesh::sphere(0.05, 24).clustered().simplified(0.004).expect("a 24-segment sphere simplifies at 4 mm");
    let mut seeds: Vec<Vec<u8>> = [Mesh::cuboid(vifo_render::glam::Vec3::splat(0.1)), Mesh::sphere(0.05, 6), sphere, coarse]
        .iter()
        .map(|m| {
            let mut p = Packer::new();
            p.mesh(m);
            p.finish()
        })
        .collect();
    for (w, h) in [(1, 1), (3, 2)] {
        let mut p = Packer::new();
        p.texture(&Texture::from_rgba8(w, h, &vec![7; (w * h * 4) as usize]).expect("a valid size"));
        seeds.push(p.finish());
    }
    seeds
}

/// A small packed mesh (or texture) whose lengths, indices and values may disagree.
fn packed_generate(rng: &mut dyn Rng) -> Vec<u8> {
    use vifo_render::pack::Packer;
    fn coord(rng: &mut dyn Rng) -> f32 {
        [0.0f32, 1.0, -0.5, 1e30, f32::NAN][rng.random_range(0..5)]
    }
    fn v3s(rng: &mut dyn Rng, n: usize) -> Vec<[f32; 3]> {
        (0..n).map(|_| [coord(rng), coord(rng), coord(rng)]).collect()
    }
    fn words<const N: usize>(rng: &mut dyn Rng, n: usize, below: u32) -> Vec<[u32; N]> {
        (0..n).map(|_| std::array::from_fn(|_| rng.random_range(0..below.max(1)))).collect()
    }
    let mut p = Packer::new();
    let n = rng.random_range(0..6usize);
    let near = |rng: &mut dyn Rng| if rng.random_range(0..4) == 0 { n + 1 } else { n };
    if rng.random_range(0..4) == 0 {
        let (w, h) = (rng.random_range(0..4u32), rng.random_range(0..4u32));
        p.u32(w);
        p.u32(h);
        p.u32(rng.random_range(0..3));
        let texels = (w * h) as usize + rng.random_range(0..2);
        p.slice(&words::<1>(rng, texels, 256));
        return p.finish();
    }
    let tris = rng.random_range(0..5usize);
    let (v, nv) = (v3s(rng, n), near(rng));
    p.slice(&v);
    p.slice(&v3s(rng, nv));
    p.u32(rng.random_range(0..2));
    let nu = near(rng);
    p.slice(&(0..nu).map(|_| [coord(rng), coord(rng)]).collect::<Vec<_>>());
    p.slice(&words::<3>(rng, tris, n as u32 + 1));
    let np = near(rng);
    p.slice(&v3s(rng, np));
    let of_vertex = near(rng);
    p.slice(&words::<1>(rng, of_vertex, np as u32 + 1));
    p.slice(&words::<3>(rng, tris, np as u32 + 1));
    let clusters = rng.random_range(0..3);
    p.slice(&words::<15>(rng, clusters, (tris + 2) as u32));
    let (points, order) = (near(rng), near(rng));
    p.slice(&words::<1>(rng, points, np as u32 + 1));
    p.slice(&words::<1>(rng, order, n as u32 + 1));
    p.finish()
}

/// Reads the bytes as a packed mesh and as a packed texture; an accepted mesh is drawn, so a
/// mesh that passes the checks but would break the rasterizer is found too.
fn packed_run(bytes: &[u8]) -> bool {
    use vifo_render::pack::Unpacker;
    use vifo_render::{Camera, Instance, Renderer, Scene, Transform};
    let mut u = Unpacker::new(bytes);
    let mesh = u.mesh().ok().filter(|_| u.finish().is_ok());
    let mut t = Unpacker::new(bytes);
    let texture = t.texture().is_ok() && t.finish().is_ok();
    if let Some(mesh) = &mesh {
        let scene = Scene { instances: vec![Instance::new(std::sync::Arc::new(mesh.clone()), Transform::IDENTITY, 1)], ..Scene::default() };
        let eye = vifo_render::glam::Vec3::new(0.3, -0.2, 0.4);
        let _ = Renderer::default().render(&scene, &Camera::look_at(eye, vifo_render::glam::Vec3::ZERO, vifo_render::glam::Vec3::Z, 45.0, 16, 16));
    }
    mesh.is_some() || texture
}
