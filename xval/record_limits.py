"""Records MuJoCo sequences that reach where the reference set does not, for `vifo xval DIR`.

The shared reference sequence (../shared/xval/libero_reference) keeps the arm well inside its joint ranges and
never grasps. These sequences, run in the original stack (OffScreenRenderEnv, seed 0, init state 0, as the
reference README describes), drive the arm into its joint limits and hold it there, close the gripper on an object
while the arm moves, and send full-scale OSC targets far outside the workspace:

- `j<k>_<side>_...`: settle 10 steps, push one constant full-scale action until the named joints run past their
  limits and hold them there, then reverse it for 20 steps. Which joints each push reaches was found by trying
  every constant action along one or two of the six axes in MuJoCo; together they take each of joints 1-7 past a
  limit (MuJoCo's soft limit constraint, `solref` 0.02 1, `solimp` 0.9 0.95 0.001, margin 0).
- `swing_j1_lo_j2_lo`, `drive_j3_hi`, `drive_j3_lo`, `drive_j4_hi_j2_lo`, `swing_j2_hi`: closed-loop sequences
  for the limits that the constant pushes reach only through a whirl near the stretched arm or with the hand
  sliding on link 5 (where MuJoCo does not repeat itself: xval/sensitivity.py). `drive_*` asks the OSC each step
  for the end-effector motion that one joint's (or a joint direction's) Jacobian column gives, until the joint
  runs past its limit, holds it there, then reverses; `swing_*` first swings the grip site around the base's
  vertical axis (turning the gripper with it) until joint 1 reaches its lower limit, and `swing_j2_hi` then
  leans the arm on joint 2 out over the empty floor behind the base to joint 2's upper limit.
- `grasp_move`: steer the grip site onto the alphabet soup can (libero_object task 0) from MuJoCo's own state,
  close on it, lift and swing it around with the gripper closed, open.
- `far_targets`: full-scale translation and rotation actions that flip every 8 steps, with the gripper toggling.

Each file is `<name>_<suite>_task<i>_init0.json` in the reference format (records 0..N, `sbs.record`), with
`meta.sequence` naming it and `meta.phases` the record ranges `vifo xval` reports separately.

Run with the original stack's python (bench/libero_side_by_side.sh builds it):
    nice ~/.cache/libero-vifo/orig-venv/bin/python xval/record_limits.py [--out DIR]
then  vifo xval DIR
"""

import argparse
import json
import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "bench"))
import libero_side_by_side as sbs  # noqa: E402  (setup, init states, records)

DEFAULT_OUT = os.path.join(os.path.expanduser("~"), ".cache", "libero-vifo", "xval-limits")
SETTLE = 10
RELEASE = 20
OPEN, CLOSE = -1.0, 1.0

# (name, constant action for the push (6 arm components), push steps): the joints past a limit in MuJoCo.
# Full scale (0.5 rad of rotation a step) reaches every joint's limit but swings the arm fast and, in some,
# through the stretched-arm singularity; at 0.4 the arm reaches the limits of joints 2-7 at moderate speed.
PUSHES = [
    ("fast_j1_hi_j5_hi_j2_lo", [0, 0, 0, 1, -1, 0], 100),
    ("fast_j2_hi_j3_hi", [1, 0, 0, 0, -1, 0], 70),
    ("fast_j4_hi_j5_hi_j7_lo", [0, 0, 1, 0, -1, 0], 70),
    ("fast_j5_lo_j6_lo", [0, 0, 0, -1, -1, 0], 90),
    ("fast_j6_hi_j7_lo", [0, 0, 0, 1, 0, 1], 90),
    ("fast_j7_hi", [0, 0, 0, 0, 0, -1], 60),
    ("fast_j2_lo_j4_lo", [-1, 0, 0, 0, 0, 0], 50),
    ("j6_hi_j4_hi", [0.4, 0, 0, 0, -0.4, 0], 100),
    ("j7_lo_j6_hi", [0, 0, 0, 0.4, 0, 0.4], 130),
    ("j7_hi_j6_hi", [0, 0, 0, 0, 0, -0.4], 160),
    ("j4_lo_j2_lo", [-0.4, 0, 0, 0, 0, 0], 90),
    ("j5_lo_j2_hi_j3_lo", [0, 0, 0, -0.4, -0.4, 0], 150),
    ("j5_hi_j2_hi", [0, 0, 0, 0.4, 0, 0], 130),
]
PUSH_TASK = "libero_spatial"
GRASP_TASK = ("libero_object", "alphabet_soup_1")


