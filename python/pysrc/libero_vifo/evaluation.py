"""Your own policy, a Python function, through the benchmark as ``vifo run`` runs a served one.

``evaluate(policy, name, selection)`` runs the selection's episodes with the same Rust code as
``vifo run`` (``_native.run_specs``) into a ``vifo run`` results file and writes the report, so
``vifo report`` and ``vifo run --resume`` (or ``resume=True`` here) read and continue it. No
policy server is needed: the function is called in this process.
"""

import os

from . import _native
from ._args import index, selection as _selection

__all__ = ["evaluate", "results_path"]


def results_path(folder, name):
    """The results file that ``vifo run``, ``evaluate`` and ``libero_vifo.ray`` write for the
    policy ``name`` (its given name, or the policy string: a built-in, a server URL) in
    ``folder``: ``folder/results-<name, file-safe>.jsonl``."""
    if not isinstance(name, str):
        raise TypeError(f"name: expected a string, got {type(name).__name__}")
    return os.path.join(os.fspath(folder), _native.results_file_name(name))


def evaluate(
    policy,
    name,
    selection,
    out="vifo-run-python",
    resume=False,
    size=256,
    cue_facing="upright",
    report=True,
    quiet=False,
    assets=None,
    robot_assets=None,
    builtin_look=False,
):
    """Runs ``selection`` with ``policy`` into ``out/results-<name>.jsonl`` and its report.

    - ``policy``: ``policy(obs, instruction)`` returns the next action, 7 numbers (LIBERO's:
      end-effector delta position and rotation, gripper). ``obs`` is the gym env's observation:
      ``agentview_image`` and ``robot0_eye_in_hand_image`` (uint8 H×W×3, upright; LIBERO's raw
      frames are these upside down), ``robot0_eef_pos``, ``robot0_eef_quat`` (x y z w),
      ``robot0_gripper_qpos``, ``robot0_joint_pos`` (``_cos``, ``_sin``). ``instruction`` is
      the protocol's (empty under ``no_language``). Where the policy has a ``reset()`` method it
      is called at the start of each episode (after LIBERO's settle steps).
    - ``name``: what its records and report rows carry (and the results file's name).
    - ``selection``: ``vifo run``'s options as a dict: ``set`` (``paper``/``full``),
      ``suites``, ``protocols``, ``families``, ``per_family``, ``episodes``, and ``sample``
      (about that many episodes of the selection, spread over its protocols, as ``vifo run
      --sample``).
    - ``resume``: continue the results file (finished episodes are skipped, errors retried).
    - ``size``, ``cue_facing``, ``assets``, ``robot_assets``, ``builtin_look``: as ``vifo run``
      takes them (``--size``, ``--cue-facing``, the look).

    The first exception the policy raises, or an action that is not 7 finite numbers, stops the
    run and is raised here (its episode is recorded as an error, which ``resume=True`` retries);
    so does Ctrl-C, after the running episode. Episodes run one at a time, in this process.

    Returns a dict: ``episodes`` (in the selection), ``ran``, ``errors``, ``already_done``,
    ``output`` (the results file) and ``report`` (its folder, or ``None``).
    """
    set_name, rest = _selection(selection)
    output = results_path(out, name)
    specs = _native.episode_specs(set=set_name, **rest)
    os.makedirs(os.path.dirname(output) or ".", exist_ok=True)
    ran, errors, already_done = _native.run_specs(
        [spec for _, spec in specs], policy, output, set=set_name, resume=resume, size=index(size, "size"), quiet=quiet,
        assets=assets, robot_assets=robot_assets, builtin_look=builtin_look, cue_facing=cue_facing, name=name,
    )
    report_dir = None
    if report:
        report_dir = os.path.join(os.fspath(out), "report")
        _native.write_report([output], report_dir, False)
    return {"episodes": len(specs), "ran": ran, "errors": errors, "already_done": already_done, "output": output,
            "report": report_dir}
