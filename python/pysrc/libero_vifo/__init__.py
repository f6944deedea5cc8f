"""LIBERO-VIFO from Python: the pure-Rust LIBERO environment behind LIBERO's own API.

Switch an evaluation script by changing its imports::

    from libero_vifo.libero import benchmark, get_libero_path
    from libero_vifo.libero.envs import OffScreenRenderEnv
"""

from . import _native

__all__ = ["libero", "cue_instances"]


def cue_instances(set="paper"):
    """The cue instance ids of the 40 tasks (``libero_goal/0/F7/glow_halo``) in the ``paper``
    set (1,347) or the ``full`` one, for ``OffScreenRenderEnv(cue=...)``."""
    return _native.cue_instances(set)
