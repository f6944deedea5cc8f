"""gymnasium environments (importing this module registers them; needs ``gymnasium``, which
the wheel does not depend on):

- ``libero_vifo/<suite>-<task>``: the 40 tasks, original protocol (``libero_vifo/libero_goal-0``);
- ``libero_vifo/<suite>-<task>-<condition>-<family>-<variant>``: each cue instance of the paper
  set (``<suite>/<task>/<family>/<variant>``) under each cue protocol, ``condition`` one of
  ``authorized``, ``conflict``, ``no_language`` (``libero_vifo/libero_goal-0-conflict-F7-glow_halo``;
  3 x 1,347 ids; a repeated variant's ``@k`` is written ``.k``, which gymnasium's ids allow).
  Instances of the ``full`` set only: ``gymnasium.make("libero_vifo/<suite>-<task>",
  cue=<id>, language_condition=<condition>)``.

An episode here is the one ``vifo`` runs: ``reset`` loads an initial state (``options =
{"init_state": k}``, else one drawn from the reset seed) and runs LIBERO's 10 settle steps;
``terminated`` when the task is done, ``truncated`` at the suite's budget. Images are upright
(row 0 at the top), unlike ``OffScreenRenderEnv``'s robosuite order.

``LiberoVifoVectorEnv`` (also ``gymnasium.make_vec(id, num_envs=N,
vectorization_mode="vector_entry_point")``) steps N episodes in one call on Rust threads with
the GIL released; its sub-envs are the same episodes, bit for bit, as the single env's.
"""

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

try:  # gymnasium >= 1.1 names the mode with an enum, which its vector wrappers require
    from gymnasium.vector import AutoresetMode

    _NEXT_STEP = AutoresetMode.NEXT_STEP
except ImportError:  # gymnasium 1.0: a string
    _NEXT_STEP = "NextStep"

from . import _native
from ._args import action as _action
from ._args import count, index
from .libero.benchmark import _TASKS

__all__ = ["LiberoVifoEnv", "LiberoVifoVectorEnv"]

_DUMMY = [0.0] * 6 + [-1.0]
_SETTLE_STEPS = 10
# Length and bound of each vector: the eef stays within the Panda's reach (< 1.3 m) of its
# base near the world origin, arm joints within the Panda's limits (all inside ±3.8 rad),
# fingers within their 4 cm travel.
_VECTORS = {
    "robot0_eef_pos": (3, 3.0),
    "robot0_eef_quat": (4, 1.0),
    "robot0_gripper_qpos": (2, 0.1),
    "robot0_joint_pos": (7, 3.8),
    "robot0_joint_pos_cos": (7, 1.0),
    "robot0_joint_pos_sin": (7, 1.0),
}


def _observation_space(size):
    image = spaces.Box(0, 255, (size, size, 3), np.uint8)
    vectors = {k: spaces.Box(-b, b, (n,), np.float64) for k, (n, b) in _VECTORS.items()}
    return spaces.Dict({"agentview_image": image, "robot0_eye_in_hand_image": image, **vectors})


def _resolve_condition(cue, language_condition):
    if language_condition is None:
        language_condition = "original" if cue is None else "authorized"
    if language_condition != "original" and cue is None:
        raise ValueError(f"language_condition {language_condition!r} needs cue=<instance id>")
    return language_condition


def _task_info(suite, task):
    task = index(task, "task")
    found = [t for t in _TASKS if (t["suite"], t["index"]) == (suite, task)]
    if not found:
        raise ValueError(f"unknown task {suite}/{task}")
    return found[0]


