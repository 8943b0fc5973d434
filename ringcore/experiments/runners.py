"""Task runners for sweeps: ``run_<engine>_task(task, path) -> summary``.

Each runner builds the model from the task dict, runs it, writes ONE run file at ``path``
with the attributes ``complete = 1`` and ``summary_json`` (what :func:`sweep.execute_task`
reads back to skip finished runs) and returns the summary dict.

The hydro and N-body runners write checkpoints (``complete = 0``) while they run and continue
an unfinished file of the same task, so a stopped sweep loses at most one checkpoint interval.
Their defaults (:data:`HYDRO_DEFAULTS`, :data:`NBODY_DEFAULTS`) are chosen for a quick sweep
on a few cores, not for the paper's box sizes; override them with the task keys ``lx``,
``h`` (hydro), ``ly`` (N-body), ``orbits``, ``checkpoint_every``.
"""
from __future__ import annotations

import json
import math
import time

import numpy as np
import xarray as xr

from .. import linear, params
from ..analysis.saturation import C_EMPIRICAL
from ..hydro import Hydro1D, HydroOptions
from ..io import RunFileError, attrs_from_dict, read_run, write_run
from ..nbody import NBodyOptions, ShearingBox
from ..spec import RunSpec, resolve
from .checkpoint import engine_class, run_checkpointed

# hydro: L_x = 3 km (about 20 wavelengths of the saturated wave at sigma0 = 400), h = 2.5 m as in the
# paper, 300 orbits, the fast "cfl" time step (f_t = FAST_DT_FACTOR), 10 samples per orbit, white noise
# of amplitude 1e-4 down to 50 m, and a temperature floor of 0.01 T0 (long nonlinear runs; see HydroOptions)
HYDRO_DEFAULTS = dict(lx=3000.0, h=2.5, orbits=300.0, samples_per_orbit=10, timestep="cfl", T_floor=0.01,
                      amplitude=1e-4, lambda_min=50.0, checkpoint_every=50.0)
# N-body: 400 m x 10 m box (about 1,900 particles at tau = 1.5), Bridges law, 1,000 steps per orbit,
# 100 orbits, box means every 0.5 orbit, profiles every 5 orbits
NBODY_DEFAULTS = dict(lx=400.0, ly=10.0, orbits=100.0, dt_orbit=1e-3, record_every=0.5, profile_every=5.0,
                      checkpoint_every=10.0)
SUMMARY_FRACTION = 0.25  # summaries average over the last quarter of the run


def ring_params(task: dict) -> params.RingParams:
    """RingParams of a task (keys set, sigma0, isothermal, p_s, ps_scale, beta) through the one resolver
    :func:`ringcore.spec.resolve` (``p_s`` only with the isothermal model)."""
    return resolve(RunSpec.from_mapping(task))[0]


def _nan(x):
    return None if x is None or (isinstance(x, float) and not math.isfinite(x)) else x


def summary_attr(summary: dict) -> str:
    """The ``summary_json`` attribute of a finished task file: the WHOLE task summary plus its wall
    time ``wall_s`` (non-finite numbers as null), so that a re-run that skips the task reads back
    every column of ``sweep.nc``."""
    return json.dumps({k: _nan(v) for k, v in summary.items()})


def run_linear_task(task: dict, path) -> dict:
    """Linear-theory 'run': lambda_zero, fastest-growing wavelength and rate (seconds per task)."""
    t0 = time.perf_counter()
    p = ring_params(task)
    s = linear.summary(p)
    summary = {"lambda_zero_m": s.lambda_zero_m, "lambda_max_growth_m": s.lambda_max_growth_m,
               "max_growth_rate": s.max_growth_rate, "Q0": s.Q0}
    lam = np.geomspace(20, 5000, 200)
    d = linear.dispersion(p, lam)
    ds = xr.Dataset({"growth_rate": ("wavelength", d.growth_rate, {"units": "Omega"}),
                     "frequency": ("wavelength", d.frequency, {"units": "Omega"})},
                    coords={"wavelength": ("wavelength", lam, {"units": "m"})})
    ds.attrs.update(attrs_from_dict("param", p.as_dict()))
    ds.attrs.update(complete=1, summary_json=summary_attr({**summary, "wall_s": time.perf_counter() - t0}))
    write_run(ds, path, kind="linear")
    return summary


