"""libero_vifo.ray on a local 2-worker Ray cluster: the same tables as the runner `vifo run`
uses on the same selection, a results file `vifo run --resume` accepts, and a worker killed
with SIGKILL mid-run recovered with no missing and no duplicate episode."""

import importlib.util
import json
import os
import pathlib
import subprocess
import sys

import pytest

from libero_vifo import _native

if importlib.util.find_spec("ray") is None:
    print("SKIPPED: libero_vifo.ray tests need ray (.ci/run installs it: pip install libero_vifo[ray])")
    pytest.skip("ray is not installed", allow_module_level=True)

import ray  # noqa: E402

from libero_vifo.ray import default_output, run_benchmark  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
SELECTION = {"suites": ["libero_goal"], "protocols": ["original", "authorized"], "families": ["F2"], "per_family": 2, "episodes": 2}


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


def tables(report_dir):
    return {name: (report_dir / name).read_text() for name in ("table1.md", "table2.md")}


def test_a_ray_run_gives_vifo_runs_table_and_file(cluster, tmp_path):
    out = tmp_path / "ray.jsonl"
    s = run_benchmark(SELECTION, "expert-cue", output=out, report_dir=tmp_path / "ray-report", batch_size=2)
    specs = _native.episode_specs(**SELECTION)
    assert s["episodes"] == len(specs) == 8 and s["ran"] == 8
    assert (s["missing"], s["duplicates"], s["failed_batches"]) == (0, 0, 0)
    # The runner of `vifo run` on the same selection, in this process.
    ref = tmp_path / "native.jsonl"
    assert _native.run_specs([j for _, j in specs], "expert-cue", str(ref), threads=2)[0] == 8
    _native.write_report([str(ref)], str(tmp_path / "native-report"))
    assert tables(tmp_path / "ray-report") == tables(tmp_path / "native-report")
    strip = lambda path: sorted(json.dumps({**json.loads(l), "wall_ms": 0}) for l in path.read_text().splitlines())  # noqa: E731
    assert strip(out) == strip(ref)
    # The file is vifo run's: resuming it finds everything done, and so does a Ray resume.
    assert _native.run_specs([j for _, j in specs], "expert-cue", str(out), resume=True) == (0, 0, 8)
    again = run_benchmark(SELECTION, "expert-cue", output=out, resume=True)
    assert (again["ran"], again["already_done"], again["duplicates"]) == (0, 8, 0)
    with pytest.raises(RuntimeError, match="already holds results"):
        run_benchmark(SELECTION, "expert-cue", output=out)
    with pytest.raises(ValueError, match="unknown policy"):
        run_benchmark(SELECTION, "nope", output=tmp_path / "x.jsonl")
    # Checked before any batch starts, each naming its argument.
    with pytest.raises(ValueError, match="camera size 0"):
        run_benchmark(SELECTION, "zero", output=tmp_path / "y.jsonl", size=0)
    with pytest.raises(ValueError, match=r"selection\['episodes'\] -1: expected 0 or more"):
        run_benchmark({**SELECTION, "episodes": -1}, "zero", output=tmp_path / "y.jsonl")
    with pytest.raises(ValueError, match='protocol "foo"'):
        run_benchmark({**SELECTION, "protocols": ["foo"]}, "zero", output=tmp_path / "y.jsonl")
    assert not (tmp_path / "y.jsonl").exists()


def test_a_server_that_is_not_up_gives_error_records_and_says_why(cluster, tmp_path):
    # Port 1 on this machine refuses connections: every episode is an error record, and the
    # summary names the cause once with its count.
    s = run_benchmark(SELECTION, "ws://127.0.0.1:1", output=tmp_path / "down.jsonl", batch_size=4, quiet=True)
    assert s["ran"] == s["errors"] == 8 and s["missing"] == 0
    [(count, message)] = s["error_messages"]
    assert count == 8 and "ws://127.0.0.1:1" in message and "connect" in message, message