class LiberoVifoEnv(gymnasium.Env):
    """One built-in task with two ``size``² cameras, under the original protocol or, with a
    cue instance id, under ``language_condition`` (``authorized`` by default). ``cue_facing``:
    ``"upright"`` draws the cue readable in the upright frame, ``"model"`` readable in the frame
    LIBERO-trained models receive (the upright one mirrored left-right by LIBERO's 180° rotation)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 20}

    def __init__(self, suite, task, size=256, render_mode=None, cue=None, language_condition=None, cue_facing="upright"):
        self._info = _task_info(suite, task)
        size = index(size, "size")
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode {render_mode!r}: only 'rgb_array'")
        self.render_mode = render_mode
        self._env = _native.NativeEnv(suite, task, size, _resolve_condition(cue, language_condition), cue, cue_facing=cue_facing)
        self.language_instruction = self._env.instruction
        self.observation_space = _observation_space(size)
        self.action_space = spaces.Box(-1.0, 1.0, (7,), np.float32)
        self._last = None

    def _observe(self, obs):
        self._last = obs
        out = {k: np.ascontiguousarray(obs[k][::-1]) for k in ("agentview_image", "robot0_eye_in_hand_image")}
        out.update({k: obs[k] for k in _VECTORS})
        return out

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        options = options or {}
        init = index(options.get("init_state", self.np_random.integers(self._info["init_states"])), "init_state")
        obs = self._env.reset(init)
        for _ in range(_SETTLE_STEPS):
            obs, _, _ = self._env.step(_DUMMY)
        return self._observe(obs), {"init_state": init, "language": self.language_instruction}

    def step(self, action):
        obs, reward, done = self._env.step(_action(action, (7,)).tolist())
        success = self._env.check_success()
        language, cue = self._env.successes()
        info = {"success": success, "language_success": language, "cue_success": cue}
        return self._observe(obs), reward, success, done and not success, info

    def render(self):
        if self._last is None:
            return None
        return np.ascontiguousarray(self._last["agentview_image"][::-1])

    def close(self):
        self._env.close()


class LiberoVifoVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` episodes of one task (or one per entry of ``episodes``: ``(suite, task)``
    or ``(suite, task, language_condition, cue)``) stepped together on ``threads`` Rust
    threads (default: one per env), the GIL released. 1 to ``_native.MAX_ENVS`` (1024) envs:
    each holds its own simulator and renderer (a few MB).

    ``reset`` starts every sub-env from an initial state (``options={"init_state": k}`` or a
    list of N, else drawn from the reset seed) with the 10 settle steps, as ``vifo run``;
    ``step`` takes an (N, 7) batch. Autoreset is gymnasium 1.0's next-step mode: the step after
    a sub-env ended resets it to a drawn initial state (reward 0, not done) and ignores its
    action. Infos: ``init_state`` where a sub-env (re)started, ``success`` per step (the task
    the protocol scores; under conflict either), ``language_success`` and ``cue_success``
    where the protocol has that task (they tell LFR from UVF), and
    ``error`` where a sub-env's physics blew up: that sub-env is truncated (its episode scores
    nothing and keeps its last observation) and autoresets; the others' steps stand.
    ``cue_facing`` as :class:`LiberoVifoEnv`'s. ``render_mode="rgb_array"``: ``render()`` gives
    the N agentview images of the last step. ``max_episode_steps`` truncates an episode after
    that many steps where it comes before the suite's budget (``gymnasium.make_vec`` passes both).
    """

    metadata = {"autoreset_mode": _NEXT_STEP, "render_modes": ["rgb_array"], "render_fps": 20}

    def __init__(self, num_envs=1, suite=None, task=None, size=256, cue=None, language_condition=None, threads=None, episodes=None,
                 cue_facing="upright", render_mode=None, max_episode_steps=None):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode {render_mode!r}: only 'rgb_array'")
        self.render_mode = render_mode
        self._max_steps = None if max_episode_steps is None else index(max_episode_steps, "max_episode_steps")
        if episodes is None:
            if suite is None or task is None:
                raise ValueError("name the task (suite=, task=) or pass episodes=[(suite, task[, language_condition, cue]), ...]")
            episodes = [(suite, task, language_condition, cue)] * count(num_envs, "num_envs", _native.MAX_ENVS)
        rows = []
        for e in episodes:
            s, t, condition, c = (tuple(e) + (None, None))[:4]
            _task_info(s, t)
            rows.append((s, index(t, "task"), _resolve_condition(c, condition), c))
        self.num_envs = len(rows)
        self._counts = [_task_info(s, t)["init_states"] for s, t, _, _ in rows]
        threads = self.num_envs if threads is None else index(threads, "threads")
        self._env = _native.NativeVectorEnv(rows, index(size, "size"), threads, cue_facing)
        self.language_instructions = self._env.instructions()
        self.single_observation_space = _observation_space(size)
        self.single_action_space = spaces.Box(-1.0, 1.0, (7,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._last = None

    def _draw(self, k):
        return int(self.np_random.integers(self._counts[k]))

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        init = (options or {}).get("init_state")
        if init is None:
            inits = [self._draw(k) for k in range(self.num_envs)]
        elif np.ndim(init) == 0:
            inits = [index(init, "init_state")] * self.num_envs
        else:
            inits = [index(i, "init_state") for i in init]
        obs = self._env.reset(inits)
        self._autoreset[:] = False
        self._steps[:] = 0
        self._last = obs
        return obs, {"init_state": np.array(inits), "_init_state": np.ones(self.num_envs, dtype=bool)}

    def step(self, actions):
        if self.closed:
            raise RuntimeError("the vector env is closed")
        actions = _action(actions, (self.num_envs, 7))
        # A step refused (a NaN action) must not use up the draws of the restarts it would make.
        drawn_from = self.np_random.bit_generator.state
        resets = [self._draw(k) if self._autoreset[k] else None for k in range(self.num_envs)]
        try:
            obs, rewards, terminated, truncated, errors, successes = self._env.step(actions, resets)
        except ValueError:
            self.np_random.bit_generator.state = drawn_from
            raise
        terminated, truncated = np.array(terminated), np.array(truncated)
        self._steps = np.where(self._autoreset, 0, self._steps + 1)
        if self._max_steps is not None:
            truncated |= ~self._autoreset & ~terminated & (self._steps >= self._max_steps)
        info = {"success": terminated.copy(), "_success": ~self._autoreset}
        for k, key in enumerate(("language_success", "cue_success")):
            flags = [s[k] for s in successes]
            defined = np.array([f is not None for f in flags])
            if defined.any():
                info[key] = np.array([bool(f) for f in flags])
                info["_" + key] = defined
        failed = np.array([e is not None for e in errors])
        if failed.any():
            info["error"] = np.array(["" if e is None else e for e in errors], dtype=object)
            info["_error"] = failed
        restarted = np.array([r is not None for r in resets])
        if restarted.any():
            info["init_state"] = np.array([-1 if r is None else r for r in resets])
            info["_init_state"] = restarted
        self._autoreset = terminated | truncated
        self._last = obs
        return obs, np.array(rewards), terminated, truncated, info

    def render(self):
        if self.render_mode is None or self._last is None:
            return None
        return self._last["agentview_image"].copy()

    def close_extras(self, **kwargs):
        # Also called (by __del__) on an env whose constructor raised.
        if hasattr(self, "_env"):
            self._env.close()


CUE_CONDITIONS = ("authorized", "conflict", "no_language")


def _register(env_id, **kwargs):
    if env_id not in gymnasium.registry:
        gymnasium.register(
            id=env_id,
            entry_point="libero_vifo.gym:LiberoVifoEnv",
            vector_entry_point="libero_vifo.gym:LiberoVifoVectorEnv",
            kwargs=kwargs,
        )


for _t in _TASKS:
    _register(f"libero_vifo/{_t['suite']}-{_t['index']}", suite=_t["suite"], task=_t["index"])
for _cue in _native.cue_instances("paper"):
    _suite, _index, _family, _variant = _cue.split("/")
    for _condition in CUE_CONDITIONS:
        _register(
            f"libero_vifo/{_suite}-{_index}-{_condition}-{_family}-{_variant.replace('@', '.')}",
            suite=_suite,
            task=int(_index),
            cue=_cue,
            language_condition=_condition,
        )
