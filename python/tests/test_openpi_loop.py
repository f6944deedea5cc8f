"""openpi's LIBERO client loop (python/examples/openpi_libero/main.py, only its imports switched
to libero_vifo) runs against the project's scripted openpi server (tests/python)."""

import importlib.util
import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
MAIN = ROOT / "python" / "examples" / "openpi_libero" / "main.py"
SERVER = ROOT / "tests" / "python" / "scripted_policy_server.py"
NEEDED = ["openpi_client", "websockets", "imageio", "imageio_ffmpeg", "tqdm", "tyro"]


def test_openpi_main_runs_a_suite_against_the_scripted_server(tmp_path):
    missing = [m for m in NEEDED if importlib.util.find_spec(m) is None]
    if missing:
        print(f"SKIPPED: openpi's client loop needs {', '.join(missing)} (.ci/run installs them)")
        pytest.skip(f"needs {', '.join(missing)}")
    from libero_vifo.libero import benchmark

    log = tmp_path / "requests.jsonl"
    server = subprocess.Popen([sys.executable, str(SERVER), "--port", "0", "--log", str(log)], stdout=subprocess.PIPE, text=True)
    try:
        port = int(server.stdout.readline().split()[1])
        videos = tmp_path / "videos"
        run = subprocess.run(
            [sys.executable, str(MAIN), "--args.port", str(port), "--args.host", "127.0.0.1",
             "--args.task-suite-name", "libero_spatial", "--args.num-trials-per-task", "1",
             "--args.video-out-path", str(videos)],
            capture_output=True, text=True, timeout=900, env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
    finally:
        server.kill()
        server.wait()
    assert run.returncode == 0, run.stderr[-3000:]
    assert "Total episodes: 10" in run.stderr, run.stderr[-3000:]
    assert len(list(videos.glob("rollout_*.mp4"))) == 10
    requests = [__import__("json").loads(line) for line in log.read_text().splitlines()]
    suite = benchmark.get_benchmark_dict()["libero_spatial"]()
    # Every task asked the server with its own language, openpi's shapes and dtypes.
    assert {r["prompt"] for r in requests} == {suite.get_task(i).language for i in range(10)}
    first = requests[0]["shapes"]
    assert first["observation/image"] == {"shape": [224, 224, 3], "dtype": "|u1"}
    assert first["observation/wrist_image"] == {"shape": [224, 224, 3], "dtype": "|u1"}
    assert first["observation/state"] == {"shape": [8], "dtype": "<f8"}
    # The scripted actions (the state plus small offsets) finish no task: every episode runs
    # its whole budget (220 steps, a request per 5) and the loop, which counts a `done` as a
    # success, must count none (the end of the budget is not `done`, as in LIBERO).
    assert len(requests) == 10 * 220 // 5
    assert "# successes: 0 (0.0%)" in run.stderr and "Total success rate: 0.0" in run.stderr, run.stderr[-3000:]
    assert len(list(videos.glob("rollout_*_failure.mp4"))) == 10
    print(f"openpi loop: {len(requests)} requests over 10 tasks; "
          f"{run.stderr.count('Caught exception')} episodes ended by an exception")
