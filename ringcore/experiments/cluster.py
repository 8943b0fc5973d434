"""``reproduce`` on dask.distributed: a recipe's independent runs as tasks, each with its own checkpoints.

The cluster is found as for :func:`ringcore.experiments.sweep.run_sweep`: a ``client`` given, a scheduler
address, the client already running in this process (``distributed.default_client()``, e.g. of a
dask-jobqueue cluster), else a ``LocalCluster`` of one single-threaded worker process per CPU.

A planned recipe (:mod:`ringcore.experiments.plan`) submits one task per run; every run writes
``OUT/NAME.runs/LABEL_HASH.nc`` (checkpoints every few orbits, then the finished run), so re-issuing the same
command after a crash, a preempted batch job or a lost worker continues each unfinished run from its last
checkpoint and skips the finished ones; the figure and its data file are drawn from the run files when the
last run ends.  A recipe without a plan is one task computing the whole recipe on a worker.
"""
from __future__ import annotations

import json
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path

from ..checks import check_choice, check_int
from .plan import PLANS, STATUS_DONE, execute_run, partial_note, read_runs, run_path
from .registry import MODES, RecipeResult, checkpoint_interval, get_plan, get_recipe, plan_tasks
from .reproduce_progress import Progress
from .sweep import _infrastructure, connect, default_workers, local_cluster, running_client


class RunsFailed(RuntimeError):
    """Some runs of a recipe failed (the message names each and why); the finished ones are kept."""


@dataclass
class ReproduceResult:
    """The recipe's outputs, one row per run (status, worker, timings) and the wall time [s]."""

    result: RecipeResult | None
    rows: list = field(default_factory=list)
    wall_s: float = 0.0
    partial: str | None = None


def _report_to(topic: str):
    """A progress reporter for a task on a worker: an event on ``topic`` at most every 0.5 s per run."""
    last = {}

    def report(label, orbit, until):
        from distributed import get_worker

        now = time.monotonic()
        if orbit < until and now - last.get(label, -1.0) < 0.5:
            return
        last[label] = now
        try:
            get_worker().log_event(topic, {"label": label, "orbit": float(orbit), "until": float(until)})
        except ValueError:  # not on a worker (a task run in the client process): no progress events
            pass
    return report


def run_task(task: dict, outdir: str, every: float, topic: str | None) -> dict:
    """The Dask task of one run (:func:`ringcore.experiments.plan.execute_run`), plus the worker's address."""
    from distributed import get_worker

    row = execute_run(task, outdir, every, None if topic is None else _report_to(topic))
    try:
        row["worker"] = get_worker().address
    except ValueError:
        row["worker"] = "local"
    return row


def whole_recipe_task(name: str, mode: str, outdir: str) -> dict:
    """The Dask task of a recipe without a plan: the whole recipe on a worker, into ``OUTDIR/NAME.runs/``
    (the calling process holds the final names; it moves the files there, :func:`_publish`)."""
    import os

    from .plan import runs_dir

    t0, c0 = time.perf_counter(), time.process_time()
    res = get_recipe(name).run(mode, runs_dir(name, outdir), overwrite=True)
    return dict(label=name, status=STATUS_DONE, file=str(res.data), result=(str(res.png), str(res.data),
                res.caption), pid=os.getpid(), wall_s=time.perf_counter() - t0, cpu_s=time.process_time() - c0)


def _publish(row: dict, outdir, overwrite) -> RecipeResult:
    """Move the files a whole-recipe task wrote under ``NAME.runs/`` to ``OUTDIR`` (atomically, each)."""
    from ..io.atomic import write_bytes

    png, data, cap = row["result"]
    out = []
    for src in (Path(png), Path(data)):
        out.append(write_bytes(Path(outdir) / src.name, src.read_bytes(), overwrite))
        src.unlink()
    try:
        Path(png).parent.rmdir()  # the staging folder, when the recipe left nothing else there
    except OSError:
        pass
    return RecipeResult(out[0], out[1], cap, row["wall_s"])


def _gather(client, submit, items: list, labels: list, retries: int, progress: Progress) -> list:
    """Run ``submit(item)`` futures to the end; a task lost with its worker is submitted again up to ``retries``
    times (it continues from its last checkpoint); a task failing in the physics is reported once."""
    from dask.distributed import as_completed

    futures = [submit(it) for it in items]
    which = {f.key: (i, 0) for i, f in enumerate(futures)}
    rows = [None] * len(items)
    ac = as_completed(futures)
    for fut in ac:
        i, tries = which.pop(fut.key)
        try:
            r = fut.result()
        except Exception as exc:
            if _infrastructure(exc) and client.status == "running" and tries < retries:
                progress.line(f"{labels[i]}: worker lost ({type(exc).__name__}); continuing it from its last "
                              "checkpoint on another worker")
                new = submit(items[i])
                which[new.key] = (i, tries + 1)
                ac.add(new)
                continue
            r = {"label": labels[i], "status": "failed", "error": f"{type(exc).__name__}: {exc}"}
        rows[i] = r
        progress.finished(r)
    return rows


def _open_client(client, scheduler, n_workers, dashboard):
    """``(client, owned client, owned cluster)`` in the order of the module docstring."""
    from dask.distributed import Client

    if client is not None:
        return client, None, None
    if scheduler is not None:
        c = connect(scheduler)
        return c, c, None
    c = running_client()
    if c is not None:
        return c, None, None
    cluster = local_cluster(n_workers, dashboard)
    c = Client(cluster)
    return c, c, cluster


