"""How far MuJoCo parts from itself on the limit-driving sequences when its start is nudged: the floor under
`vifo xval`'s end-effector figures there.

Any second simulator differs from MuJoCo by some rounding at every step (ours by 1e-7 to 1e-5 rad per control step
from MuJoCo's own state, `vifo xval`'s one-step figures). Where a sequence amplifies such differences (a whirl
through the stretched-arm singularity, a stick-slip contact), no simulator that is not MuJoCo bit for bit can stay
within 1 mm of it. This script measures that amplification in MuJoCo alone: it replays the actions of each
push-task sequence that `xval/record_limits.py` recorded (`--recorded DIR`), then again with the arm's seven joint positions moved by +-EPS rad after the
initial state is loaded (alternating signs, at rest), and prints the largest distance between the two grip sites
over the sequence, for each EPS.

Run with the original stack's python (bench/libero_side_by_side.sh builds it):
    nice ~/.cache/libero-vifo/orig-venv/bin/python xval/sensitivity.py [--eps 1e-7 1e-5] [SEQUENCE ...]
"""

import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "bench"))
import libero_side_by_side as sbs  # noqa: E402
import record_limits as rl  # noqa: E402


def grip_path(env, init, actions, eps):
    """Grip-site positions after every step, with the arm's joints nudged by +-eps at the start."""
    env.seed(0)
    env.reset()
    env.set_init_state(init)
    sim = env.env.sim
    robot = env.env.robots[0]
    if eps:
        for k, i in enumerate(robot._ref_joint_pos_indexes):
            sim.data.qpos[i] += eps if k % 2 == 0 else -eps
        sim.forward()
    site = sim.model.site_name2id("gripper0_grip_site")
    path = []
    for a in actions:
        env.step([float(x) for x in a])
        path.append(env.env.sim.data.site_xpos[site].copy())
    return path


def recorded_actions(folder, name):
    """The actions of sequence `name` as `record_limits.py` recorded them (closed-loop ones decided them from
    MuJoCo's state as it ran; here they are replayed as they are)."""
    path = os.path.join(folder, f"{name}_{rl.PUSH_TASK}_task0_init0.json")
    try:
        with open(path) as f:
            steps = json.load(f)["steps"]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"sensitivity: cannot read {path} ({e}); record it first: xval/record_limits.py --out {folder}")
    return [r["action_applied_before"] for r in steps[1:]]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sequences", nargs="*", help="sequences of xval/record_limits.py on the push task (default: all of them)")
    ap.add_argument("--recorded", default=rl.DEFAULT_OUT, help=f"folder of the recordings (default {rl.DEFAULT_OUT})")
    ap.add_argument("--eps", nargs="+", type=float, default=[1e-7, 1e-5], help="nudges in rad (default 1e-7 1e-5)")
    args = ap.parse_args()
    known = [name for name, *_ in rl.PUSHES] + [name for name, *_ in rl.CLOSED_LOOP]
    unknown = [s for s in args.sequences if s not in known]
    if unknown:
        sys.exit(f"sensitivity: unknown sequence {unknown[0]!r}; expected one of {', '.join(known)}")
    if any(not e > 0 for e in args.eps):
        sys.exit("sensitivity: every --eps must be > 0")
    root = sbs.setup()
    env, init = rl.make_env(root, rl.PUSH_TASK, sbs.TASKS[rl.PUSH_TASK])
    print("largest grip-site distance (mm) between MuJoCo's run and MuJoCo's run from a start nudged by +-EPS rad")
    print(f"{'sequence':<24} " + " ".join(f"{f'EPS {e:g}':>12}" for e in args.eps), flush=True)
    for name in args.sequences or known:
        actions = recorded_actions(args.recorded, name)
        base = grip_path(env, init, actions, 0.0)
        far = []
        for eps in args.eps:
            path = grip_path(env, init, actions, eps)
            far.append(max(sum((p - q) ** 2 for p, q in zip(a, b)) ** 0.5 for a, b in zip(base, path)) * 1e3)
        print(f"{name:<24} " + " ".join(f"{d:12.3f}" for d in far), flush=True)
    env.close()


if __name__ == "__main__":
    main()