def test_a_named_served_policy_names_its_records_and_results_file(cluster, tmp_path, monkeypatch):
    """``name=`` as ``vifo run --policy-name``: the records (error records here, its server being
    down) and the default results file carry it rather than ``openpi@<url>``; a name that is
    no name, or one given to a built-in, is refused before Ray runs anything."""
    monkeypatch.chdir(tmp_path)
    for policy, name, error, says in [
        ("ws://127.0.0.1:1", "zero", ValueError, "a built-in policy's name"),
        ("ws://127.0.0.1:1", " ", ValueError, "1 to 100 printable characters"),
        ("ws://127.0.0.1:1", 3, TypeError, "name: expected a string"),
        ("zero", "mine", ValueError, "zero is built-in"),
    ]:
        with pytest.raises(error, match=says):
            run_benchmark(SELECTION, policy, name=name)
    assert not (tmp_path / "vifo-run-ray").exists()
    s = run_benchmark(SELECTION, "ws://127.0.0.1:1", name="pi05 goal/1", batch_size=4, quiet=True)
    assert s["output"] == os.path.join("vifo-run-ray", "results-pi05_goal_1.jsonl") and s["ran"] == s["errors"] == 8
    assert s["output"] == default_output("ws://127.0.0.1:1", name="pi05 goal/1")
    # Without a name, the first server's URL as given (vifo run's --policy), not its record name.
    assert default_output(["ws://h:1", "ws://h:2"], "runs", model_profile="pi05") == os.path.join("runs", "results-ws___h_1.jsonl")
    policies = {json.loads(line)["policy"] for line in open(s["output"])}
    assert policies == {"pi05 goal/1"}, policies
    assert s["policy"] == "pi05 goal/1" and s["servers"] == ["ws://127.0.0.1:1"], s


def test_batches_drawn_with_another_look_than_the_files_are_not_written(cluster, tmp_path, capsys):
    # A file whose record says LIBERO's assets (of another hash) drew it; a served policy's
    # records (errors, as its server is down, with the look the workers found) would mix looks
    # in one file: refused, and resuming retries them.
    out = tmp_path / "looks.jsonl"
    specs = _native.episode_specs(**SELECTION)
    _native.run_specs([specs[0][1]], "expert-cue", str(out))
    first = json.loads(out.read_text().splitlines()[0])
    # The built-in policy was sent no images: its record has no look, so it goes with any.
    assert first["look"] == "none", first
    served = {**first, "look": "libero-assets:0123456789abcdef", "policy": _native.policy_name("ws://127.0.0.1:1")}
    out.write_text(json.dumps(served) + "\n")
    # Every batch refused, nothing written: an exception with the reason, not a summary.
    with pytest.raises(RuntimeError, match=r"every batch \(2\) failed and no episode was written .*this run's with libero-assets:0123456789abcdef; not written"):
        run_benchmark(SELECTION, "ws://127.0.0.1:1", output=out, resume=True, batch_size=4, quiet=True)
    said = capsys.readouterr().out
    assert "episodes was drawn with look " in said, said
    assert len(out.read_text().splitlines()) == 1
    # Resuming with another policy would count the served policy's episode as done: refused,
    # as `vifo run --resume` refuses it (before, the built-in's records joined the file).
    with pytest.raises(RuntimeError, match="holds completed episodes of the policy openpi@ws://127.0.0.1:1, not of expert-cue"):
        run_benchmark(SELECTION, "expert-cue", output=out, resume=True, batch_size=4, quiet=True)
    out.write_text(json.dumps(first) + "\n")
    s = run_benchmark(SELECTION, "expert-cue", output=out, resume=True, batch_size=4, quiet=True)
    assert (s["already_done"], s["ran"], s["failed_batches"], s["missing"]) == (1, 7, 0, 0)
    with pytest.raises(ValueError, match="builtin_look=True draws no asset files"):
        run_benchmark(SELECTION, "expert-cue", output=tmp_path / "x.jsonl", assets=str(tmp_path), builtin_look=True)


def test_runs_of_two_looks_on_one_cluster_each_get_their_workers(cluster, tmp_path):
    # A Ray worker draws with the one look its process chose (where a policy is sent images: a
    # served one, here down, so each episode is an error record drawn with the run's look). A
    # later run with another look gets workers of its own instead of failing its batches.
    one = {**SELECTION, "protocols": ["original"], "episodes": 1}
    down = "ws://127.0.0.1:1"
    for n, builtin in enumerate((True, False, True)):
        s = run_benchmark(one, down, output=tmp_path / f"run{n}.jsonl", batch_size=1, quiet=True, builtin_look=builtin)
        assert (s["ran"], s["errors"], s["failed_batches"]) == (2, 2, 0), (n, s)
    # Workers whose look cannot be found fail every batch: an exception naming the cause.
    with pytest.raises(RuntimeError, match=r"every batch \(2\) failed .* the first failed: ValueError: assets=.*nowhere: no such folder"):
        run_benchmark(one, down, output=tmp_path / "lost.jsonl", batch_size=1, quiet=True, assets=str(tmp_path / "nowhere"))


