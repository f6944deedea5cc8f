"""Vector env scaling: env steps/s of ``LiberoVifoVectorEnv`` with 1 thread and with 2 threads
on the same N episodes, two 256x256 cameras each (the issue's gate: 2 threads >= 1.8x 1 thread).
Prints the load average beside the figures: on a shared machine other processes take cores.

    python python/bench_vector.py [--envs 2] [--steps 40] [--rounds 5] [--size 256]
"""

import argparse
import os
import statistics
import time

import numpy as np

from libero_vifo.gym import LiberoVifoVectorEnv


def steps_per_second(env, actions):
    """Env steps per wall second, and the cores the process used meanwhile (CPU s / wall s)."""
    env.reset(options={"init_state": 0})
    start, cpu = time.perf_counter(), time.process_time()
    for a in actions:
        env.step(a)
    wall = time.perf_counter() - start
    return len(actions) * env.num_envs / wall, (time.process_time() - cpu) / wall


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--envs", type=int, default=2)
    p.add_argument("--steps", type=int, default=40, help="vector steps per round")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--size", type=int, default=256)
    args = p.parse_args()
    actions = np.tile(np.array([0.2, 0.0, -0.1, 0.0, 0.0, 0.05, -1.0]), (args.steps, args.envs, 1))
    envs = {t: LiberoVifoVectorEnv(suite="libero_goal", task=0, num_envs=args.envs, size=args.size, threads=t) for t in (1, 2)}
    rates = {1: [], 2: []}
    load_before = os.getloadavg()
    # Rounds alternate so that load from other processes hits both sides alike; medians.
    for _ in range(args.rounds):
        for t in (1, 2):
            rates[t].append(steps_per_second(envs[t], actions))
    load_after = os.getloadavg()
    (one, one_cores), (two, two_cores) = (
        (statistics.median(r[0] for r in rates[t]), statistics.median(r[1] for r in rates[t])) for t in (1, 2)
    )
    print(f"libero_goal/0 x {args.envs} envs, two {args.size}x{args.size} cameras, {args.rounds} rounds of {args.steps} vector steps, medians")
    print(f"cores: {os.cpu_count()}; load average (1 min) before {load_before[0]:.2f}, after {load_after[0]:.2f}")
    # Cores used: where other processes hold the cores (Linux shares CPU time per session when
    # sched_autogroup is on), 2 threads cannot get 2 cores, whatever the env does.
    print(f"1 thread:  {one:.1f} env steps/s ({one_cores:.2f} cores used, {one / one_cores:.1f} steps per CPU second)")
    print(f"2 threads: {two:.1f} env steps/s ({two_cores:.2f} cores used, {two / two_cores:.1f} steps per CPU second)")
    print(f"2 threads / 1 thread: {two / one:.2f}x (gate >= 1.8x)")


if __name__ == "__main__":
    main()
