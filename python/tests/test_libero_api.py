"""libero_vifo.libero as openpi's examples/libero/main.py uses LIBERO: names, shapes, dtypes,
the episode equal to the Rust env's bit for bit, and clear exceptions for wrong arguments."""

import importlib.metadata
import math
import os
import pathlib
import pickle
import re
import threading

import numpy as np
import pytest

from libero_vifo import _native
from libero_vifo.libero import benchmark, get_libero_path
from libero_vifo.libero.envs import OffScreenRenderEnv

SIZE = 64
DUMMY = [0.0] * 6 + [-1.0]


def make_env(suite="libero_goal", i=0, size=SIZE, **cue):
    task = benchmark.get_benchmark_dict()[suite]().get_task(i)
    path = pathlib.Path(get_libero_path("bddl_files")) / task.problem_folder / task.bddl_file
    return OffScreenRenderEnv(bddl_file_name=path, camera_heights=size, camera_widths=size, **cue)


def test_the_four_suites_and_their_tasks():
    d = benchmark.get_benchmark_dict()
    assert set(d) == {"libero_spatial", "libero_object", "libero_goal", "libero_10"}
    # openpi's LIBERO script lists libero_90: a KeyError that names the suites, not a bare one.
    with pytest.raises(KeyError, match="unknown suite 'libero_90'; known: libero_spatial"):
        d["libero_90"]
    assert d.get("libero_90") is None
    for name, cls in d.items():
        suite = cls()
        assert suite.n_tasks == 10
        for i in range(suite.n_tasks):
            task = suite.get_task(i)
            assert task.problem_folder == name
            assert task.bddl_file == task.name + ".bddl"
            assert task.language and task.language == task.language.strip()
            assert len(suite.get_task_init_states(i)) == 50
    assert benchmark.get_benchmark_dict()["libero_goal"]().get_task(0).language == "open the middle drawer of the cabinet"
    with pytest.raises(IndexError, match="tasks 0 to 9"):
        d["libero_goal"]().get_task(10)
    with pytest.raises(KeyError, match="unknown LIBERO path"):
        get_libero_path("nope")


def test_the_rest_of_libero_s_benchmark_api_and_its_index_types():
    suite = benchmark.get_benchmark_dict()["libero_goal"]()
    # Task ids sharded with numpy (np.array_split) are numpy integers, which LIBERO's lists take.
    assert suite.get_task(np.int64(3)) == suite.get_task(3)
    assert suite.get_task_init_states(np.int32(3)) == suite.get_task_init_states(3)
    for bad in ("3", 3.0, True):
        with pytest.raises(TypeError, match="task: expected an integer"):
            suite.get_task(bad)
    with pytest.raises(ValueError, match="task -1: expected 0 or more"):
        suite.get_task(-1)
    assert suite.get_task_bddl_file_path(0) == os.path.join(get_libero_path("bddl_files"), "libero_goal", suite.get_task(0).bddl_file)
    assert make_env(size=16).language_instruction == suite.get_task(0).language
    assert suite.get_task_bddl_files() == [suite.get_task(i).bddl_file for i in range(10)]
    assert len(suite.get_task_problems()) == 10
    assert suite.get_task_demonstration(2) == f"libero_goal/{suite.get_task(2).name}_demo.hdf5"
    suite.set_task_embs(["e0", "e1"])
    assert suite.get_task_emb(1) == "e1"
    # Suites pickle with the standard pickle (multiprocessing), as LIBERO's module-level classes do.
    again = pickle.loads(pickle.dumps(suite))
    assert type(again) is type(suite) and again.get_task(0) == suite.get_task(0)


