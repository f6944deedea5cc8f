"""``libero_vifo.evaluate``: a Python function as the policy of a ``vifo run`` results file and
report; what it is given is the gym env's observation; its errors stop the run and are raised."""

import json

import numpy as np
import pytest

import libero_vifo
from libero_vifo import _native

GOAL_ORIGINAL = {"suites": ["libero_goal"], "protocols": ["original"], "episodes": 1}


class Recorder:
    """Holds still, keeping what it was given."""

    def __init__(self):
        self.seen, self.resets = [], 0

    def reset(self):
        self.resets += 1

    def __call__(self, obs, instruction):
        self.seen.append((obs, instruction))
        return np.zeros(7)


def test_a_python_policy_runs_into_a_results_file_and_report_as_vifo_run_would(tmp_path):
    policy = Recorder()
    selection = {**GOAL_ORIGINAL, "sample": 1}
    summary = libero_vifo.evaluate(policy, "py-still", selection, out=tmp_path, size=32, quiet=True)
    assert summary["ran"] == 1 and summary["errors"] == 0 and summary["episodes"] == 1 and policy.resets == 1
    assert summary["output"] == libero_vifo.results_path(tmp_path, "py-still") == str(tmp_path / "results-py-still.jsonl")
    (record,) = [json.loads(line) for line in open(summary["output"])]
    assert record["policy"] == "py-still"
    assert "| py-still |" in open(tmp_path / "report" / "table1.md").read()
    assert "| py-still | libero_goal |" in open(tmp_path / "report" / "suites.md").read()
    # The built-in `zero` (which reads no images and fast-forwards a world at rest) ends the
    # same episode the same way.
    ((_, spec),) = _native.episode_specs(set="paper", **selection)
    _native.run_specs([spec], "zero", str(tmp_path / "zero.jsonl"), size=32)
    (zero,) = [json.loads(line) for line in open(tmp_path / "zero.jsonl")]
    assert record["spec"] == zero["spec"] and record["outcome"] == zero["outcome"]
    # What the policy was given first is the gym env's first observation of that episode.
    spec = json.loads(spec)
    first, instruction = policy.seen[0]
    assert instruction == spec["instruction"] and first["agentview_image"].shape == (32, 32, 3)
    pytest.importorskip("gymnasium")
    from libero_vifo.gym import LiberoVifoEnv

    env = LiberoVifoEnv(spec["task"]["suite"], spec["task"]["index"], size=32)
    obs, _ = env.reset(options={"init_state": spec["init"]})
    for key in ("agentview_image", "robot0_eye_in_hand_image", "robot0_eef_pos", "robot0_eef_quat", "robot0_gripper_qpos", "robot0_joint_pos"):
        assert np.array_equal(first[key], obs[key]), key
    env.close()
    # Resumed: nothing left to do.
    again = libero_vifo.evaluate(Recorder(), "py-still", selection, out=tmp_path, size=32, resume=True, quiet=True)
    assert again["ran"] == 0 and again["already_done"] == 1


def test_the_policys_exception_stops_the_run_and_is_raised(tmp_path):
    def broken(obs, instruction):
        if len(broken.calls) == 3:
            raise KeyError("no such joint")
        broken.calls.append(1)
        return [0.0] * 7

    broken.calls = []
    with pytest.raises(KeyError, match="no such joint"):
        libero_vifo.evaluate(broken, "py-broken", GOAL_ORIGINAL, out=tmp_path, size=32, quiet=True)
    # One episode was recorded, as an error a resumed run retries; the other nine never ran.
    records = [json.loads(line) for line in open(tmp_path / "results-py-broken.jsonl")]
    assert len(records) == 1 and "no such joint" in records[0]["outcome"]["message"], records
    for k, (bad, says) in enumerate((
        (lambda obs, i: [0.0] * 6, "returned 6 numbers, expected 7"),
        (lambda obs, i: [0.0] * 6 + [float("nan")], "returned NaN at element 6"),
        (lambda obs, i: "up", "returned no sequence of numbers"),
    )):
        with pytest.raises(ValueError, match=says):
            libero_vifo.evaluate(bad, "py-bad", {**GOAL_ORIGINAL, "sample": 1}, out=tmp_path / f"bad{k}", size=32, quiet=True)


def test_wrong_arguments_are_named(tmp_path):
    with pytest.raises(ValueError, match="needs name="):
        _native.run_specs([], lambda o, i: [0.0] * 7, str(tmp_path / "x.jsonl"))
    with pytest.raises(ValueError, match="not a built-in policy's name"):
        libero_vifo.evaluate(lambda o, i: [0.0] * 7, "zero", GOAL_ORIGINAL, out=tmp_path)
    with pytest.raises(ValueError, match="expected a policy name, a server URL or a callable"):
        _native.run_specs([], 42, str(tmp_path / "x.jsonl"), name="n")
    with pytest.raises(ValueError, match="zero is built-in and its records carry its own name"):
        _native.run_specs([], "zero", str(tmp_path / "x.jsonl"), name="n")
    with pytest.raises(ValueError, match=r"unknown keys \['suite'\]"):
        libero_vifo.evaluate(lambda o, i: [0.0] * 7, "n", {"suite": "libero_goal"}, out=tmp_path)


def test_ctrl_c_stops_the_run_after_the_running_episode(tmp_path):
    """Python handles signals on its main thread only, which waits in Rust during a run: without
    the run's own check a Ctrl-C did nothing until every episode was done."""
    import signal
    import subprocess
    import sys
    import time

    # A terminal's Ctrl-C handler: a child of a job started in the background (CI's) inherits
    # SIGINT ignored, and Python then keeps it ignored.
    script = f"""
import signal, sys, time
import numpy as np
import libero_vifo
signal.signal(signal.SIGINT, signal.default_int_handler)
def slow(obs, instruction):
    print("acting", flush=True)
    time.sleep(0.01)
    return np.zeros(7)
try:
    libero_vifo.evaluate(slow, "py-slow", {GOAL_ORIGINAL!r}, out={str(tmp_path)!r}, size=32, quiet=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(3)
"""
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "acting"
    child.send_signal(signal.SIGINT)
    start = time.monotonic()
    out, _ = child.communicate(timeout=120)
    assert child.returncode == 3 and "interrupted" in out, (child.returncode, out[-300:])
    assert time.monotonic() - start < 30
    # The running episode is recorded as stopped (an error, retried on resume); no other ran.
    records = [json.loads(line) for line in open(tmp_path / "results-py-slow.jsonl")]
    assert len(records) == 1 and "stopped" in records[0]["outcome"]["message"], records