def reproduce(name: str, mode: str = "full", outdir=".", *, client=None, scheduler: str | None = None,
              n_workers: int | None = None, retries: int = 2, progress: bool = True, overwrite: bool | None = None,
              partial: bool = False, orbits: float | None = None, checkpoint_every: float | None = None,
              dashboard: bool = False, stream=None) -> ReproduceResult:
    """Run recipe ``name`` with its independent runs as tasks on dask.distributed (module docstring).

    Parameters
    ----------
    name, mode : str
        The recipe (``ringcore reproduce --list``) and ``"quick"`` or ``"full"``.
    outdir : path
        Output folder: ``NAME.png``, ``NAME.nc`` and the run files in ``NAME.runs/``.
    client, scheduler, n_workers :
        The cluster: a ``distributed.Client``, a scheduler address ``tcp://HOST:PORT``, or the size of the
        LocalCluster (default: the CPUs of this process).
    retries : int
        How often a run lost with its worker is continued on another (0-20).
    progress : bool
        Progress per run and in all on ``stream`` (default stderr): bars on a terminal, else log lines.
    overwrite : bool, optional
        Replace existing ``NAME.png`` / ``NAME.nc`` (see :meth:`~ringcore.experiments.registry.Recipe.run`).
    partial : bool
        Compute nothing: draw ``NAME.partial.png`` / ``NAME.partial.nc`` from the runs finished so far and the
        last checkpoints of the others, marked as partial.
    orbits : float, optional
        Every run's length [orbits] instead of the recipe's (a trial; the caption says so).
    checkpoint_every : float, optional
        Orbits between checkpoints of each run (default: the recipe's, 10 quick / 5 full).

    Raises
    ------
    RunsFailed
        A run failed (each named with its error); the finished runs' files are kept for the next attempt.
    """
    check_choice("mode", mode, MODES)
    retries = check_int("retries", retries, 0, 20)
    n_workers = default_workers() if n_workers is None else check_int("n_workers", n_workers, 1, 512)
    plan = get_plan(name)
    out = Path(outdir)
    t0 = time.perf_counter()
    if plan is None:
        if partial or orbits is not None or checkpoint_every is not None:
            raise ValueError(f"recipe = {name!r} is computed as one piece: partial, orbits and checkpoint_every "
                             f"apply only to recipes made of runs ({', '.join(sorted(PLANS))})")
    else:
        tasks, settings = plan_tasks(name, mode, orbits)
        every = checkpoint_interval(name, mode, checkpoint_every)
        if partial:
            models, missing = read_runs(out, tasks, partial=True)
            if not models:
                raise FileNotFoundError(f"{out / (name + '.runs')}: no run of {name} ({mode}) has a checkpoint yet")
            note = partial_note(models, tasks) if missing else None
            res = plan.assemble(mode, out, models, settings, note or "PARTIAL (all runs finished)")
            return ReproduceResult(res, [], time.perf_counter() - t0, note)
    out.mkdir(parents=True, exist_ok=True)
    client, own, cluster = _open_client(client, scheduler, n_workers, dashboard)
    try:
        if plan is None:
            prog = Progress(name, [dict(label=name, orbits=0.0)], progress, stream)
            rows = _gather(client, lambda _: client.submit(whole_recipe_task, name, mode, str(out), pure=False),
                           [name], [name], retries, prog)
        else:
            topic = f"ringcore-reproduce-{uuid.uuid4().hex}"
            prog = Progress(name, tasks, progress, stream)
            for t in tasks:  # runs finished or checkpointed before: the bars start there
                prog.seen_checkpoint(t["label"], run_path(out, t))
            client.subscribe_topic(topic, prog.event)
            try:
                rows = _gather(client, lambda t: client.submit(run_task, t, str(out), every, topic, pure=False,
                                                               key=f"{name}-{t['label']}-{uuid.uuid4().hex[:8]}"),
                               tasks, [t["label"] for t in tasks], retries, prog)
            finally:
                client.unsubscribe_topic(topic)
        prog.close()
    finally:
        if own is not None:
            own.close()
        if cluster is not None:
            cluster.close()
    failed = [r for r in rows if r["status"] == "failed"]
    if failed:
        raise RunsFailed(f"{len(failed)} of {len(rows)} runs of {name} failed: " +
                         "; ".join(f"{r['label']}: {r['error']}" for r in failed) +
                         " (the finished runs are kept: fix the cause and re-issue the command)")
    if plan is None:
        return ReproduceResult(_publish(rows[0], out, overwrite), rows, time.perf_counter() - t0)
    models, missing = read_runs(out, tasks)
    if missing:  # a run file vanished or was replaced while assembling: never draw a wrong figure
        raise RunsFailed(f"runs {missing} of {name} have no finished run file in {out / (name + '.runs')}")
    import contextlib

    from ..io.atomic import output_policy

    with output_policy(overwrite) if overwrite is not None else contextlib.nullcontext():
        res = plan.assemble(mode, out, models, settings, None)
    wall = time.perf_counter() - t0
    return ReproduceResult(RecipeResult(res.png, res.data, res.caption, wall), rows, wall)


def rows_json(rows: list) -> str:
    """The per-run rows as JSON (for ``--json``)."""
    return json.dumps(rows, default=str)
