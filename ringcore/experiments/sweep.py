"""Parameter sweeps on dask.distributed.

A sweep is a list of *tasks* (plain dicts: ``{"engine": "hydro", "set": "tau15", "sigma0": 400, ...}``).
Each task runs in a worker process through the engine's runner (:data:`RUNNERS`), which writes
one run file at once and returns a small summary dict.  A task whose run file already exists
and is complete is skipped (its summary is read back), so a stopped sweep can simply be
started again.  Failures are collected with their error message, never dropped.

Runs on a ``LocalCluster`` (one single-threaded worker process per core) by default, or on
any running scheduler (``dask scheduler`` / ``dask worker ADDRESS``, or dask-jobqueue on HPC)
given its address.
"""
from __future__ import annotations

import hashlib
import importlib
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..checks import check_choice, check_int
from ..io import RunFileError, netcdf_bytes, read_run, write_bytes
from ..io.errors import output_error

# engine -> "module:function" taking (task: dict, path: Path) and returning a summary dict
RUNNERS = {
    "linear": "ringcore.experiments.runners:run_linear_task",
    "hydro": "ringcore.experiments.runners:run_hydro_task",
    "nbody": "ringcore.experiments.runners:run_nbody_task",
}
SUMMARY_KEYS = ("lambda_p_m", "e_kin", "c_mean", "orbits", "wall_s")


def task_name(task: dict) -> str:
    """A stable, readable file stem for a task: engine, set, sigma0 and a short hash of the rest."""
    h = hashlib.sha1(json.dumps(task, sort_keys=True, default=str).encode()).hexdigest()[:8]
    return f"{task.get('engine')}_{task.get('set', 'x')}_s{float(task.get('sigma0', 0)):g}_{h}"


def _resolve(engine: str):
    check_choice("engine", engine, RUNNERS)
    mod, fn = RUNNERS[engine].split(":")
    return getattr(importlib.import_module(mod), fn)


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
    """One dataset with one entry per successful task (dimension ``run``)."""
    ok = [r for r in rows if r["status"] in ("done", "skipped")]
    keys = list(SUMMARY_KEYS) + sorted({k for r in ok for k, v in r.items()
                                        if isinstance(v, (int, float)) and k not in SUMMARY_KEYS})
    data = {k: ("run", np.array([_num(r.get(k)) for r in ok])) for k in keys}
    tasks = [json.loads(r["task"]) for r in ok]
    coords = {"sigma0": ("run", np.array([float(t.get("sigma0", math.nan)) for t in tasks]), {"units": "kg m-2"}),
              "task": ("run", np.array([r["task"] for r in ok], dtype=object)),
              "file": ("run", np.array([r["file"] for r in ok], dtype=object))}
    ds = xr.Dataset(data, coords=coords)
    units = {"lambda_p_m": "m", "e_kin": "sigma0 c0^2 (dimensionless)", "c_mean": "m s-1", "orbits": "orbits",
             "wall_s": "s"}
    units.update(lambda_zero_m="m", lambda_max_growth_m="m", lambda_p_mean_m="m", lambda_p_psd_m="m",
                 lambda_p_empirical_m="m", e_kin_rp="sigma0 (R_p Omega)^2 with R_p = 1 m")
    if {t.get("engine") for t in tasks} == {"nbody"}:
        units["e_kin"] = "sigma0 (R_p Omega)^2 with R_p = 1 m"
    for k, u in units.items():
        if k in ds:
            ds[k].attrs["units"] = u
    return ds.sortby("sigma0") if ds.sizes.get("run", 0) else ds


CONNECT_TIMEOUT_S = 5.0  # seconds to reach a --scheduler before giving up


def sweep_points(ds: xr.Dataset) -> list:
    """The runs of a sweep Dataset (:func:`aggregate`'s ``sweep.nc``) as dicts: ``sigma0`` [kg/m^2],
    ``lambda_p_m`` [m], ``set``, ``isothermal``, ``engine`` (from the ``task`` coordinate; "?" if absent) and
    ``saturated`` (the per-run variable: True/False, None where it is missing or nan).  Runs without a
    finite sigma0 and lambda_p are left out."""
    if "lambda_p_m" not in ds or "sigma0" not in ds.coords:
        return []
    n = ds.sizes.get("run", 0)
    tasks = ds["task"].values if "task" in ds.coords else [None] * n
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


def run_sweep(tasks, outdir, scheduler: str | None = None, n_workers: int = 2, progress: bool = True,
              dashboard: bool = True, attrs: dict | None = None) -> SweepResult:
    """Run ``tasks`` on dask.distributed and write each result file as soon as it is done.

    Parameters
    ----------
    tasks : list of dict
        Each with an ``engine`` key (one of RUNNERS) and the engine's settings.
    outdir : path
        Folder for the run files and ``sweep.nc`` (aggregate).
    scheduler : str, optional
        Address of a running dask scheduler (``tcp://host:8786``); default: a LocalCluster.
    n_workers : int
        Worker processes of the LocalCluster (1 thread each).
    attrs : dict, optional
        Global attributes of ``sweep.nc`` (provenance), written atomically with it.
    """
    from dask.distributed import Client, LocalCluster, as_completed
    from tqdm.auto import tqdm

    tasks = list(tasks)
    for t in tasks:
        _resolve(t.get("engine"))
    n_workers = check_int("n_workers", n_workers, 1, 512)
    out = Path(outdir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(exc, out) from None
    t0 = time.perf_counter()
    cluster = None
    if scheduler is not None:
        client = connect(scheduler)
    else:
        cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0" if dashboard else None)
        client = Client(cluster)
    rows = []
    try:
        if progress and client.dashboard_link:
            print(f"dask dashboard: {client.dashboard_link}", flush=True)
        futures = client.map(execute_task, tasks, outdir=str(out), pure=False)
        bar = tqdm(total=len(futures), desc="sweep", unit="run", disable=not progress)
        for fut in as_completed(futures):
            r = fut.result()
            rows.append(r)
            if r["status"] == "failed":
                bar.write(f"FAILED {r['file']}: {r['error']}")
            bar.update(1)
        bar.close()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    ds = aggregate(rows)
    ds.attrs.update(attrs or {})
    write_bytes(out / "sweep.nc", netcdf_bytes(ds))  # atomic: a failed write never leaves a half sweep.nc
    failed = [r for r in rows if r["status"] == "failed"]
    return SweepResult(rows=rows, dataset=ds, failed=failed, wall_s=time.perf_counter() - t0)
