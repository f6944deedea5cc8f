"""Drop-in for ``libero.libero.benchmark``: the four VLA suites and their tasks."""

from collections import namedtuple

from .. import _native

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
        self._tasks = [t for t in _TASKS if t["suite"] == self.name]
        self.n_tasks = len(self._tasks)

    def _task(self, i):
        if not isinstance(i, int) or not 0 <= i < self.n_tasks:
            raise IndexError(f"task {i!r}: {self.name} has tasks 0 to {self.n_tasks - 1}")
        return self._tasks[i]

    def get_task(self, i):
        t = self._task(i)
        return Task(t["name"], t["language"], "LiberoVifo", t["suite"], t["name"] + ".bddl", t["name"] + ".pruned_init")

    def get_task_names(self):
        return [t["name"] for t in self._tasks]

    def get_task_init_states(self, i):
        t = self._task(i)
        return [InitState(self.name, i, k) for k in range(t["init_states"])]

    def get_num_tasks(self):
        return self.n_tasks

    def get_max_steps(self):
        """The suite's policy budget (openpi's and OpenVLA's max_steps)."""
        return self._tasks[0]["max_steps"]


def _suite_class(suite):
    return type(suite.upper(), (Benchmark,), {"name": suite})


BENCHMARK_MAPPING = {s: _suite_class(s) for s in SUITES}


def get_benchmark_dict():
    """Suite name -> suite class (call it to get the suite), as LIBERO's."""
    return dict(BENCHMARK_MAPPING)


def get_benchmark(name):
    try:
        return BENCHMARK_MAPPING[name.lower()]
    except KeyError:
        raise KeyError(f"unknown suite {name!r}; known: {', '.join(SUITES)}") from None
