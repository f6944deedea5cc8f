"""The benchmark sharded over a Ray cluster (needs ``ray``: ``pip install libero_vifo[ray]``).

``run_benchmark(selection, policy)`` lists the selection's episodes as ``vifo run`` does, skips
those the results file already completed, splits the rest into batches and runs each batch as
one Ray task: one process runs its episodes with the same Rust code as ``vifo run``
(``_native.run_specs``) and returns their records. The driver appends each returned record to
the results file through the runner's own lock, checks and writer, so the file is a ``vifo
run`` results file: ``vifo report`` reads it and ``vifo run --resume`` (or ``resume=True``
here) continues it.

A worker that dies (killed, out of memory, a lost node) fails its task and Ray runs the task
again (``max_retries``); records come back only from a finished task and the driver writes a
key once, so a batch cut short leaves no record and a retried one no duplicate. The summary
counts missing and duplicate episodes of the file after the run.
"""

import collections
import json
import os
import tempfile
import time

import ray

from . import _native
from ._args import index, selection as _selection
from .evaluation import results_path

__all__ = ["run_benchmark", "default_output"]


def _run_batch(specs, policy, set_name, size, look, model_profile=None):
    """One Ray task: the episodes ``specs`` (JSON) in this process, drawn with the look that
    ``look`` (``run_specs``'s look arguments) finds here; ``[(key, record line)]``."""
    with tempfile.TemporaryDirectory(prefix="libero-vifo-batch-") as scratch:
        path = os.path.join(scratch, "results.jsonl")
        _native.run_specs(specs, policy, path, set=set_name, threads=1, size=size, model_profile=model_profile, **look)
        with open(path) as f:
            lines = [line for line in f.read().splitlines() if line.strip()]
        keys = [key for key, _ in _native.record_keys(path)]
    return list(zip(keys, lines))


# What a record stores as the look of an episode whose policy was sent no images (the built-in
# policies): the same result with any look, so it goes with every look (``report::NO_IMAGES``).
_NO_IMAGES = "none"


def _look_name(look):
    """A record's look as ``vifo report`` names it (the built-in look is stored empty)."""
    return look or "built-in"


def _first_look(path):
    """The look of the first record of the results file ``path`` that was drawn with one."""
    with open(path) as f:
        for line in f:
            if line.strip():
                look = json.loads(line).get("look", "")
                if look != _NO_IMAGES:
                    return look
    return None


def default_output(policy, folder="vifo-run-ray", name=None, model_profile=None):
    """The results file ``run_benchmark`` writes to when given no ``output`` (with ``folder``
    as the folder): ``results-<name, else the (first) policy string, file-safe>.jsonl``, as
    ``vifo run --out folder`` names it."""
    first = policy[0] if isinstance(policy, (list, tuple)) and policy else policy
    _, label, _ = _native.check_policy(first, model_profile, name)
    return results_path(folder, label)


