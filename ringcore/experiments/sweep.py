"""Parameter sweeps on dask.distributed.

A sweep is a list of *tasks* (plain dicts: ``{"engine": "hydro", "set": "tau15", "sigma0": 400, ...}``).
Each task runs in a worker process through the engine's runner (:data:`RUNNERS`), which writes
one run file at once and returns a small summary dict.  A task whose run file already exists
and is complete is skipped (its summary is read back), so a stopped sweep can simply be
started again.  Failures are collected with their error message, never dropped.

Runs on a client given (``client=``, e.g. of a dask-jobqueue cluster), a scheduler given by address
(``dask scheduler`` / ``dask worker ADDRESS``), a client already running in the process, or else a
``LocalCluster`` of one single-threaded worker process per CPU.  A task lost with its worker is run
again (``retries``); a task failing in the physics is reported once.  ``sweep.nc`` is a labelled grid
(:mod:`ringcore.io.sweep_grid`).
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import xarray as xr

from ..checks import check_choice, check_int
from ..io import RunFileError, netcdf_bytes, read_run, write_bytes
from ..io import reserve_output
from ..io.errors import output_error
from ..io.lock import HELD, key
from ..io.runfile import written_on
from ..provenance import software_attrs
from ..io.sweep_grid import as_runs, grid_dataset


def _runner(engine: str):
    """The runner of ``engine``: ``ringcore.experiments.runners.run_<engine>_task``, imported when a task
    runs (the runners load the engines, ~2 s; the command line's --help and argument checks do not)."""
    def run(task: dict, path):
        from . import runners

        return getattr(runners, f"run_{engine}_task")(task, path)
    return run


# engine -> function taking (task: dict, path: Path) and returning a summary dict
RUNNERS = {engine: _runner(engine) for engine in ("linear", "hydro", "nbody")}
SUMMARY_KEYS = ("lambda_p_m", "e_kin", "c_mean", "orbits", "wall_s")


def task_name(task: dict) -> str:
    """A stable, readable file stem for a task: engine, set, sigma0 and a short hash of the rest."""
    h = hashlib.sha1(json.dumps(task, sort_keys=True, default=str).encode()).hexdigest()[:8]
    return f"{task.get('engine')}_{task.get('set', 'x')}_s{float(task.get('sigma0', 0)):g}_{h}"


def _resolve(engine: str):
    check_choice("engine", engine, RUNNERS)
    return RUNNERS[engine]


def execute_task(task: dict, outdir: str) -> dict:
    """Run (or skip) one task in the current process; returns its summary with ``status``."""
    path = Path(outdir) / f"{task_name(task)}.nc"
    base = {"task": json.dumps(task, sort_keys=True), "file": str(path)}
    if path.exists():
        try:
            ds = read_run(path)
            if ds.attrs.get("complete", 0):
                summary = json.loads(ds.attrs["summary_json"])
                missing = _missing_keys(task, summary)
                if not missing:
                    return {**base, **summary, "status": "skipped"}
                # a file of an older ringcore without the whole summary: complete it from the task
                return {**base, **summary, **missing, "status": "skipped"}
        except (RunFileError, KeyError, ValueError):
            pass  # damaged or unfinished: run again
    t0 = time.perf_counter()
    try:
        summary = _resolve(task["engine"])(dict(task), path)
    except Exception as exc:  # reported, not dropped
        return {**base, "status": "failed", "error": f"{type(exc).__name__}: {exc}"}
    summary["wall_s"] = time.perf_counter() - t0
    return {**base, **summary, "status": "done"}


def _missing_keys(task: dict, summary: dict) -> dict:
    """Summary entries an older task file lacks: the comparison theory (recomputed from the task) and
    the wall time (unknown: nan)."""
    out = {}
    if task.get("engine") in ("hydro", "nbody") and "lambda_zero_m" not in summary:
        # deferred: .runners loads both numba engines (~2 s); a process that drives or reads sweeps needs neither
        from .runners import _theory, ring_params

        out.update(_theory(ring_params(task)))
    if "wall_s" not in summary:
        out["wall_s"] = math.nan
    return out


@dataclass
class SweepResult:
    """Per-task summaries and the aggregated dataset."""

    rows: list
    dataset: xr.Dataset
    failed: list = field(default_factory=list)
    wall_s: float = 0.0


def _num(v) -> float:
    return math.nan if v is None else float(v)


def aggregate(rows) -> xr.Dataset:
    """The labelled grid of the task summaries ``rows`` (:func:`ringcore.io.sweep_grid.grid_dataset`):
    one dimension per swept setting (``sigma0`` [kg m-2], ``ps_scale``, ``seed``, ...) with coordinates; every
    summary number a variable (nan where a task failed), ``e_kin`` in one unit whatever the engine."""
    ok = [r for r in rows if r["status"] in ("done", "skipped")]
    other_units = ("e_kin_rp", "e_kin_dimless")  # e_kin in other units or names: the grid has one e_kin
    keys = list(SUMMARY_KEYS) + sorted({k for r in ok for k, v in r.items()
                                        if isinstance(v, (int, float)) and k not in SUMMARY_KEYS and k not in other_units})
    return grid_dataset(rows, keys)


CONNECT_TIMEOUT_S = 5.0  # seconds to reach a --scheduler before giving up


def sweep_points(ds: xr.Dataset) -> list:
    """The finished runs of a sweep Dataset (``sweep.nc``, the grid of :func:`aggregate` or an older file's
    ``run`` layout: :func:`~ringcore.io.sweep_grid.as_runs`) as dicts: ``sigma0`` [kg/m^2],
    ``lambda_p_m`` [m], ``set``, ``isothermal``, ``engine`` (from the ``task`` coordinate; "?" if absent) and
    ``saturated`` (the per-run variable: True/False, None where it is missing or nan).  Runs without a
    finite sigma0 and lambda_p are left out."""
    ds = as_runs(ds)
    if "lambda_p_m" not in ds or "sigma0" not in ds.coords:
        return []
    n = ds.sizes.get("run", 0)
    tasks = ds["task"].values if "task" in ds.variables else [None] * n
    sat = ds["saturated"].values.astype(float) if "saturated" in ds else np.full(n, np.nan)
    pts = []
    for s, lam, t, ok in zip(ds["sigma0"].values, ds["lambda_p_m"].values, tasks, sat):
        if not (np.isfinite(s) and np.isfinite(lam)):
            continue
        task = json.loads(t) if isinstance(t, str) else {}
        pts.append(dict(sigma0=float(s), lambda_p_m=float(lam), set=task.get("set", "?"),
                        isothermal=bool(task.get("isothermal", False)), engine=task.get("engine", "?"),
                        saturated=bool(ok) if np.isfinite(ok) else None))
    return pts


def shipped_sweep_files(main: Path) -> list:
    """``main`` (a shipped ``saturation_sweep.nc``) and every ``saturation_sweep_*.nc`` next to it."""
    main = Path(main)
    return [main, *sorted(main.parent.glob("saturation_sweep_*.nc"))]


class SchedulerUnreachable(ConnectionError):
    """The dask scheduler given by address cannot be reached (one-line message)."""


def connect(address: str, timeout: float = CONNECT_TIMEOUT_S):
    """A ``dask.distributed.Client`` of the scheduler at ``address``; :class:`SchedulerUnreachable`
    (one line) if it cannot be reached within ``timeout`` seconds."""
    from dask.distributed import Client
    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        proto, loc = parse_address(address)
        if proto in ("tcp", "tls"):
            parse_host_port(loc)
    except (ValueError, TypeError) as exc:
        raise ValueError(f"scheduler = {address!r} is not a scheduler address ({exc}): give tcp://HOST:PORT") from None
    try:
        return Client(address, timeout=f"{timeout:g}s")
    except (OSError, TimeoutError, ValueError) as exc:
        why = " ".join(str(exc).split()).split(": ")[-1][:160] or type(exc).__name__
        raise SchedulerUnreachable(f"cannot reach the dask scheduler at {address!r} within {timeout:g} s "
                                   f"({why}); start it (dask scheduler) or drop --scheduler") from None


def default_workers() -> int:
    """Worker processes of a local cluster sized to this machine: the CPUs this process may run on."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # not on Linux
        return max(1, os.cpu_count() or 1)


def running_client():
    """The ``dask.distributed.Client`` already running in this process (the default client), or None."""
    try:
        from distributed import default_client
    except ImportError:  # pragma: no cover - dask.distributed is a dependency
        return None
    try:
        c = default_client()
    except ValueError:  # no client
        return None
    return c if c.status == "running" else None


def _infrastructure(exc: BaseException) -> bool:
    """True for a failure of the cluster, not of the task: a worker died (KilledWorker), a connection closed,
    the task was cancelled with its worker.  Physics errors never get here (:func:`execute_task` reports them)."""
    from distributed import KilledWorker
    from distributed.comm.core import CommClosedError

    import asyncio
    import concurrent.futures

    return isinstance(exc, (KilledWorker, CommClosedError, OSError, asyncio.CancelledError,
                            concurrent.futures.CancelledError))


def _collect(client, tasks, outdir: str, retries: int, progress: bool) -> list:
    """Submit every task and gather the summaries; a task lost to the cluster is submitted again up to
    ``retries`` times (dask's own ``retries=`` covers an exception raised on the worker outside the task)."""
    from dask.distributed import as_completed
    from ..log import progress_bar as tqdm

    futures = client.map(execute_task, tasks, outdir=outdir, pure=False, retries=retries)
    which = {f.key: (i, 0) for i, f in enumerate(futures)}
    rows, bar = [], tqdm(total=len(futures), desc="sweep", unit="run", disable=not progress)
    ac = as_completed(futures)
    for fut in ac:
        i, tries = which.pop(fut.key)
        try:
            r = fut.result()
        except Exception as exc:
            if not _infrastructure(exc) or client.status != "running":
                raise
            if tries < retries:
                bar.write(f"retrying {task_name(tasks[i])} ({type(exc).__name__}: {exc})")
                new = client.submit(execute_task, tasks[i], outdir=outdir, pure=False, retries=retries)
                which[new.key] = (i, tries + 1)
                ac.add(new)
                continue
            path = Path(outdir) / f"{task_name(tasks[i])}.nc"
            r = {"task": json.dumps(tasks[i], sort_keys=True), "file": str(path), "status": "failed",
                 "error": f"{type(exc).__name__} after {tries + 1} attempts: {exc}"}
        rows.append(r)
        if r["status"] == "failed":
            bar.write(f"FAILED {r['file']}: {r['error']}")
        bar.update(1)
    bar.close()
    return rows


def local_cluster(n_workers: int, dashboard: bool = True):
    """The sweep's own ``LocalCluster``: ``n_workers`` single-threaded processes, everything on 127.0.0.1.

    The dashboard has no login, so it listens on this machine only (a free port; ``ssh -L`` reaches it from
    elsewhere).  Without a dashboard the scheduler still starts its HTTP server (health routes), on port
    8787 unless told otherwise: a free localhost port keeps a second sweep or the lab from colliding.
    """
    from dask.distributed import LocalCluster  # deferred on purpose: dask.distributed is slow to import

    from .. import threads

    extra = {} if dashboard else {"scheduler_kwargs": {"dashboard": False, "dashboard_address": "127.0.0.1:0"}}
    # each run's threads: the machine's cores shared among the workers (more threads than cores would make
    # every run wait for the others), unless RINGCORE_THREADS (ringcore sweep --threads) says otherwise
    per_run = os.environ.get(threads.ENV) or str(max(1, threads.available() // max(1, n_workers)))
    return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                        dashboard_address="127.0.0.1:0" if dashboard else None, env={threads.ENV: per_run}, **extra)


def run_sweep(tasks, outdir, scheduler: str | None = None, n_workers: int | None = None, progress: bool = True,
              dashboard: bool = True, attrs: dict | None = None, client=None, retries: int = 2) -> SweepResult:
    """Run ``tasks`` on dask.distributed and write each result file as soon as it is done.

    The cluster, in this order: ``client``; the scheduler at ``scheduler``; a client already running in this
    process (``distributed.default_client()``, e.g. one made for a dask-jobqueue cluster); else a new
    ``LocalCluster`` of ``n_workers`` single-threaded processes, closed at the end.  A client given or found is
    left open.  The folder is reserved (``OUTDIR/.sweep.nc.lock``) while the sweep runs: a second sweep into
    the same folder is refused at once (:class:`~ringcore.io.atomic.OutputBusy`).

    Parameters
    ----------
    tasks : list of dict
        Each with an ``engine`` key (one of RUNNERS) and the engine's settings.
    outdir : path
        Folder for the run files and ``sweep.nc`` (:func:`aggregate`, a labelled grid).
    scheduler : str, optional
        Address of a running dask scheduler (``tcp://host:8786``).
    n_workers : int, optional
        Worker processes of the LocalCluster (1 thread each); default :func:`default_workers`.
    attrs : dict, optional
        Global attributes of ``sweep.nc`` (provenance), written atomically with it.
    client : distributed.Client, optional
        A client of a running cluster (dask-jobqueue, a LocalCluster of the caller).
    retries : int
        How often a task lost to the cluster (a worker died: ``KilledWorker``, ``CommClosedError``) is run
        again, 0 to 20.  A task that fails in the physics (bad parameters, blow-up) is reported once, never
        retried.

    Returns
    -------
    SweepResult
        Per-task rows, the aggregate dataset (also written to ``OUTDIR/sweep.nc``), failures, wall time [s].
    """
    from dask.distributed import Client

    tasks = list(tasks)
    for t in tasks:
        _resolve(t.get("engine"))
    n_workers = default_workers() if n_workers is None else check_int("n_workers", n_workers, 1, 512)
    retries = check_int("retries", retries, 0, 20)
    out = Path(outdir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(exc, out) from None
    target = out / "sweep.nc"
    # one sweep per folder at a time (the command line reserves the folder itself, for its figure too)
    held = None if key(target) in HELD else reserve_output(target, overwrite=True, label="outdir", utf8=True)
    t0 = time.perf_counter()
    cluster = own = None
    try:
        if client is None and scheduler is not None:
            client = own = connect(scheduler)
        elif client is None:
            client = running_client()
        if client is None:
            cluster = local_cluster(n_workers, dashboard)
            client = own = Client(cluster)
        try:
            if progress and client.dashboard_link:
                print(f"dask dashboard: {client.dashboard_link}", flush=True)
            rows = _collect(client, tasks, str(out), retries, progress)
        finally:
            if own is not None:
                own.close()
            if cluster is not None:
                cluster.close()
        ds = aggregate(rows)
        ds.attrs.update(**software_attrs(), created=datetime.now(timezone.utc).isoformat(timespec="seconds"),
                        written_on=written_on())
        ds.attrs.update(attrs or {})
        write_bytes(target, netcdf_bytes(ds))  # atomic: a failed write never leaves a half sweep.nc
    finally:
        if held is not None:
            held.release()
    failed = [r for r in rows if r["status"] == "failed"]
    return SweepResult(rows=rows, dataset=ds, failed=failed, wall_s=time.perf_counter() - t0)
