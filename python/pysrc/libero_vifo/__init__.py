"""LIBERO-VIFO from Python: the pure-Rust LIBERO environment behind LIBERO's own API.

Switch an evaluation script by changing its imports::

    from libero_vifo.libero import benchmark, get_libero_path
    from libero_vifo.libero.envs import OffScreenRenderEnv
"""

from . import _native  # noqa: F401

__all__ = ["libero"]
