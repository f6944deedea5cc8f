"""libero_vifo.gym: registration, spaces, gymnasium's env checker, and the same episode as
the Rust env (upright images)."""

import warnings

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

import libero_vifo.gym  # noqa: E402,F401  (registers the environments)
from gymnasium.utils.env_checker import check_env  # noqa: E402
from libero_vifo import _native  # noqa: E402


def test_forty_tasks_and_every_cue_variant_are_registered():
    ids = [i for i in gymnasium.registry if i.startswith("libero_vifo/")]
    assert len(ids) == 40 + 3 * 1347
    assert "libero_vifo/libero_10-9" in ids
    assert "libero_vifo/libero_goal-0-conflict-F7-glow_halo" in ids
    for i in ids:
        assert gymnasium.envs.registration.parse_env_id(i)[1] == i.split("/")[1], i


def test_a_cue_variant_equals_the_rust_env_with_that_cue():
    env = gymnasium.make("libero_vifo/libero_goal-0-no_language-F4-goal_inset", size=32)
    obs, info = env.reset(options={"init_state": 2})
    assert info["language"] == "" and env.unwrapped.language_instruction == ""
    ref = _native.reference_episode("libero_goal", 0, 2, 32, [], upright=True, condition="no_language", cue="libero_goal/0/F4/goal_inset")
    plain = _native.reference_episode("libero_goal", 0, 2, 32, [], upright=True)
    assert obs["agentview_image"].tobytes() == ref[0][0]["agentview_image"].tobytes()
    assert obs["agentview_image"].tobytes() != plain[0][0]["agentview_image"].tobytes()
    made = gymnasium.make("libero_vifo/libero_goal-0", size=32, cue="libero_goal/0/F4/goal_inset", language_condition="no_language")
    assert made.reset(options={"init_state": 2})[0]["agentview_image"].tobytes() == obs["agentview_image"].tobytes()


def test_check_env_is_clean():
    env = gymnasium.make("libero_vifo/libero_goal-0", size=32)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=False)
    env.close()


def test_a_gym_episode_equals_the_rust_env():
    env = gymnasium.make("libero_vifo/libero_goal-0", size=32)
    obs, info = env.reset(options={"init_state": 4})
    assert info["init_state"] == 4 and env.observation_space.contains(obs)
    rng = np.random.default_rng(1)
    actions = [rng.uniform(-1, 1, 7).astype(np.float32) for _ in range(6)]
    ref = _native.reference_episode("libero_goal", 0, 4, 32, [a.astype(np.float64).tolist() for a in actions], upright=True)
    assert obs["agentview_image"].tobytes() == ref[0][0]["agentview_image"].tobytes()
    for a, (ro, rr, rd) in zip(actions, ref[1:]):
        obs, reward, terminated, truncated, _ = env.step(a)
        assert obs["robot0_eye_in_hand_image"].tobytes() == ro["robot0_eye_in_hand_image"].tobytes()
        assert obs["robot0_eef_pos"].tobytes() == ro["robot0_eef_pos"].tobytes()
        assert (reward, terminated or truncated) == (rr, rd)
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(6))