def test_observation_keys_dtypes_shapes():
    env = make_env()
    env.seed(0)
    env.reset()
    obs = env.set_init_state(benchmark.get_benchmark_dict()["libero_goal"]().get_task_init_states(0)[3])
    for key in ("agentview_image", "robot0_eye_in_hand_image"):
        assert obs[key].dtype == np.uint8 and obs[key].shape == (SIZE, SIZE, 3)
        assert obs[key].std() > 0
    for key, n in [("robot0_eef_pos", 3), ("robot0_eef_quat", 4), ("robot0_gripper_qpos", 2), ("robot0_joint_pos", 7),
                   ("robot0_joint_vel", 7), ("robot0_gripper_qvel", 2)]:
        assert obs[key].dtype == np.float64 and obs[key].shape == (n,), key
    assert abs(np.linalg.norm(obs["robot0_eef_quat"]) - 1) < 1e-9
    assert np.allclose(obs["robot0_joint_pos_cos"], np.cos(obs["robot0_joint_pos"]))
    assert obs["akita_black_bowl_1_pos"].shape == (3,) and obs["akita_black_bowl_1_quat"].shape == (4,)
    obs, reward, done, info = env.step(DUMMY)
    assert (reward, done, info) == (0.0, False, {"language_success": False, "cue_success": None})
    # The velocities are the joints' own: moving the hand, each joint that moves a good deal in
    # a step turns the way its velocity says.
    before = obs["robot0_joint_pos"]
    obs, *_ = env.step([0.5, 0.3, -0.4, 0.0, 0.0, 0.0, 1.0])
    moved = obs["robot0_joint_pos"] - before
    big = np.abs(moved) > 1e-3
    assert big.any() and np.array_equal(np.sign(moved[big]), np.sign(obs["robot0_joint_vel"][big])), (moved, obs["robot0_joint_vel"])
    assert np.any(obs["robot0_gripper_qvel"] != 0)
    assert env.check_success() is False
    assert env.get_sim_state().dtype == np.float64
    env.close()


@pytest.mark.parametrize(
    "condition, cue",
    [
        ("original", None),
        ("authorized", "libero_goal/0/F1/caption_bar"),
        ("conflict", "libero_goal/0/F7/glow_halo"),
        ("no_language", "libero_goal/0/F4/goal_inset"),
    ],
)
def test_an_openpi_style_episode_equals_the_rust_env_bit_for_bit(condition, cue):
    """openpi's loop: 10 dummy steps after set_init_state, then policy actions. The Rust
    reference resets with its settle steps (as `vifo run`'s rollout does) and takes the same
    policy actions; under a cue protocol both draw the cue."""
    rng = np.random.default_rng(5)
    actions = [list(rng.uniform(-1, 1, 7)) for _ in range(12)]
    reference = _native.reference_episode("libero_goal", 0, 7, SIZE, actions, condition=condition, cue=cue)
    env = make_env(cue=cue, language_condition=condition)
    assert env.language_condition == condition
    if condition == "original":
        assert env.language_instruction == "open the middle drawer of the cabinet"
    elif condition == "authorized":
        assert env.language_instruction == "follow the visual cue in the observation and complete the task"
    elif condition == "no_language":
        assert env.language_instruction == ""
    else:
        assert env.language_instruction not in ("", "open the middle drawer of the cabinet")
    env.reset()
    obs = env.set_init_state(benchmark.get_benchmark_dict()["libero_goal"]().get_task_init_states(0)[7])
    for _ in range(10):
        obs, reward, done, _ = env.step(DUMMY)
    steps = [(obs, reward, done)]
    for a in actions:
        obs, reward, done, _ = env.step(a)
        steps.append((obs, reward, done))
    assert len(steps) == len(reference)
    for t, ((o, r, d), (ro, rr, rd)) in enumerate(zip(steps, reference)):
        assert o.keys() == ro.keys(), t
        for key in o:
            assert o[key].dtype == ro[key].dtype and o[key].tobytes() == ro[key].tobytes(), (t, key)
        assert (r, d) == (rr, rd), t
    # The robot moved: the comparison is of different states, not of one frame.
    assert not np.array_equal(steps[0][0]["robot0_eef_pos"], steps[-1][0]["robot0_eef_pos"])
    if cue is not None:
        # The cue is in the picture: the same state without it looks different.
        plain = _native.reference_episode("libero_goal", 0, 7, SIZE, actions)
        assert plain[-1][0]["agentview_image"].tobytes() != steps[-1][0]["agentview_image"].tobytes()
        assert plain[-1][0]["robot0_eef_pos"].tobytes() == steps[-1][0]["robot0_eef_pos"].tobytes()