def push_sequence(arm, steps):
    actions = [[0.0] * 6 + [OPEN]] * SETTLE
    actions += [[float(a) for a in arm] + [OPEN]] * steps
    actions += [[-float(a) for a in arm] + [OPEN]] * RELEASE
    phases = [["settle", 1, SETTLE], ["push", SETTLE + 1, SETTLE + steps],
              ["release", SETTLE + steps + 1, SETTLE + steps + RELEASE]]
    return actions, phases


def far_sequence():
    """Full-scale actions flipping every 8 steps along each axis in turn (targets 40 cm past the pose)."""
    actions = [[0.0] * 6 + [OPEN]] * SETTLE
    for k in range(12):
        for sign in (1.0, -1.0):
            a = [0.0] * 6
            a[k % 6] = sign
            a[(k + 2) % 6] = -sign
            actions += [a + [CLOSE if k % 2 else OPEN]] * 8
    return actions, [["settle", 1, SETTLE], ["far", SETTLE + 1, len(actions)]]


def toward(env, target, gain=20.0):
    """A translation action steering the grip site toward `target` (OSC's scale: 1.0 is 5 cm)."""
    eef = env.env.sim.data.site_xpos[env.env.sim.model.site_name2id("gripper0_grip_site")]
    return [max(-1.0, min(1.0, gain * (t - e))) for t, e in zip(target, eef)]


def arm_contacts(env):
    """Contacts between the arm or gripper and anything else, at the end of the step (for the log: where the
    arm touches the scene, our primitive link shapes stand in for robosuite's meshes)."""
    sim = env.env.sim
    m, d = sim.model, sim.data
    robot = [m.body_id2name(m.geom_bodyid[g]).startswith(("robot0_", "gripper0_"))
             for g in range(m.ngeom)]
    return sum(1 for c in d.contact[:d.ncon] if robot[c.geom1] != robot[c.geom2])


def run(env, init, actions_or_policy, steps):
    """Resets to `init`, records every step; `actions_or_policy(t, env)` gives the action of step t."""
    env.seed(0)  # the reset's fixture placement draws from it: each file the same whatever ran before
    env.reset()
    env.set_init_state(init)
    records = [sbs.record(env, 0, None)]
    for t in range(steps):
        a = [float(x) for x in actions_or_policy(t, env)]
        env.step(a)
        records.append(sbs.record(env, t + 1, a))
        records[-1]["arm_contacts"] = arm_contacts(env)
    return records


def replayed(actions, phases):
    """A fixed action sequence as `main`'s jobs take it: the policy, the step count and the phases."""
    return lambda t, _env: actions[t], len(actions), phases


def swing_policy(out, back, rate=0.04):
    """After settling, the grip site swung clockwise (seen from above) around the base's vertical axis by `rate`
    rad a step for `out` steps, then back for `back` steps, at its radius and height, the gripper turning with it."""
    state = {}

    def policy(t, env):
        sim = env.env.sim
        grip = sim.data.site_xpos[sim.model.site_name2id("gripper0_grip_site")]
        base = sim.data.body_xpos[sim.model.body_name2id("robot0_base")]
        if t < SETTLE:
            return [0.0] * 6 + [OPEN]
        if not state:
            state.update(phi=math.atan2(grip[1] - base[1], grip[0] - base[0]), z=grip[2],
                         r=math.hypot(grip[0] - base[0], grip[1] - base[1]))
        k = t - SETTLE
        turn = -rate if k < out else rate
        phi = state["phi"] - rate * (k + 1 if k < out else 2 * out - k - 1)
        target = [base[0] + state["r"] * math.cos(phi), base[1] + state["r"] * math.sin(phi), state["z"]]
        return toward(env, target) + [0.0, 0.0, turn / 0.5, OPEN]

    return policy


