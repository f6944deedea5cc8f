"""Argument checks shared by the LIBERO drop-in, the gymnasium envs and the Ray runner, so a
wrong value raises ``TypeError`` or ``ValueError`` naming the argument, never an
``OverflowError`` from the Rust side or a silent conversion."""

import operator

import numpy as np


# Larger counts and indices than any env takes; Rust would refuse them with an OverflowError.
_MOST = 2**31 - 1


def _integer(value, name):
    """``value`` as an ``int``: Python and numpy integers pass (LIBERO indexes lists, which take
    anything with ``__index__``); ``"3"``, ``3.9`` and ``True`` do not."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name}: expected an integer, got {value!r}")
    try:
        return operator.index(value)
    except TypeError:
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__} {value!r}") from None


def index(value, name):
    """``value`` as a non-negative ``int`` up to 2**31 - 1 (see ``_integer``)."""
    i = _integer(value, name)
    if i < 0:
        raise ValueError(f"{name} {i}: expected 0 or more")
    if i > _MOST:
        raise ValueError(f"{name} {i}: expected at most {_MOST}")
    return i


def count(value, name, most):
    """``value`` as an ``int`` from 1 to ``most``: how many things to make, checked before any
    is made (see ``_integer``)."""
    i = _integer(value, name)
    if not 1 <= i <= most:
        raise ValueError(f"{name} {i}: expected 1 to {most}")
    return i


def action(value, shape):
    """``value`` as a float64 array of ``shape`` (one action ``(7,)`` or a batch ``(N, 7)``)."""
    a = np.asarray(value)
    if a.dtype.kind not in "biuf":
        raise TypeError(f"action of dtype {a.dtype}: expected real numbers")
    a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape != shape:
        name = "action" if len(shape) == 1 else "actions"
        raise ValueError(f"{name} of shape {a.shape}: expected {shape}")
    return a


def selection(value):
    """``vifo run``'s selection options as a dict (``set``, ``suites``, ``protocols``,
    ``families``, ``per_family``, ``episodes``, ``sample``): ``(set name, the rest)``, the rest
    as ``_native.episode_specs`` takes it."""
    rest = dict(value)
    set_name = rest.pop("set", "paper")
    unknown = set(rest) - {"suites", "protocols", "families", "per_family", "episodes", "sample"}
    if unknown:
        raise ValueError(
            f"selection: unknown keys {sorted(unknown)} (expected set, suites, protocols, families, per_family, episodes, sample)"
        )
    for key in ("per_family", "episodes", "sample"):
        if rest.get(key) is not None:
            rest[key] = index(rest[key], f"selection[{key!r}]")
    return set_name, rest
