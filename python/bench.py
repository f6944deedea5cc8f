"""Python overhead: steps/s of OffScreenRenderEnv.step from Python vs the same Rust env
stepped natively, two 256x256 cameras (the issue's gate: Python >= 90 % of native).

    python python/bench.py [--steps 100] [--rounds 7] [--size 256]
"""

import argparse
import pathlib
import statistics
import time

from libero_vifo import _native
from libero_vifo.libero import benchmark, get_libero_path
from libero_vifo.libero.envs import OffScreenRenderEnv


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=100, help="steps per round")
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--size", type=int, default=256)
    args = p.parse_args()
    action = [0.2, 0.0, -0.1, 0.0, 0.0, 0.05, -1.0]
    task = benchmark.get_benchmark_dict()["libero_goal"]().get_task(0)
    path = pathlib.Path(get_libero_path("bddl_files")) / task.problem_folder / task.bddl_file
    env = OffScreenRenderEnv(bddl_file_name=path, camera_heights=args.size, camera_widths=args.size)
    # Rounds alternate so that load from other processes hits both sides alike; medians.
    python, native = [], []
    for _ in range(args.rounds):
        env.reset()
        start = time.perf_counter()
        for _ in range(args.steps):
            env.step(action)
        python.append(args.steps / (time.perf_counter() - start))
        native.append(_native.native_steps_per_second("libero_goal", 0, args.size, args.steps, action))
    python, native = statistics.median(python), statistics.median(native)
    print(f"libero_goal/0, two {args.size}x{args.size} cameras, {args.rounds} rounds of {args.steps} steps, medians")
    print(f"native: {native:.1f} steps/s")
    print(f"python: {python:.1f} steps/s ({100 * python / native:.1f} % of native; gate >= 90 %)")


if __name__ == "__main__":
    main()