def joint_policy(direction, push, rate=0.1):
    """For `push` steps, the end-effector motion that the arm's joints moving along `direction` (7 numbers) by
    `rate` rad would give, from MuJoCo's Jacobian at the grip site (OSC scale: 1.0 is 5 cm or 0.5 rad); then
    the opposite motion."""
    import numpy as np

    def policy(t, env):
        sim = env.env.sim
        cols = env.env.robots[0]._ref_joint_vel_indexes
        jp = sim.data.get_site_jacp("gripper0_grip_site").reshape(3, -1)[:, cols]
        jr = sim.data.get_site_jacr("gripper0_grip_site").reshape(3, -1)[:, cols]
        dq = np.asarray(direction, dtype=float) * (rate if t < push else -rate)
        return ([float(np.clip(x / 0.05, -1, 1)) for x in jp @ dq] +
                [float(np.clip(x / 0.5, -1, 1)) for x in jr @ dq] + [OPEN])

    return policy


def joint(k, sign=1.0):
    """The direction of joint `k` (1-7) alone."""
    return [sign if i == k - 1 else 0.0 for i in range(7)]


# (name, swing out, swing back, joint direction, push steps) of the closed-loop sequences (module doc).
CLOSED_LOOP = [
    ("swing_j1_lo_j2_lo", 150, 40, None, 0),
    ("drive_j3_hi", 0, 0, joint(3), 200),
    ("drive_j3_lo", 0, 0, joint(3, -1.0), 200),
    ("drive_j4_hi_j2_lo", 0, 0, joint(4), 200),
    ("swing_j2_hi", 90, 0, joint(2), 200),
]


def closed_loop(out, back, direction, push):
    """A `CLOSED_LOOP` sequence: settle, swing out and back, then push along `direction` and `RELEASE` back."""
    start = SETTLE + out + back
    steps = start + (push + RELEASE if push else 0)
    swinging = swing_policy(out, back)
    pushing = joint_policy(direction, push) if push else None

    def policy(t, env):
        return swinging(t, env) if t < start else pushing(t - start, env)

    phases = [["settle", 1, SETTLE], ["swing", SETTLE + 1, start]] if out else [["settle", 1, SETTLE]]
    if push:
        phases += [["push", start + 1, start + push], ["release", start + push + 1, steps]]
    return policy, steps, phases


def grasp_policy(obj):
    """Over the object, down, close, lift and swing, open (decided from MuJoCo's state as it runs)."""
    def policy(t, env):
        sim = env.env.sim  # a reset builds a new sim
        pos = sim.data.body_xpos[sim.model.body_name2id(env.env.objects_dict[obj].root_body)].tolist()
        if t < SETTLE:
            return [0.0] * 6 + [OPEN]
        if t < 40:
            return toward(env, [pos[0], pos[1], pos[2] + 0.12]) + [0, 0, 0, OPEN]
        if t < 60:
            return toward(env, [pos[0], pos[1], pos[2] + 0.01]) + [0, 0, 0, OPEN]
        if t < 75:
            return [0.0] * 6 + [CLOSE]
        if t < 95:
            return [0.0, 0.0, 0.6, 0.0, 0.0, 0.0, CLOSE]
        if t < 135:
            p = 2 * math.pi * (t - 95) / 40
            return [0.6 * math.sin(p), 0.6 * math.cos(p), 0.0, 0.3 * math.sin(p), 0.0, 0.3 * math.cos(p), CLOSE]
        return [0.0] * 6 + [OPEN]

    phases = [["settle", 1, 10], ["approach", 11, 60], ["close", 61, 75], ["lift", 76, 95],
              ["carry", 96, 135], ["open", 136, 150]]
    return policy, 150, phases


