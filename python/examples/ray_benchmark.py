"""The benchmark on a Ray cluster: a selection run with a policy into a `vifo run` results file,
then the tables. Without --address it starts a local cluster of --workers CPUs.

    python python/examples/ray_benchmark.py --policy expert-cue --suite libero_goal --per-family 1 --workers 2
    python python/examples/ray_benchmark.py --address auto --policy ws://gpu1:8000 --policy ws://gpu2:8000 --suite all

With --kill-after N it SIGKILLs one busy Ray worker once N episodes are written (the recovery
check), and prints the missing and duplicate counts either way. Like `vifo run`, it exits with an
error status when episodes ended in errors or are missing (the file and the tables are kept).
"""

import argparse
import os
import signal
import subprocess
import sys
import threading
import time

from libero_vifo.ray import default_output, run_benchmark


def busy_workers():
    """PIDs of Ray worker processes running a batch (their process title names the task)."""
    out = subprocess.run(["ps", "-eo", "pid=,args="], capture_output=True, text=True).stdout
    return [int(line.split(None, 1)[0]) for line in out.splitlines() if "ray::_run_batch" in line and "grep" not in line]


def kill_one_when(output, written):
    """Waits until `output` holds `written` records, then SIGKILLs one busy worker."""
    while True:
        lines = open(output).read().count("\n") if os.path.exists(output) else 0
        pids = busy_workers()
        if lines >= written and pids:
            os.kill(pids[0], signal.SIGKILL)
            print(f"killed Ray worker {pids[0]} (SIGKILL) with {lines} episodes written", flush=True)
            return pids[0]
        time.sleep(0.05)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--address", default=None)
    p.add_argument("--policy", action="append", required=True, help="a built-in policy or a server URL, as vifo run --policy takes it; repeatable (servers)")
    p.add_argument("--model-profile", help="the served model's profile, as vifo run --model-profile takes it")
    p.add_argument("--policy-name", help="the name a served policy's records and results file carry, as vifo run --policy-name takes it")
    p.add_argument("--set", default="paper")
    p.add_argument("--suite", action="append", default=[])
    p.add_argument("--protocol", action="append", default=[])
    p.add_argument("--family", action="append", default=[])
    p.add_argument("--per-family", type=int)
    p.add_argument("--episodes", type=int, default=1)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--batch-size", type=int)
    p.add_argument("--out", default="vifo-run-ray")
    p.add_argument("--resume", action="store_true")
    p.add_argument("--kill-after", type=int, help="SIGKILL a busy worker once this many episodes are written")
    p.add_argument("--assets", help="LIBERO's asset folder on every node (default: VIFO_LIBERO_ASSETS, then the installed packages)")
    p.add_argument("--robot-assets", help="robosuite's models/assets folder on every node (default: the installed robosuite)")
    p.add_argument("--builtin-look", action="store_true", help="draw the built-in look whatever is installed")
    args = p.parse_args()
    selection = {"set": args.set, "suites": args.suite, "protocols": args.protocol, "families": args.family,
                 "per_family": args.per_family, "episodes": args.episodes}
    policy = args.policy[0] if len(args.policy) == 1 else args.policy
    output = default_output(args.policy, args.out, args.policy_name, args.model_profile)
    if args.kill_after is not None:
        threading.Thread(target=kill_one_when, args=(output, args.kill_after), daemon=True).start()
    s = run_benchmark(selection, policy, address=args.address, output=output, resume=args.resume,
                      batch_size=args.batch_size, num_workers=args.workers, report_dir=os.path.join(args.out, "report"), quiet=True,
                      assets=args.assets, robot_assets=args.robot_assets, builtin_look=args.builtin_look,
                      model_profile=args.model_profile, name=args.policy_name)
    print(s["report"])
    print(f"{s['episodes']} episodes: {s['ran']} run now ({s['errors']} errors), {s['already_done']} already done, "
          f"in {s['seconds']:.1f} s -> {s['output']}")
    print(f"missing: {s['missing']}  duplicates: {s['duplicates']}  failed batches: {s['failed_batches']}")
    if s["errors"] or s["missing"]:
        sys.exit(f"{s['errors']} episodes ended in errors and {s['missing']} are missing: fix the cause and run again with --resume")


if __name__ == "__main__":
    main()
