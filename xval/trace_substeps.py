"""Traces one limit-driving sequence in the original stack substep by substep, to see what MuJoCo does where
`vifo xval` shows ours parting from it.

For every 2 ms substep of the chosen control steps it prints the arm's and fingers' joint velocities, the force of
each dof's dry-friction row (`frictionloss`) and joint-limit row, and every contact of the arm or gripper. Example
(the jolt of `j4_lo_j2_lo` at record 99, docs/measurements.md, "Side by side with the original LIBERO"):

    nice ~/.cache/libero-vifo/orig-venv/bin/python xval/trace_substeps.py j4_lo_j2_lo --records 99 99
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "bench"))
import libero_side_by_side as sbs  # noqa: E402
import record_limits as rl  # noqa: E402

# MuJoCo's constraint types (mjtConstraint) this trace names.
FRICTION_DOF, LIMIT_JOINT = 1, 3
ARM_DOFS = 9  # seven arm joints and two fingers come first in LIBERO's models


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sequence", help="a push sequence of xval/record_limits.py, e.g. j4_lo_j2_lo")
    ap.add_argument("--records", nargs=2, type=int, metavar=("FIRST", "LAST"), required=True,
                    help="control steps to trace (record numbers as `vifo xval` counts them, from 1)")
    args = ap.parse_args()
    pushes = {name: (arm, steps) for name, arm, steps in rl.PUSHES}
    if args.sequence not in pushes:
        sys.exit(f"trace_substeps: unknown sequence {args.sequence!r}; expected one of {', '.join(pushes)}")
    first, last = args.records
    if not 1 <= first <= last:
        sys.exit("trace_substeps: --records needs 1 <= FIRST <= LAST")
    actions, _ = rl.push_sequence(*pushes[args.sequence])
    if last > len(actions):
        sys.exit(f"trace_substeps: {args.sequence} has {len(actions)} records")

    root = sbs.setup()
    env, init = rl.make_env(root, rl.PUSH_TASK, sbs.TASKS[rl.PUSH_TASK])
    env.seed(0)
    env.reset()
    env.set_init_state(init)
    sim = env.env.sim
    m, d = sim.model, sim.data
    robot = [m.body_id2name(m.geom_bodyid[g]).startswith(("robot0_", "gripper0_")) for g in range(m.ngeom)]
    step = sim.step
    trace = {"record": 0, "substep": 0}

    def traced_step():
        step()
        if first <= trace["record"] <= last:
            trace["substep"] += 1
            rows = {FRICTION_DOF: [], LIMIT_JOINT: []}
            for i in range(d.nefc):
                kind, dof = int(d.efc_type[i]), int(d.efc_id[i])
                if kind in rows and dof < ARM_DOFS:
                    rows[kind].append(f"{dof + 1}:{d.efc_force[i]:+.3f}")
            touching = [f"{m.geom_id2name(c.geom1)}|{m.geom_id2name(c.geom2)}" for c in d.contact[:d.ncon]
                        if robot[c.geom1] or robot[c.geom2]]
            qd = " ".join(f"{v:+.4f}" for v in d.qvel[:ARM_DOFS])
            print(f"record {trace['record']} substep {trace['substep']:2d}  qd {qd}  friction {' '.join(rows[FRICTION_DOF])}"
                  f"  limits {' '.join(rows[LIMIT_JOINT]) or '-'}  arm contacts {', '.join(touching) or '-'}", flush=True)

    sim.step = traced_step
    for t in range(last):
        trace["record"], trace["substep"] = t + 1, 0
        env.step(actions[t])


if __name__ == "__main__":
    main()