def run_benchmark(
    selection,
    policy,
    address=None,
    output=None,
    resume=False,
    batch_size=None,
    num_workers=None,
    size=256,
    max_retries=3,
    report_dir=None,
    quiet=False,
    assets=None,
    robot_assets=None,
    builtin_look=False,
    cue_facing="upright",
    model_profile=None,
    name=None,
):
    """Runs ``selection`` with ``policy`` on a Ray cluster into a ``vifo run`` results file.

    - ``selection``: ``vifo run``'s options as a dict: ``set`` (``paper``/``full``),
      ``suites``, ``protocols``, ``families``, ``per_family``, ``episodes``, ``sample``.
    - ``policy``: a built-in (``expert-cue``, ``expert-language``, ``expert-authorized``,
      ``random``, ``zero``), a policy server as ``vifo run --policy`` takes it (``ws://``,
      ``http://…/act``, ``tcp://``, ``grpc://…``; ``model_profile`` as ``--model-profile``
      says, e.g. ``"openvla-oft"``), or a list of servers of that profile: batch
      ``j`` goes to server ``j % len(list)`` (Ray gives a batch to whichever worker is free,
      so two workers may share a server for a while); the records carry one policy name, the
      first server's (or ``name``), and a resumed file must hold that policy's records.
    - ``name``: what a served policy's records and report rows carry instead of
      ``<profile>@<url>`` (``vifo run --policy-name``), and the default results file's name:
      name each model, as two checkpoints served in turn at one address would otherwise share a
      row. A built-in keeps its own name.
    - ``address``: the cluster (``"auto"``, ``"ray://head:10001"``); ``None`` starts a local
      one with ``num_workers`` CPUs unless Ray is already initialised.
    - ``output``: the JSONL file (default ``vifo-run-ray/results-<name or policy>.jsonl``); ``resume``
      continues it. ``batch_size``: episodes per task (default: about 4 tasks per worker).
    - ``report_dir``: also write ``vifo report``'s tables there.
    - ``assets``, ``robot_assets``, ``builtin_look``: the look, as ``use_look`` takes it; each
      worker finds it on its own node (give paths that exist there, or install the asset
      wheels on every node); runs of different looks get worker processes of their own (a
      process draws with one look). Every record of a run must have one look: a batch drawn with
      another look than the file's first records is not written, and counts as failed (a
      policy sent no images, such as the built-in ones, goes with any look).
    - ``cue_facing``: ``"upright"``, or ``"model"`` to draw cues readable in the image a served
      model receives (``vifo run --cue-facing``); recorded with the look.

    Returns a summary dict: ``episodes``, ``already_done``, ``ran``, ``errors`` (and
    ``error_messages``: ``(count, message)`` pairs, most frequent first), ``missing``,
    ``duplicates``, ``failed_batches`` (tasks that failed even after their retries; their
    episodes are missing and a resumed run retries them), ``seconds``, ``output``, ``policy``
    (the name the records carry) and ``servers`` (the policy strings as given). Where every
    batch failed (nothing was written) it raises ``RuntimeError`` with the first batch's reason.
    """
    set_name, selection = _selection(selection)
    _native.check_size(index(size, "size"))
    # Checked before Ray starts: 0 workers would start a cluster without CPUs whose tasks never
    # run, a batch size below 1 would run nothing.
    if num_workers is not None and index(num_workers, "num_workers") < 1:
        raise ValueError("num_workers 0: expected 1 or more (or None: one per CPU)")
    if batch_size is not None and index(batch_size, "batch_size") < 1:
        raise ValueError("batch_size 0: expected 1 or more episodes per task (or None)")
    servers = list(policy) if isinstance(policy, (list, tuple)) else [policy]
    if not servers or not all(isinstance(p, str) for p in servers):
        raise TypeError("policy: expected a built-in policy name, a server URL or a list of server URLs")
    if len(servers) > 1 and not all("://" in p for p in servers):
        raise ValueError("policy: a list must hold servers only")
    if name is not None and not isinstance(name, str):
        raise TypeError(f"name: expected a string, got {type(name).__name__}")
    # One run, one policy row in the report: records served by several servers carry the
    # first server's name (or the one given).
    run_name = None
    for p in servers:
        record_name, _, one_client = _native.check_policy(p, model_profile, name)
        run_name = run_name or record_name
        # Ray runs batches side by side; such a server would mix their episodes up.
        if one_client and (address is not None or num_workers != 1):
            raise ValueError(f"{p}: this server holds one client at a time; give num_workers=1 (a local cluster), or use vifo run")
    if output is None:
        output = default_output(servers, name=name, model_profile=model_profile)

    if builtin_look and (assets is not None or robot_assets is not None):
        raise ValueError("builtin_look=True draws no asset files: give it without assets= and robot_assets=")
    if cue_facing not in ("upright", "model"):
        raise ValueError(f"cue_facing {cue_facing!r}: expected 'upright' or 'model'")
    look = {"assets": assets, "robot_assets": robot_assets, "builtin_look": builtin_look, "cue_facing": cue_facing}
    specs = _native.episode_specs(set=set_name, **selection)
    expected = {key for key, _ in specs}
    results = _native.ResultsFile(output, set=set_name, resume=resume, policy=run_name)
    start = time.monotonic()
    try:
        done = set(results.done())
        # The look of the records already in the file (the built-in look is stored empty).
        run_look = _first_look(output)
        todo = [(key, spec) for key, spec in dict(specs).items() if key not in done]
        if not ray.is_initialized():
            ray.init(address=address, num_cpus=num_workers if address is None else None, include_dashboard=False,
                     log_to_driver=not quiet)
        workers = max(1, int(ray.cluster_resources().get("CPU", num_workers or 1)))
        if batch_size is None:
            batch_size = max(1, -(-len(todo) // (4 * workers)))
        batches = [todo[i : i + batch_size] for i in range(0, len(todo), batch_size)]
        # Ray reuses a worker process for later tasks, and a process draws with the one look its
        # first env chose: a run of another look gets workers of its own, which Ray keeps apart
        # by runtime environment.
        process_look = {k: look[k] for k in ("assets", "robot_assets", "builtin_look")}
        task = ray.remote(max_retries=max_retries, retry_exceptions=False, num_cpus=1)(_run_batch).options(
            runtime_env={"env_vars": {"LIBERO_VIFO_RAY_LOOK": json.dumps(process_look, sort_keys=True)}}
        )
        pending = {
            task.remote([s for _, s in batch], servers[j % len(servers)], set_name, size, look, model_profile): batch
            for j, batch in enumerate(batches)
        }
        written, messages, failed, first_failure = set(), collections.Counter(), 0, None
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for ref in ready:
                batch = pending.pop(ref)
                try:
                    records = ray.get(ref)
                except ray.exceptions.RayError as e:
                    failed += 1
                    # An exception raised by the batch's code is not retried (retry_exceptions=False);
                    # a worker that died is, max_retries times.
                    why = "failed" if isinstance(e, ray.exceptions.RayTaskError) else f"failed after {max_retries} retries"
                    # The batch's own exception rather than Ray's wrapper (a coloured traceback).
                    cause = getattr(e, "cause", None) or e
                    why = f"{why}: {type(cause).__name__}: {cause}"
                    first_failure = first_failure or why
                    print(f"libero_vifo.ray: a batch of {len(batch)} episodes {why}")
                    continue
                records = [(key, line, json.loads(line)) for key, line in records]
                looks = {record.get("look", "") for _, _, record in records} - {_NO_IMAGES}
                run_look = run_look if run_look is not None else min(looks, default=None)
                if run_look is not None and looks - {run_look}:
                    failed += 1
                    why = (f"was drawn with look {_look_name(max(looks - {run_look}))}, this run's with {_look_name(run_look)}; "
                           "not written (install the same asset files on every node, or pass assets= or builtin_look=True)")
                    first_failure = first_failure or why
                    print(f"libero_vifo.ray: a batch of {len(batch)} episodes {why}")
                    continue
                for key, line, record in records:
                    if key in written or key not in expected:
                        continue
                    if record["policy"] != run_name:
                        line = json.dumps({**record, "policy": run_name})
                    results.write(line)
                    written.add(key)
                    if record["outcome"]["status"] == "error":
                        messages[record["outcome"]["message"]] += 1
                if not quiet:
                    print(f"libero_vifo.ray: {len(written)}/{len(todo)} episodes written", flush=True)
    finally:
        results.close()
    if batches and failed == len(batches):
        raise RuntimeError(f"libero_vifo.ray: every batch ({failed}) failed and no episode was written to {output}; "
                           f"the first {first_failure}")
    records = _native.record_keys(output)
    completed = collections.Counter(key for key, ok in records if ok)
    summary = {
        "episodes": len(expected),
        "already_done": len(expected & done),
        "ran": len(written),
        "errors": sum(messages.values()),
        # Why: the distinct messages, most frequent first (ties in message order), as `vifo run` prints them.
        "error_messages": sorted(((n, m) for m, n in messages.items()), key=lambda e: (-e[0], e[1])),
        # Episodes of the selection without any record, and second completed records of one
        # episode (an error record followed by its retry is how `--resume` works, not a duplicate).
        "missing": len(expected - {key for key, _ in records}),
        "duplicates": sum(n - 1 for n in completed.values()),
        "failed_batches": failed,
        "seconds": time.monotonic() - start,
        "output": str(output),
        "policy": run_name,
        "servers": servers,
    }
    if not quiet:
        for n, message in summary["error_messages"][:3]:
            print(f"libero_vifo.ray: {n} x {message}")
    if report_dir is not None:
        summary["report"] = _native.write_report([str(output)], str(report_dir))
    return summary

