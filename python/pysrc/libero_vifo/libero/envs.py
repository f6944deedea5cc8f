"""Drop-in for ``libero.libero.envs.OffScreenRenderEnv``.

Differences from LIBERO, all on purpose:
- ``reset()`` loads fixed initial state 0 (LIBERO samples a new placement); evaluations call
  ``set_init_state`` next anyway. Neither runs settle steps: the caller's dummy steps do, as
  openpi's loop does, and after LIBERO's 10 of them the episode equals ``vifo``'s bit for bit.
- The physics has no randomness, so ``seed`` only records the seed.
- Extra keyword arguments reach the cue protocols: ``cue=`` (an instance id,
  ``libero_goal/0/F7/glow_halo``; ``libero_vifo.cue_instances()`` lists them) and
  ``language_condition=`` (``authorized``, the default with a cue, ``conflict`` or
  ``no_language``; ``original``, the default without). The images then carry the cue as
  ``vifo run`` draws it and ``language_instruction`` is the protocol's instruction (openpi's
  loop reads ``task.language``; feed ``env.language_instruction`` instead). ``done``,
  ``reward`` and ``check_success`` follow the protocol's scored task.
- After the episode is done (task finished or the suite's budget + 10 steps), ``step`` raises
  ``RuntimeError`` instead of simulating on.

As in robosuite, ``camera_names`` (a name or a list of ``agentview`` and
``robot0_eye_in_hand``; both by default) picks the cameras drawn, one ``<name>_image`` key each,
and ``use_camera_obs=False`` draws none: a policy that reads only the robot's and the objects'
vectors then skips the rendering's cost. The other robosuite arguments LIBERO's scripts pass
(``has_renderer``, ``has_offscreen_renderer``, ``control_freq``, ``horizon``) are accepted and
change nothing.
"""

import os

from .. import _native
from .._args import action as _action, index
from .benchmark import InitState, _TASKS

__all__ = ["OffScreenRenderEnv"]


def _find_task(bddl_file_name):
    path = os.fspath(bddl_file_name)
    stem = os.path.splitext(os.path.basename(path))[0]
    folder = os.path.basename(os.path.dirname(path))
    found = [t for t in _TASKS if t["name"] == stem and (t["suite"] == folder or not folder)]
    suites = {t["suite"] for t in _TASKS}
    if not found and folder not in suites:
        # A copy of the file outside LIBERO's tree: its name alone says the task.
        found = [t for t in _TASKS if t["name"] == stem]
    elif not found:
        elsewhere = sorted(t["suite"] for t in _TASKS if t["name"] == stem)
        if elsewhere:
            raise ValueError(f"bddl_file_name {path!r}: task {stem!r} is in {', '.join(elsewhere)}, not in {folder!r}")
    if len(found) != 1:
        raise ValueError(
            f"bddl_file_name {path!r}: no built-in task {stem!r}"
            + (f" in {folder!r}" if folder else "")
            + " (expected get_libero_path('bddl_files')/<problem_folder>/<bddl_file> of a benchmark task)"
        )
    return found[0]


class OffScreenRenderEnv:
    """One LIBERO task with two square cameras, stepped with 7-D actions."""

    def __init__(self, bddl_file_name, camera_heights=128, camera_widths=128, cue=None, language_condition=None, cue_facing="upright", **kwargs):
        if camera_heights != camera_widths:
            raise ValueError(f"camera_heights {camera_heights} != camera_widths {camera_widths}: cameras are square here")
        unknown = set(kwargs) - {"camera_names", "has_renderer", "has_offscreen_renderer", "use_camera_obs", "control_freq", "horizon"}
        if unknown:
            raise TypeError(f"OffScreenRenderEnv: unsupported arguments {sorted(unknown)}")
        self._task = _find_task(bddl_file_name)
        if cue is not None and not isinstance(cue, str):
            raise TypeError(f"cue: expected an instance id string, got {type(cue).__name__}")
        if language_condition is None:
            language_condition = "original" if cue is None else "authorized"
        if language_condition != "original" and cue is None:
            raise ValueError(f"language_condition {language_condition!r} needs cue=<instance id> (libero_vifo.cue_instances() lists them)")
        size = index(camera_heights, "camera_heights")
        camera_names = kwargs.get("camera_names", ["agentview", "robot0_eye_in_hand"])
        if isinstance(camera_names, str):
            camera_names = [camera_names]
        if not isinstance(camera_names, (list, tuple)) or not all(isinstance(n, str) for n in camera_names):
            raise TypeError(f"camera_names: expected a camera name or a list of them, got {camera_names!r}")
        cameras = list(camera_names) if kwargs.get("use_camera_obs", True) else []
        self._env = _native.NativeEnv(self._task["suite"], self._task["index"], size, language_condition, cue, cameras, cue_facing)
        self._seed = None
        self.cue = cue
        self.language_condition = language_condition
        self.language_instruction = self._env.instruction

    def seed(self, seed):
        self._seed = seed

    def reset(self):
        return self._env.reset(0)

    def set_init_state(self, init_state):
        if not isinstance(init_state, InitState):
            raise TypeError(
                f"set_init_state: expected an entry of benchmark get_task_init_states(), got {type(init_state).__name__}"
            )
        if (init_state.suite, init_state.task_index) != (self._task["suite"], self._task["index"]):
            raise ValueError(
                f"set_init_state: state of {init_state.suite}/{init_state.task_index}, "
                f"this env runs {self._task['suite']}/{self._task['index']}"
            )
        return self._env.reset(index(init_state.index, "init_state.index"))

    def step(self, action):
        """LIBERO's 4-tuple: obs, reward (1.0 once the task is done), done (the task is
        done: LIBERO's ``_check_success()``, not the end of the budget), info
        (``language_success`` and ``cue_success``: each task's success, ``None`` where the
        protocol has no such task; under conflict ``done`` is either, and these tell LFR from
        UVF)."""
        obs, reward, _ = self._env.step(_action(action, (7,)).tolist())
        language, cue = self._env.successes()
        return obs, reward, self._env.check_success(), {"language_success": language, "cue_success": cue}

    def check_success(self):
        return self._env.check_success()

    def get_sim_state(self):
        return self._env.sim_state()

    def close(self):
        self._env.close()