def test_a_sigkilled_worker_is_recovered_without_missing_or_duplicate_episodes(tmp_path):
    """The example script on its own local cluster; `random` runs every episode to its budget,
    so the kill lands while a batch is running."""
    out = tmp_path / "run"
    run = subprocess.run(
        [sys.executable, str(ROOT / "python" / "examples" / "ray_benchmark.py"), "--policy", "random",
         "--suite", "libero_goal", "--protocol", "original", "--episodes", "2", "--workers", "2",
         "--batch-size", "2", "--kill-after", "2", "--out", str(out)],
        capture_output=True, text=True, timeout=600,
    )
    print(run.stdout[-1500:])
    assert run.returncode == 0, run.stderr[-3000:]
    assert "killed Ray worker" in run.stdout
    assert "missing: 0  duplicates: 0  failed batches: 0" in run.stdout
    records = _native.record_keys(str(out / "results-random.jsonl"))
    assert len(records) == 20 and len({k for k, _ in records}) == 20 and all(ok for _, ok in records)


def test_batches_are_spread_over_the_openpi_servers(cluster, tmp_path):
    missing = [m for m in ("openpi_client", "websockets") if importlib.util.find_spec(m) is None]
    if missing:
        print(f"SKIPPED: the scripted openpi server needs {', '.join(missing)}")
        pytest.skip(f"needs {', '.join(missing)}")
    servers, logs = [], []
    try:
        for k in range(2):
            logs.append(tmp_path / f"server{k}.jsonl")
            servers.append(subprocess.Popen(
                [sys.executable, str(ROOT / "tests" / "python" / "scripted_policy_server.py"), "--port", "0", "--log", str(logs[-1])],
                stdout=subprocess.PIPE, text=True))
        urls = [f"ws://127.0.0.1:{int(p.stdout.readline().split()[1])}" for p in servers]
        selection = {"suites": ["libero_goal"], "protocols": ["original"], "families": ["F1", "F2"], "per_family": 1, "episodes": 2}
        out = tmp_path / "served.jsonl"
        s = run_benchmark(selection, urls, output=out, batch_size=1, size=32)
    finally:
        for p in servers:
            p.kill()
            p.wait()
    n = len(_native.episode_specs(**selection))
    assert n >= 2 and (s["episodes"], s["ran"], s["missing"], s["duplicates"]) == (n, n, 0, 0)
    # Both servers answered, and every record names one policy (one row in the report).
    assert all(log.exists() and log.read_text().count("\n") > 0 for log in logs)
    policies = {json.loads(line)["policy"] for line in out.read_text().splitlines()}
    assert policies == {f"openpi@{urls[0]}"}, policies
    assert s["policy"] == f"openpi@{urls[0]}" and s["servers"] == urls, s


def test_bad_run_arguments_are_refused_before_ray_starts(tmp_path):
    """0 workers started a cluster without CPUs whose tasks never ran, a batch size of -1 ran
    nothing and reported success, and 10**7 episodes aborted the interpreter allocating them."""
    out = tmp_path / "r.jsonl"
    for kwargs, error, says in [
        ({"num_workers": 0}, ValueError, "num_workers 0"),
        ({"batch_size": 0}, ValueError, "batch_size 0"),
        ({"batch_size": -1}, ValueError, "batch_size -1: expected 0 or more"),
        ({"batch_size": 2.5}, TypeError, "batch_size: expected an integer"),
    ]:
        with pytest.raises(error, match=says):
            run_benchmark(SELECTION, "zero", output=str(out), **kwargs)
    with pytest.raises(ValueError, match="10000000 episodes per instance: at most 10000"):
        run_benchmark({**SELECTION, "episodes": 10**7}, "zero", output=str(out))
    assert not out.exists()
