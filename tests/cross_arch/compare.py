#!/usr/bin/env python3
"""Same results on another CPU architecture: runs the same `vifo` commands with two builds and
compares what they print and write, byte for byte.

The second build is usually an aarch64 one run under qemu-user (as .ci/run does):

  compare.py --vifo target/fast/vifo \\
      --other "qemu-aarch64 -L /usr/aarch64-linux-gnu target/aarch64-unknown-linux-gnu/fast/vifo"

What is compared:
  1. episodes (`vifo web episode --json`, the built-in look): the browser test's instances (every
     cue family, the four suites, the language conditions) run by the expert, plus a random-action
     and a language-only episode: final state hash, steps, predicates and the hash of both
     cameras' last frames with the cue drawn;
  2. a benchmark run (`vifo run`, libero_goal, every protocol, one instance per family): the
     results files without their wall times, the report's tables, charts and clips;
  3. LIBERO's look, where its assets are installed: each build loads them into its own empty
     look cache (so the mesh simplifier and texture downsizing run on both), then renders an
     expert rollout of libero_spatial/0 through both cameras; every frame's PNG is compared.

Prints one line per comparison and a `CROSS-ARCH` summary; exits non-zero when anything differs.
"""

import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "web"))
from browser_test import HASHED, PLAYED, SWEEP, SWEEP_STEPS  # noqa: E402

# (task, cue, condition, policy, steps): the browser test's episodes, then two that reach parts
# of the code the expert does not (seeded random actions, the original language-only protocol).
EPISODES = (
    [(task, cue, condition, "expert-cue", None) for task, cue, condition in [PLAYED] + HASHED]
    + [(task, cue, condition, "expert-cue", SWEEP_STEPS) for task, cue, condition in SWEEP]
    + [("libero_object/3", "libero_object/3/F1/caption_bar", "authorized", "random", 60),
       ("libero_spatial/4", None, "original", "expert-language", None)]
)
RUN_ARGS = ["run", "--suite", "libero_goal", "--protocol", "all", "--per-family", "1", "--episodes", "1",
            "--policy", "expert-cue", "--threads", "2", "--quiet", "--builtin-look"]
LOOK_TASK, LOOK_STEPS = "libero_spatial/0", 12


class Builds:
    def __init__(self, reference, other, work):
        self.commands = {"reference": reference, "other": other}
        self.work = work
        self.checked = 0
        self.differences = []

    def run(self, which, args, env=None, cwd=None):
        """stdout of `vifo args` with build `which`; a failure is reported with its stderr."""
        proc = subprocess.run(self.commands[which] + args, capture_output=True, text=True, env=env, cwd=cwd)
        if proc.returncode != 0:
            raise SystemExit(f"{which} build failed: {' '.join(args)}\n{proc.stderr.strip()}")
        return proc.stdout

    def both(self, args, env_for=None):
        """Runs `args` with both builds, each in its own folder under the work folder."""
        outs = {}
        for which in self.commands:
            folder = self.work / which
            folder.mkdir(parents=True, exist_ok=True)
            env = env_for(which) if env_for else None
            outs[which] = self.run(which, args, env=env, cwd=folder)
        return outs

    def compare(self, what, reference, other):
        self.checked += 1
        same = reference == other
        if not same:
            self.differences.append(what)
        print(f"  {what}: {'equal' if same else 'DIFFERENT'}", flush=True)
        return same


def episodes(builds):
    print(f"episodes ({len(EPISODES)}, `vifo web episode`, built-in look, 128²):", flush=True)
    started = time.time()

    def episode_args(task, cue, condition, policy, steps):
        args = ["web", "episode", "--task", task, "--condition", condition, "--policy", policy, "--json"]
        if cue:
            args += ["--cue", cue]
        if steps:
            args += ["--steps", str(steps)]
        return args

    # One episode per core at a time (each `vifo web episode` is single-threaded, and under an
    # emulator slow); reported in the list's order.
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        runs = [pool.submit(builds.both, episode_args(*episode)) for episode in EPISODES]
        for (task, cue, condition, policy, _steps), run in zip(EPISODES, runs):
            report_episode(builds, task, cue, condition, policy, run.result())
    print(f"  ({time.time() - started:.0f} s)", flush=True)


