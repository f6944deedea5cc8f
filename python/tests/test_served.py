"""Served policies of every format from Python, as ``vifo run --policy URL --model-profile P``
takes them (only openpi's ws:// was accepted before)."""

import importlib.util
import json
import pathlib
import subprocess
import sys

import pytest

from libero_vifo import _native

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_an_openvla_oft_server_runs_an_episode_under_its_profile(tmp_path):
    if importlib.util.find_spec("json_numpy") is None:
        print("SKIPPED: the scripted OpenVLA-OFT server needs json-numpy")
        pytest.skip("needs json-numpy")
    server = subprocess.Popen([sys.executable, str(ROOT / "tests" / "python" / "format_servers.py"), "openvla-oft", "--port", "0"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = f"http://127.0.0.1:{int(server.stdout.readline().split()[1])}/act"
        ((_, spec),) = _native.episode_specs(suites=["libero_goal"], protocols=["original"], episodes=1, sample=1)
        out = tmp_path / "oft.jsonl"
        # name= names a server's records, as vifo run --policy-name.
        assert _native.run_specs([spec], url, str(out), model_profile="openvla-oft", name="oft-goal") == (1, 0, 0)
    finally:
        server.kill()
        _, errors = server.communicate()
    assert "CHECK FAILED" not in errors, errors
    (record,) = [json.loads(line) for line in open(out)]
    assert record["policy"] == "oft-goal" and record["outcome"]["status"] == "completed", record


def test_served_policies_are_checked_and_named_as_vifo_run_names_them():
    assert _native.check_policy("ws://h:8000") == ("openpi@ws://h:8000", "ws://h:8000", False)
    assert _native.check_policy("ws://h:8000", "pi05") == ("pi05@ws://h:8000", "ws://h:8000", False)
    assert _native.check_policy("http://h:8777/act") == ("openvla-oft@http://h:8777/act", "http://h:8777/act", False)
    assert _native.check_policy("tcp://h:10086", "xiaomi") == ("xiaomi@tcp://h:10086", "tcp://h:10086", True)
    assert _native.check_policy("expert-cue") == ("expert-cue", "expert-cue", False)
    # name= as vifo run --policy-name: the records and the results file carry it instead of
    # <profile>@<url> and the URL.
    assert _native.check_policy("tcp://h:10086", "xiaomi", "x0-libero") == ("x0-libero", "x0-libero", True)
    for policy, profile, says in (
        ("zero", "pi05", "zero is built-in"),
        ("ws://h:8000", "gpt-9", "unknown model_profile"),
        ("tcp://h", None, "no port"),
        ("h:8000", None, "unknown policy"),
    ):
        with pytest.raises(ValueError, match=says):
            _native.check_policy(policy, profile)


def test_ray_refuses_a_server_that_holds_one_client_on_several_workers(tmp_path):
    pytest.importorskip("ray")
    from libero_vifo.ray import run_benchmark

    with pytest.raises(ValueError, match="holds one client at a time; give num_workers=1"):
        run_benchmark({"suites": ["libero_goal"]}, "tcp://127.0.0.1:1", model_profile="xiaomi", num_workers=2,
                      output=tmp_path / "x.jsonl")
    assert not (tmp_path / "x.jsonl").exists()