def test_cue_arguments_are_checked():
    with pytest.raises(ValueError, match=r"unknown cue instance .*no variant .no_such_arrow.*libero_vifo\.cue_instances\(\)"):
        make_env(cue="libero_goal/0/F2/no_such_arrow")
    with pytest.raises(ValueError, match="belongs to task libero_goal/4"):
        make_env(cue="libero_goal/4/F2/straight_arrow_red", language_condition="conflict")
    with pytest.raises(ValueError, match='language_condition "nope"'):
        make_env(cue="libero_goal/0/F1/caption_bar", language_condition="nope")
    with pytest.raises(ValueError, match="needs cue="):
        make_env(language_condition="authorized")
    with pytest.raises(ValueError, match="original protocol shows no cue"):
        make_env(cue="libero_goal/0/F1/caption_bar", language_condition="original")
    with pytest.raises(TypeError, match="instance id"):
        make_env(cue=3)
    env = make_env(cue="libero_goal/0/F1/caption_bar")
    assert (env.language_condition, env.cue) == ("authorized", "libero_goal/0/F1/caption_bar")
    ids = __import__("libero_vifo").cue_instances()
    assert len(ids) == 1347 and "libero_goal/0/F1/caption_bar" in ids
    assert len(__import__("libero_vifo").cue_instances("full")) == 1671


