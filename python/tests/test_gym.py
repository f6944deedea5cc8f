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


def test_a_cue_facing_the_model_is_the_same_in_the_single_and_the_vector_env():
    caption = "libero_goal/0/F1/caption_bar"
    frames = {}
    for facing in ("upright", "model"):
        single = gymnasium.make("libero_vifo/libero_goal-0", size=32, cue=caption, cue_facing=facing)
        vector = libero_vifo.gym.LiberoVifoVectorEnv(2, "libero_goal", 0, size=32, cue=caption, cue_facing=facing)
        one = single.reset(options={"init_state": 1})[0]["agentview_image"]
        many = vector.reset(options={"init_state": [1, 1]})[0]["agentview_image"]
        assert one.tobytes() == many[0].tobytes() == many[1].tobytes(), facing
        frames[facing] = one
        vector.close()
    assert frames["upright"].tobytes() != frames["model"].tobytes()
    with pytest.raises(ValueError, match='cue_facing "up"'):
        libero_vifo.gym.LiberoVifoVectorEnv(1, "libero_goal", 0, size=32, cue=caption, cue_facing="up")


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


def test_the_vector_env_steps_the_single_envs_episodes_on_any_thread_count():
    from libero_vifo.gym import LiberoVifoVectorEnv

    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, (5, 2, 7))
    episodes = [("libero_goal", 0), ("libero_goal", 0, "conflict", "libero_goal/0/F7/glow_halo")]
    refs = [
        _native.reference_episode("libero_goal", 0, 4, 32, actions[:, 0].tolist(), upright=True),
        _native.reference_episode("libero_goal", 0, 9, 32, actions[:, 1].tolist(), upright=True, condition="conflict", cue="libero_goal/0/F7/glow_halo"),
    ]
    seen = []
    for threads in (1, 2):
        env = LiberoVifoVectorEnv(episodes=episodes, size=32, threads=threads)
        assert env.num_envs == 2 and env.action_space.shape == (2, 7)
        obs, info = env.reset(options={"init_state": [4, 9]})
        assert env.observation_space.contains(obs) and list(info["init_state"]) == [4, 9]
        frames = [obs["agentview_image"].tobytes()]
        for t in range(5):
            obs, reward, terminated, truncated, info = env.step(actions[t])
            for k in range(2):
                ro, rr, rd = refs[k][t + 1]
                assert obs["robot0_eye_in_hand_image"][k].tobytes() == ro["robot0_eye_in_hand_image"].tobytes(), (threads, t, k)
                assert obs["robot0_eef_pos"][k].tobytes() == ro["robot0_eef_pos"].tobytes()
                assert (reward[k], terminated[k] or truncated[k]) == (rr, rd)
            frames.append(obs["agentview_image"].tobytes())
        seen.append(frames)
        with pytest.raises(ValueError, match=r"shape \(2, 6\)"):
            env.step(np.zeros((2, 6)))
        bad = np.zeros((2, 7))
        bad[1, 3] = np.nan
        with pytest.raises(ValueError, match="env 1: element 3 is NaN"):
            env.step(bad)
        env.close()
    assert seen[0] == seen[1]
    assert env.unwrapped is env


def test_make_vec_builds_the_vector_env_and_it_autoresets_next_step():
    envs = gymnasium.make_vec("libero_vifo/libero_goal-0", num_envs=2, vectorization_mode="vector_entry_point", size=16)
    obs, info = envs.reset(seed=1)
    assert obs["agentview_image"].shape == (2, 16, 16, 3)
    # Force the end of sub-env 1's episode, then check the next step restarts it.
    envs.unwrapped._autoreset[1] = True
    obs, reward, terminated, truncated, info = envs.step(np.zeros((2, 7), dtype=np.float32))
    assert info["_init_state"].tolist() == [False, True] and reward[1] == 0.0
    envs.close()
    # gymnasium's own arguments: frames to look at, and a step limit below the suite's budget.
    envs = gymnasium.make_vec("libero_vifo/libero_goal-0", num_envs=2, vectorization_mode="vector_entry_point", size=16,
                              render_mode="rgb_array", max_episode_steps=3)
    obs, _ = envs.reset(seed=1)
    assert envs.render().tobytes() == obs["agentview_image"].tobytes()
    for t in range(3):
        obs, reward, terminated, truncated, info = envs.step(np.zeros((2, 7), dtype=np.float32))
        assert truncated.tolist() == [t == 2] * 2 and not terminated.any()
    assert envs.render().shape == (2, 16, 16, 3) and envs.render().tobytes() == obs["agentview_image"].tobytes()
    obs, reward, terminated, truncated, info = envs.step(np.zeros((2, 7), dtype=np.float32))
    assert info["_init_state"].all() and not truncated.any()
    envs.close()
    with pytest.raises(ValueError, match="render_mode 'human'"):
        gymnasium.make_vec("libero_vifo/libero_goal-0", num_envs=1, vectorization_mode="vector_entry_point", size=16, render_mode="human")