def _theory(p) -> dict:
    """lambda_zero and C_EMPIRICAL lambda_zero (Eq. (55)) of the task's parameters, for comparison."""
    if p.sigma0 <= 0:
        return {"lambda_zero_m": math.nan, "lambda_p_empirical_m": math.nan}
    try:
        lz = linear.lambda_zero(p)
    except ValueError:  # no lambda_zero (Q0 < 1): nothing to compare with
        lz = math.nan
    return {"lambda_zero_m": lz, "lambda_p_empirical_m": C_EMPIRICAL * lz}


def _continue_or_new(path, task_json: str, kind: str, make):
    """The unfinished model of the same task saved at ``path``, or ``make()``."""
    try:
        ds = read_run(path, kind=kind)
        if ds.attrs.get("task_json") == task_json and not ds.attrs.get("complete", 0):
            return engine_class(kind).from_dataset(ds)
    except RunFileError:
        pass
    return make()


def _run_engine_task(task: dict, path, kind: str, defaults: dict, make) -> dict:
    t0 = time.perf_counter()
    cfg = {**defaults, **{k: v for k, v in task.items() if k in defaults and v is not None}}
    p = ring_params(task)
    task_json = json.dumps(task, sort_keys=True)
    model = _continue_or_new(path, task_json, kind, lambda: make(p, cfg, task))
    run_checkpointed(model, until=float(cfg["orbits"]), out=path, every=float(cfg["checkpoint_every"]),
                     progress=False, finish=False, task_json=task_json)
    summary = {**model.summary(SUMMARY_FRACTION), **_theory(p)}
    model.save(path, complete=True, task_json=task_json,
               summary_json=summary_attr({**summary, "wall_s": time.perf_counter() - t0}))
    return summary


def _make_hydro(p, cfg, task):
    opt = HydroOptions(L_x=float(cfg["lx"]), h=float(cfg["h"]), timestep=cfg["timestep"],
                       samples_per_orbit=int(cfg["samples_per_orbit"]), T_floor=float(cfg["T_floor"]))
    return Hydro1D(p, opt, initial="noise", seed=int(task.get("seed", 0)), amplitude=float(cfg["amplitude"]),
                   lambda_min=float(cfg["lambda_min"]))


def _make_nbody(p, cfg, task):
    opt = NBodyOptions(L_x=float(cfg["lx"]), L_y=float(cfg["ly"]), dt_orbit=float(cfg["dt_orbit"]),
                       record_every=float(cfg["record_every"]), profile_every=float(cfg["profile_every"]))
    return ShearingBox(p, opt, seed=int(task.get("seed", 0)))


def run_hydro_task(task: dict, path) -> dict:
    """Hydro run from white noise (:data:`HYDRO_DEFAULTS`; task keys set, sigma0, ps_scale, isothermal,
    seed, lx, h, orbits).  Summary: lambda_p_m (most frequent sampled prevalent wavelength over the last
    quarter), lambda_p_psd_m, lambda_p_mean_m, e_kin (mean, sigma0 (R_p Omega)^2), e_kin_dimless (the same in sigma0 c0^2), c_mean (mass-weighted
    sqrt(T) of the final state, m/s), orbits, steps, lambda_zero_m, lambda_p_empirical_m (1.4 lambda_zero)."""
    return _run_engine_task(task, path, "hydro", HYDRO_DEFAULTS, _make_hydro)


def run_nbody_task(task: dict, path) -> dict:
    """N-body run from a uniform random state (:data:`NBODY_DEFAULTS`; task keys set, sigma0, seed, lx, ly,
    orbits).  Summary: lambda_p_m (most frequent recorded prevalent wavelength over the last quarter),
    lambda_p_mean_m, e_kin (sigma0 (R_p Omega)^2), c_mean (m/s), orbits, N, lambda_zero_m,
    lambda_p_empirical_m.  The hydro-only keys ps_scale, p_s and isothermal change only the comparison theory."""
    return _run_engine_task(task, path, "nbody", NBODY_DEFAULTS, _make_nbody)
