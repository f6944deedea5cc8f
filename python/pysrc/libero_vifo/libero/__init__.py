"""Drop-in for ``libero.libero``: ``benchmark``, ``get_libero_path`` and ``envs``.

The tasks are built into the wheel (no BDDL files, assets or init-state files on disk).
``get_libero_path`` returns paths under this package that only name things: an env finds its
task from the last two parts of ``bddl_file_name`` (``<problem_folder>/<bddl_file>``).
"""

import os

from . import benchmark, envs  # noqa: F401

_ROOT = os.path.dirname(os.path.abspath(__file__))
_PATHS = {
    "benchmark_root": _ROOT,
    "bddl_files": os.path.join(_ROOT, "bddl_files"),
    "init_states": os.path.join(_ROOT, "init_files"),
    "datasets": os.path.join(_ROOT, "datasets"),
    "assets": os.path.join(_ROOT, "assets"),
}


def get_libero_path(query_key):
    """LIBERO's folder called ``query_key`` (``bddl_files``, ``init_states``, ...)."""
    try:
        return _PATHS[query_key]
    except KeyError:
        raise KeyError(f"unknown LIBERO path {query_key!r}; known: {', '.join(_PATHS)}") from None


__all__ = ["benchmark", "envs", "get_libero_path"]