def test_a_fortran_ordered_batch_gives_each_env_its_own_row():
    """The native step read a Fortran-ordered batch in memory order: env 0 got values of env 1."""
    from libero_vifo.gym import LiberoVifoVectorEnv

    actions = np.zeros((2, 7))
    actions[0, :3] = [0.5, -0.5, 0.3]
    ends = []
    for batch in (np.ascontiguousarray(actions), np.asfortranarray(actions)):
        venv = LiberoVifoVectorEnv(num_envs=2, suite="libero_goal", task=0, size=16)
        venv.reset(options={"init_state": 0})
        obs = [venv._env.step(batch, [None, None])[0] for _ in range(3)][-1]
        ends.append(obs["robot0_eef_pos"].tobytes())
        venv.close()
    assert ends[0] == ends[1]


def test_a_refused_step_draws_no_restart():
    """A NaN batch after an episode ended used up the seeded draws of the restarts it would
    have made, so the same seed restarted other initial states."""
    restarts = []
    for refuse in (False, True):
        envs = gymnasium.make_vec("libero_vifo/libero_goal-0", num_envs=2, vectorization_mode="vector_entry_point", size=16,
                                  max_episode_steps=1)
        envs.reset(seed=5)
        envs.step(np.zeros((2, 7)))
        if refuse:
            bad = np.zeros((2, 7))
            bad[0, 0] = np.nan
            with pytest.raises(ValueError, match="NaN"):
                envs.step(bad)
        info = envs.step(np.zeros((2, 7)))[4]
        restarts.append(info["init_state"].tolist())
        envs.close()
    assert restarts[0] == restarts[1]
    with pytest.raises(TypeError, match="task: expected an integer, got True"):
        gymnasium.make("libero_vifo/libero_goal-0", task=True)


def test_infos_tell_the_language_task_from_the_cue_task():
    from libero_vifo.gym import LiberoVifoVectorEnv

    env = gymnasium.make("libero_vifo/libero_goal-0-conflict-F7-glow_halo", size=16)
    env.reset(options={"init_state": 0})
    _, _, terminated, _, info = env.step(np.zeros(7))
    assert info["language_success"] is False and info["cue_success"] is False and not terminated
    plain = gymnasium.make("libero_vifo/libero_goal-0", size=16)
    plain.reset(options={"init_state": 0})
    assert plain.step(np.zeros(7))[4]["cue_success"] is None
    episodes = [("libero_goal", 0), ("libero_goal", 0, "conflict", "libero_goal/0/F7/glow_halo")]
    venv = LiberoVifoVectorEnv(episodes=episodes, size=16)
    venv.reset(options={"init_state": 0})
    _, _, _, _, info = venv.step(np.zeros((2, 7)))
    assert info["_language_success"].tolist() == [True, True] and info["_cue_success"].tolist() == [False, True]
    assert not info["language_success"].any() and not info["cue_success"].any()
    venv.close()


def test_a_sub_env_whose_physics_blows_up_is_truncated_with_the_error_and_the_others_step_on():
    from libero_vifo.gym import LiberoVifoVectorEnv

    env = LiberoVifoVectorEnv(suite="libero_goal", task=0, num_envs=3, size=16, threads=2)
    env.reset(options={"init_state": 0})
    actions = np.zeros((3, 7))
    before, *_ = env.step(actions)
    env._env._throw_object(1, 400.0)
    obs, reward, terminated, truncated, info = env.step(actions)
    assert truncated.tolist() == [False, True, False] and not terminated.any()
    assert info["_error"].tolist() == [False, True, False]
    assert info["error"][1].startswith("physics blew up at step 2: ") and "exceeds" in info["error"][1]
    # The others stepped (as the reference did), the broken one kept its last observation.
    ref = _native.reference_episode("libero_goal", 0, 0, 16, [[0.0] * 7] * 2, upright=True)
    for k in (0, 2):
        assert obs["robot0_eye_in_hand_image"][k].tobytes() == ref[2][0]["robot0_eye_in_hand_image"].tobytes()
    assert obs["agentview_image"][1].tobytes() == before["agentview_image"][1].tobytes()
    # Next step: autoreset restarts it, the others go on.
    obs, reward, terminated, truncated, info = env.step(actions)
    assert info["_init_state"].tolist() == [False, True, False] and "error" not in info
    env.close()