def report_episode(builds, task, cue, condition, policy, printed):
    """Compares one episode's JSON as the two builds printed it."""
    outs = {which: json.loads(out) for which, out in printed.items()}
    ref = outs["reference"]
    label = f"{cue or task} {condition} {policy}, {ref['steps']} steps, state {ref['state_hash']}, frames {ref['frame_hash']}"
    if not builds.compare(label, ref, outs["other"]):
        for key in sorted(ref):
            if ref[key] != outs["other"].get(key):
                print(f"    {key}: {ref[key]} != {outs['other'].get(key)}")


def without_wall_times(path):
    """A results file's records with their wall times dropped, in a fixed order."""
    records = []
    for line in path.read_text().splitlines():
        record = json.loads(line)
        record.pop("wall_ms", None)
        records.append(json.dumps(record, sort_keys=True))
    return sorted(records)


def benchmark_run(builds):
    print("benchmark run (`vifo " + " ".join(RUN_ARGS) + "`):", flush=True)
    started = time.time()
    for which in builds.commands:
        shutil.rmtree(builds.work / which / "run", ignore_errors=True)
    builds.both(RUN_ARGS + ["--out", "run"])
    ref, other = builds.work / "reference" / "run", builds.work / "other" / "run"
    files = sorted({p.relative_to(run) for run in (ref, other) for p in run.rglob("*") if p.is_file() and p.suffix != ".lock"})
    for name in files:
        if not (ref / name).exists() or not (other / name).exists():
            builds.compare(f"{name} (written by one build only)", True, False)
        elif name.suffix == ".jsonl":
            records = without_wall_times(ref / name)
            builds.compare(f"{name} ({len(records)} records, wall times left out)", records, without_wall_times(other / name))
        else:
            builds.compare(str(name), (ref / name).read_bytes(), (other / name).read_bytes())
    print(f"  ({time.time() - started:.0f} s)", flush=True)


def look(builds):
    status = subprocess.run(builds.commands["reference"] + ["assets", "--json"], capture_output=True, text=True)
    try:
        found = json.loads(status.stdout)
    except json.JSONDecodeError:
        found = None
    if status.returncode != 0 or not found or not found.get("look", "").startswith("libero-assets"):
        print("SKIPPED LIBERO's look: its assets are not installed here (`vifo assets` says so); "
              "the built-in look was compared above")
        return
    print(f"LIBERO's look ({found['look']}), each build loading it into an empty look cache:", flush=True)

    # The first render fills the cache, the second reads what the same build made.
    for which in builds.commands:
        shutil.rmtree(builds.work / which / "look-cache", ignore_errors=True)

    def env_for(which):
        return {**os.environ, "VIFO_LOOK_CACHE": str(builds.work / which / "look-cache")}

    for camera in ["agentview", "robot0_eye_in_hand"]:
        folder = f"frames-{camera}"
        for which in builds.commands:
            shutil.rmtree(builds.work / which / folder, ignore_errors=True)
        started = time.time()
        builds.both(["render", "--task", LOOK_TASK, "--expert", "--steps", str(LOOK_STEPS), "--camera", camera,
                     "--frames", folder], env_for)
        frames = {which: {p.name: p.read_bytes() for p in (builds.work / which / folder).glob("*.png")}
                  for which in builds.commands}
        ref, other = frames["reference"], frames["other"]
        if not ref:
            raise SystemExit(f"the reference build wrote no frames of {LOOK_TASK} {camera}")
        same = sum(other.get(name) == png for name, png in ref.items())
        builds.compare(f"{LOOK_TASK} {camera}: {same} of {len(ref)} frames byte-identical "
                       f"({time.time() - started:.0f} s)", ref, other)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vifo", required=True, help="the reference build")
    parser.add_argument("--other", required=True, help="command line of the other build (may start with an emulator)")
    parser.add_argument("--work", default="target/cross-arch", help="folder for both builds' outputs")
    args = parser.parse_args()
    work = Path(args.work).resolve()
    reference = [str(Path(args.vifo).resolve())]
    other = shlex.split(args.other)
    if Path(other[-1]).exists():
        other[-1] = str(Path(other[-1]).resolve())
    builds = Builds(reference, other, work)
    started = time.time()
    episodes(builds)
    benchmark_run(builds)
    look(builds)
    equal = builds.checked - len(builds.differences)
    print(f"CROSS-ARCH: {equal} of {builds.checked} outputs equal between `{args.vifo}` and `{args.other}` "
          f"({time.time() - started:.0f} s)")
    if builds.differences:
        print("different: " + "; ".join(builds.differences))
        sys.exit(1)


if __name__ == "__main__":
    main()
