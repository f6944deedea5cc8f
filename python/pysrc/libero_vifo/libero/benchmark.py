"""Drop-in for ``libero.libero.benchmark``: the four VLA suites and their tasks."""

import os
from collections import namedtuple

from .. import _native
from .._args import index

Task = namedtuple("Task", ["name", "language", "problem", "problem_folder", "bddl_file", "init_states_file"])
"""LIBERO's task record. ``language`` is the instruction evaluations feed the policy."""

InitState = namedtuple("InitState", ["suite", "task_index", "index"])
"""One of a task's 50 fixed initial states; pass it to ``OffScreenRenderEnv.set_init_state``.
Opaque, unlike LIBERO's flattened MuJoCo states (ours also fix the fixtures' poses)."""

SUITES = ("libero_spatial", "libero_object", "libero_goal", "libero_10")

_TASKS = _native.tasks()


class Benchmark:
    """One suite, in LIBERO's task order."""

    name = None

    def __init__(self, task_order_index=0):
        if task_order_index != 0:
            raise ValueError(f"task_order_index {task_order_index}: only LIBERO's default order 0 exists here")
        self.task_order_index = task_order_index
        self.task_embs = None
        self._tasks = [t for t in _TASKS if t["suite"] == self.name]
        self.n_tasks = len(self._tasks)

    def _task(self, i):
        i = index(i, "task")
        if i >= self.n_tasks:
            raise IndexError(f"task {i}: {self.name} has tasks 0 to {self.n_tasks - 1}")
        return self._tasks[i]

    def get_task(self, i):
        t = self._task(i)
        return Task(t["name"], t["language"], "LiberoVifo", t["suite"], t["name"] + ".bddl", t["name"] + ".pruned_init")

    def get_task_names(self):
        return [t["name"] for t in self._tasks]

    def get_task_problems(self):
        return [self.get_task(i).problem for i in range(self.n_tasks)]

    def get_task_bddl_files(self):
        return [self.get_task(i).bddl_file for i in range(self.n_tasks)]

    def get_task_bddl_file_path(self, i):
        """The path ``OffScreenRenderEnv(bddl_file_name=...)`` takes (no file is read)."""
        from . import get_libero_path  # here: the package imports this module before defining it

        task = self.get_task(i)
        return os.path.join(get_libero_path("bddl_files"), task.problem_folder, task.bddl_file)

    def get_task_demonstration(self, i):
        """LIBERO's demonstration path, relative to its datasets folder (none ship here)."""
        task = self.get_task(i)
        return f"{task.problem_folder}/{task.name}_demo.hdf5"

    def get_task_init_states(self, i):
        t = self._task(i)
        return [InitState(self.name, t["index"], k) for k in range(t["init_states"])]

    def get_task_emb(self, i):
        return self.task_embs[i]

    def set_task_embs(self, task_embs):
        self.task_embs = task_embs

    def get_num_tasks(self):
        return self.n_tasks

    def get_max_steps(self):
        """The suite's policy budget (openpi's and OpenVLA's max_steps)."""
        return self._tasks[0]["max_steps"]


def _suite_class(suite):
    # A module global of its own name, as LIBERO's classes are, so that pickle finds it.
    cls = type(suite.upper(), (Benchmark,), {"name": suite, "__module__": __name__})
    globals()[cls.__name__] = cls
    return cls


BENCHMARK_MAPPING = {s: _suite_class(s) for s in SUITES}


class _Suites(dict):
    """A dict whose missing suite (LIBERO's ``libero_90``, which LIBERO-VIFO does not port)
    raises a ``KeyError`` that names the known ones, as ``get_benchmark`` does."""

    def __missing__(self, name):
        raise KeyError(f"unknown suite {name!r}; known: {', '.join(SUITES)}")


def get_benchmark_dict():
    """Suite name -> suite class (call it to get the suite), as LIBERO's."""
    return _Suites(BENCHMARK_MAPPING)


def get_benchmark(name):
    try:
        return BENCHMARK_MAPPING[name.lower()]
    except KeyError:
        raise KeyError(f"unknown suite {name!r}; known: {', '.join(SUITES)}") from None