def make_env(root, suite, name):
    from libero.libero.envs import OffScreenRenderEnv
    env = OffScreenRenderEnv(bddl_file_name=os.path.join(root, "bddl_files", suite, name + ".bddl"),
                             has_offscreen_renderer=False, use_camera_obs=False)
    env.seed(0)
    env.reset()
    init = sbs.load_init_states(os.path.join(root, "init_files", suite, name + ".pruned_init"))[0]
    return env, init


def save(out, seq, suite, name, env, init, records, phases):
    meta = {"suite": suite, "task_id": 0, "task_name": name, "problem_class": type(env.env).__name__,
            "init_state_flat": [float(x) for x in init], "sequence": seq, "phases": phases}
    path = os.path.join(out, f"{seq}_{suite}_task0_init0.json")
    with open(path, "w") as f:
        json.dump({"meta": meta, "steps": records}, f)
    return path


def limit_summary(records):
    """Deepest excursion past each joint's range (rad), for the log."""
    lo = [-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973]
    hi = [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973]
    past = {}
    for r in records:
        for j, q in enumerate(r["joint_qpos"]):
            for side, d in (("lo", lo[j] - q), ("hi", q - hi[j])):
                if d > 0:
                    past[f"j{j + 1}_{side}"] = max(past.get(f"j{j + 1}_{side}", 0.0), d)
    return ", ".join(f"{k} {v * 1e3:.1f} mrad" for k, v in sorted(past.items())) or "no joint past its range"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=DEFAULT_OUT, help=f"output folder (default {DEFAULT_OUT})")
    ap.add_argument("--force", action="store_true", help="record sequences whose files are already there again")
    args = ap.parse_args()
    root = sbs.setup()
    os.makedirs(args.out, exist_ok=True)
    import mujoco, robosuite
    print(f"original stack: mujoco {mujoco.__version__}, robosuite {robosuite.__version__}; to {args.out}", flush=True)
    # (sequence, suite, plan): `plan()` gives the policy, its steps and its phases.
    jobs = [(seq, PUSH_TASK, lambda arm=arm, n=n: replayed(*push_sequence(arm, n))) for seq, arm, n in PUSHES]
    jobs.append(("far_targets", PUSH_TASK, lambda: replayed(*far_sequence())))
    jobs += [(seq, PUSH_TASK, lambda loop=loop: closed_loop(*loop)) for seq, *loop in CLOSED_LOOP]
    jobs.append(("grasp_move", GRASP_TASK[0], lambda: grasp_policy(GRASP_TASK[1])))
    envs = {}
    for seq, suite, plan in jobs:
        path = os.path.join(args.out, f"{seq}_{suite}_task0_init0.json")
        if os.path.exists(path) and not args.force:
            print(f"{seq}: already recorded", flush=True)
            continue
        name = sbs.TASKS[suite]
        if suite not in envs:
            envs[suite] = make_env(root, suite, name)
        env, init = envs[suite]
        clock = time.perf_counter()
        policy, steps, phases = plan()
        records = run(env, init, policy, steps)
        save(args.out, seq, suite, name, env, init, records, phases)
        touching = [r["t"] for r in records[1:] if r["arm_contacts"]]
        touch = f"arm touches the scene at {len(touching)} records from {touching[0]}" if touching else "arm touches nothing"
        print(f"{seq}: {len(records) - 1} steps in {time.perf_counter() - clock:.1f} s; {limit_summary(records)}; {touch}",
              flush=True)
    for env, _ in envs.values():
        env.close()


if __name__ == "__main__":
    main()