def test_a_cue_can_face_the_model():
    """openpi's loop sends ``raw[::-1, ::-1]``: the upright frame mirrored left-right. With
    ``cue_facing="model"`` the caption reads the right way there; the scene is the same."""
    caption = "libero_goal/0/F1/caption_bar"
    with pytest.raises(ValueError, match='cue_facing "sideways"'):
        make_env(cue=caption, cue_facing="sideways")
    spec = _native.episode_specs(suites=["libero_goal"], protocols=["authorized"], episodes=1)[0][1]
    with pytest.raises(ValueError, match='cue_facing "sideways"'):
        _native.run_specs([spec], "zero", os.devnull, cue_facing="sideways")
    seen = {}
    for facing in ("upright", "model"):
        env = make_env(cue=caption, cue_facing=facing)
        env.reset()
        for _ in range(10):
            obs, _, _, _ = env.step(DUMMY)
        seen[facing] = obs["agentview_image"][::-1, ::-1]
    # The caption runs along the bottom of the picture; above it nothing changes.
    assert not np.array_equal(seen["upright"], seen["model"])
    assert np.array_equal(seen["upright"][: SIZE // 2], seen["model"][: SIZE // 2])


def test_images_are_bottom_up_as_robosuite_returns_them():
    env = make_env()
    env.reset()
    for _ in range(10):
        obs, _, _, _ = env.step(DUMMY)
    upright = _native.reference_episode("libero_goal", 0, 0, SIZE, [], upright=True)[0][0]
    for key in ("agentview_image", "robot0_eye_in_hand_image"):
        assert not np.array_equal(upright[key], obs[key])
        assert np.array_equal(upright[key][::-1], obs[key]), key


def test_done_is_success_only_as_in_libero():
    """openpi's and OpenVLA's loops take the budget's last step and count a ``done`` as a
    success: the end of the budget must not read as ``done``."""
    suite = benchmark.get_benchmark_dict()["libero_goal"]()
    env = make_env(size=16)
    env.reset()
    env.set_init_state(suite.get_task_init_states(0)[0])
    steps = suite.get_max_steps() + 10
    for t in range(steps):
        _, reward, done, _ = env.step(DUMMY)
        assert (reward, done, env.check_success()) == (0.0, False, False), t
    with pytest.raises(RuntimeError, match=f"episode is over \\({steps} steps\\)"):
        env.step(DUMMY)


def test_info_tells_the_language_task_from_the_cue_task():
    """Under conflict ``done`` is either task; the info says which (LFR against UVF), and
    ``None`` where the protocol has no such task."""
    suite = benchmark.get_benchmark_dict()["libero_goal"]()
    for condition, cue, defined in [("original", None, (True, False)), ("conflict", "libero_goal/0/F7/glow_halo", (True, True)),
                                    ("no_language", "libero_goal/0/F4/goal_inset", (False, True))]:
        env = make_env(size=16, cue=cue, language_condition=condition)
        env.reset()
        env.set_init_state(suite.get_task_init_states(0)[0])
        _, _, done, info = env.step(DUMMY)
        flags = (info["language_success"], info["cue_success"])
        assert tuple(f is not None for f in flags) == defined, (condition, info)
        assert done == any(bool(f) for f in flags)


@pytest.mark.parametrize(
    "action, match",
    [
        ([0.0] * 6, "length|7"),
        ([0.0] * 8, "length|7"),
        ([0.0] * 6 + [math.nan], "gripper|NaN|finite"),
        ([math.inf] + [0.0] * 6, "finite|inf"),
        (np.zeros((1, 7)), r"shape \(1, 7\): expected \(7,\)"),
        (np.zeros((7, 1)), r"shape \(7, 1\): expected \(7,\)"),
    ],
)
def test_bad_actions_raise_value_error_and_change_nothing(action, match):
    env = make_env()
    before = env.reset()
    with pytest.raises(ValueError, match=match):
        env.step(action)
    after, _, _, _ = env.step(DUMMY)
    fresh = make_env()
    fresh.reset()
    expected, _, _, _ = fresh.step(DUMMY)
    assert after["agentview_image"].tobytes() == expected["agentview_image"].tobytes()
    assert before["robot0_eef_pos"].shape == (3,)


def test_wrong_arguments_raise_clear_exceptions():
    with pytest.raises(ValueError, match="no built-in task"):
        OffScreenRenderEnv(bddl_file_name="libero_goal/not_a_task.bddl", camera_heights=64, camera_widths=64)
    # A task's file under another suite's folder is refused (it resolved by name before); a copy
    # outside LIBERO's suite folders still resolves by its name.
    goal0 = benchmark.get_benchmark_dict()["libero_goal"]().get_task(0).bddl_file
    with pytest.raises(ValueError, match=f"task '{goal0[:-5]}' is in libero_goal, not in 'libero_10'"):
        OffScreenRenderEnv(bddl_file_name=f"libero_10/{goal0}", camera_heights=64, camera_widths=64)
    assert OffScreenRenderEnv(bddl_file_name=f"my_copies/{goal0}", camera_heights=16, camera_widths=16)._task["suite"] == "libero_goal"
    with pytest.raises(ValueError, match="square"):
        make_env().__class__(bddl_file_name="x.bddl", camera_heights=64, camera_widths=32)
    with pytest.raises(ValueError, match="camera size"):
        _native.NativeEnv("libero_goal", 0, 0)
    with pytest.raises(ValueError, match="camera_heights -5: expected 0 or more"):
        make_env(size=-5)
    with pytest.raises(TypeError, match="real numbers"):
        make_env(size=16).step(np.zeros(7, dtype=complex))
    with pytest.raises(ValueError, match="unknown task"):
        _native.NativeEnv("libero_goal", 42, 64)
    env = make_env()
    with pytest.raises(RuntimeError, match="reset"):
        env.step(DUMMY)
    with pytest.raises(RuntimeError, match="call reset first"):
        env.check_success()
    spatial = benchmark.get_benchmark_dict()["libero_spatial"]().get_task_init_states(0)[0]
    with pytest.raises(ValueError, match="libero_spatial/0"):
        env.set_init_state(spatial)
    with pytest.raises(TypeError, match="get_task_init_states"):
        env.set_init_state(np.zeros(10))
    with pytest.raises(ValueError, match="initial state 50"):
        _native.NativeEnv("libero_goal", 0, 16).reset(50)
    with pytest.raises(ValueError, match="init_state.index -1: expected 0 or more"):
        env.set_init_state(benchmark.InitState("libero_goal", 0, -1))
    env.reset()
    env.close()
    for call in (env.reset, lambda: env.step(DUMMY), env.check_success, env.get_sim_state):
        with pytest.raises(RuntimeError, match="closed"):
            call()


def test_threads_step_envs_concurrently_with_the_same_results():
    """The GIL is released while stepping: two threads give the bytes one thread gives."""

    def run(out, k):
        env = make_env(size=32)
        env.reset()
        for _ in range(15):
            obs, _, _, _ = env.step([0.5, 0.0, -0.2, 0.0, 0.0, 0.1, 1.0])
        out[k] = obs["agentview_image"].tobytes() + obs["robot0_eef_pos"].tobytes()

    serial, threaded = {}, {}
    run(serial, 0)
    threads = [threading.Thread(target=run, args=(threaded, k)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert threaded[0] == threaded[1] == serial[0]


def test_the_installed_package_has_the_workspace_version_and_only_its_real_extras():
    # pyproject.toml once listed `dynamic` under the extras: the wheel then offered an extra
    # "dynamic" that required a package called "version".
    meta = importlib.metadata.metadata("libero_vifo")
    assert sorted(meta.get_all("Provides-Extra")) == ["gym", "ray"]
    cargo = (pathlib.Path(__file__).resolve().parents[2] / "Cargo.toml").read_text()
    workspace_version = re.search(r'^version = "([^"]+)"', cargo, re.M).group(1)
    assert meta["Version"] == workspace_version


def test_camera_names_and_use_camera_obs_pick_the_images_drawn():
    """robosuite's camera arguments: only the cameras named are drawn (one `<name>_image` key
    each), none with `use_camera_obs=False`, and the episode is the same whichever are drawn."""
    init = benchmark.get_benchmark_dict()["libero_goal"]().get_task_init_states(0)[2]
    envs = {
        "both": make_env(),
        "agentview": make_env(camera_names="agentview"),
        "wrist": make_env(camera_names=["robot0_eye_in_hand", "robot0_eye_in_hand"]),
        "none": make_env(use_camera_obs=False, camera_names=["agentview"]),
    }
    actions = [DUMMY] * 3 + [[0.4, -0.3, 0.2, 0.0, 0.0, 0.1, 1.0]] * 6
    last = {}
    for name, env in envs.items():
        env.set_init_state(init)
        for a in actions:
            last[name], _, _, _ = env.step(a)
        env.close()
    images = {name: sorted(k for k in obs if k.endswith("_image")) for name, obs in last.items()}
    assert images == {
        "both": ["agentview_image", "robot0_eye_in_hand_image"],
        "agentview": ["agentview_image"],
        "wrist": ["robot0_eye_in_hand_image"],
        "none": [],
    }
    both = last["both"]
    assert last["agentview"]["agentview_image"].tobytes() == both["agentview_image"].tobytes()
    assert last["wrist"]["robot0_eye_in_hand_image"].tobytes() == both["robot0_eye_in_hand_image"].tobytes()
    vectors = sorted(k for k in both if not k.endswith("_image"))
    for name, obs in last.items():
        assert sorted(k for k in obs if not k.endswith("_image")) == vectors, name
        for k in vectors:
            assert obs[k].tobytes() == both[k].tobytes(), (name, k)
    with pytest.raises(ValueError, match="camera_names: unknown camera 'frontview'; expected agentview or robot0_eye_in_hand"):
        make_env(camera_names=["agentview", "frontview"])
    with pytest.raises(TypeError, match="camera_names: expected a camera name or a list of them"):
        make_env(camera_names=5)