def test_wrong_arguments_raise_clear_exceptions():
    from libero_vifo.gym import LiberoVifoEnv, LiberoVifoVectorEnv

    with pytest.raises(ValueError, match="unknown task libero_goal/42"):
        LiberoVifoEnv("libero_goal", 42, size=16)
    with pytest.raises(ValueError, match="unknown task libero_goal/42"):
        LiberoVifoVectorEnv(episodes=[("libero_goal", 0), ("libero_goal", 42)], size=16)
    with pytest.raises(ValueError, match="unknown cue instance"):
        LiberoVifoEnv("libero_goal", 0, size=16, cue="libero_goal/0/F9/nothing")
    with pytest.raises(ValueError, match="needs cue="):
        LiberoVifoVectorEnv(suite="libero_goal", task=0, size=16, language_condition="conflict")
    with pytest.raises(ValueError, match="threads -1: expected 0 or more"):
        LiberoVifoVectorEnv(suite="libero_goal", task=0, size=16, threads=-1)
    with pytest.raises(ValueError, match="size -16: expected 0 or more"):
        LiberoVifoEnv("libero_goal", 0, size=-16)
    # Past what Rust takes: an OverflowError that named nothing before.
    with pytest.raises(ValueError, match=r"size 1180591620717411303424: expected at most 2147483647"):
        LiberoVifoEnv("libero_goal", 0, size=2**70)
    with pytest.raises(TypeError, match="num_envs: expected an integer"):
        LiberoVifoVectorEnv(num_envs="2", suite="libero_goal", task=0, size=16)
    # A count no machine holds was Python's bare MemoryError (a list of 10**9 episodes).
    assert _native.MAX_ENVS == 1024
    for wrong in (10**9, 2**70, 1025, 0, -3):
        with pytest.raises(ValueError, match=rf"^num_envs {wrong}: expected 1 to 1024$"):
            LiberoVifoVectorEnv(num_envs=wrong, suite="libero_goal", task=0, size=16)
    with pytest.raises(ValueError, match="1025 episodes: a vector env takes 1 to 1024"):
        _native.NativeVectorEnv([("libero_goal", 0, "original", None)] * 1025, 16, 1)
    with pytest.raises(ValueError, match="0 episodes: a vector env takes 1 to 1024"):
        LiberoVifoVectorEnv(episodes=[], size=16)
    env = LiberoVifoEnv("libero_goal", 0, size=16)
    env.reset(options={"init_state": 0})
    with pytest.raises(ValueError, match="not finite|NaN"):
        env.step(np.array([0, 0, 0, 0, 0, 0, np.nan]))
    with pytest.raises(ValueError, match="init_state -1: expected 0 or more"):
        env.reset(options={"init_state": -1})
    for silently_converted_before in ("3", 3.9):
        with pytest.raises(TypeError, match="init_state: expected an integer"):
            env.reset(options={"init_state": silently_converted_before})
    assert env.reset(options={"init_state": np.int64(3)})[1]["init_state"] == 3
    env.close()
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros(7))
    vec = LiberoVifoVectorEnv(suite="libero_goal", task=0, num_envs=2, size=16)
    vec.reset(options={"init_state": 0})
    with pytest.raises(ValueError, match="initial state 50"):
        vec.reset(options={"init_state": [0, 50]})
    with pytest.raises(ValueError, match="init_state -1: expected 0 or more"):
        vec.reset(options={"init_state": [0, -1]})
    with pytest.raises(ValueError, match=r"actions of shape \(3, 7\): expected \(2, 7\)"):
        vec.step(np.zeros((3, 7)))
    vec.close()
    with pytest.raises(RuntimeError, match="closed"):
        vec.step(np.zeros((2, 7)))


def test_an_env_used_from_two_threads_at_once_says_so():
    """The GIL is released while an env steps; a second thread's call on the same env is refused
    with a message that says why (PyO3's own said only "Already borrowed"), and the first
    thread's episode goes on."""
    import threading

    from libero_vifo.gym import LiberoVifoEnv, LiberoVifoVectorEnv

    for env, action in (
        (LiberoVifoEnv("libero_goal", 0, size=64), np.zeros(7)),
        (LiberoVifoVectorEnv(suite="libero_goal", task=0, num_envs=2, size=64, threads=1), np.zeros((2, 7))),
    ):
        env.reset(options={"init_state": 0})
        # Either thread may be the one refused: both keep count of what they got.
        stop, stepped, refusals = threading.Event(), [], []

        def step_once():
            try:
                env.step(action)
                stepped.append(1)
            except RuntimeError as e:
                refusals.append(str(e))

        def steady():
            while not stop.is_set() and len(stepped) < 400:
                step_once()

        worker = threading.Thread(target=steady)
        worker.start()
        try:
            while worker.is_alive() and not refusals:
                step_once()
        finally:
            stop.set()
            worker.join()
        assert refusals and all("in use by another thread" in r for r in refusals), refusals
        assert stepped, "the steps not refused stood"
        env.step(action)  # usable again once the other call is over
        env.close()
