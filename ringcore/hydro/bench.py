"""``ringcore bench hydro [--json] [--quick]``: speed of the 1D hydro scheme.

For the isothermal and the non-isothermal model (tau15, sigma0 = 400 kg/m^2, self-gravity by
the FFT mode method, h = 2.5 m) at n = 2,000 and 8,000 nodes: nanoseconds per node per RK
stage (full steps including the FFTs; CPU time of the process, best of several repeats, so that
other jobs on a shared machine do not inflate it; the code is single-threaded), time steps per orbit of
the paper's criterion (f_t = 0.1) and of the fast "cfl" option, both for the weakly perturbed
initial state (nonlinear states need more), and simulated orbits per wall-clock minute.

JSON (one object): ``{"engine": "hydro", "quick": bool, "numba": str, "pyfftw": bool,
"configs": [{"model", "n", "h_m", "ns_per_cell_stage", "steps_per_orbit",
"orbits_per_minute", "steps_per_orbit_fast", "orbits_per_minute_fast"}, ...]}``.
"""
from __future__ import annotations

import json
import math
import time

import numba

from .. import params
from .gravity import HAVE_PYFFTW
from .options import HydroOptions
from .solver import Hydro1D
from .timestep import FAST_DT_FACTOR

H_M = 2.5  # [m]


def _measure(iso: bool, n: int, quick: bool) -> dict:
    p = params.get("tau15", sigma0=400.0, isothermal=iso)
    opt = HydroOptions(L_x=n * H_M, h=H_M, gravity="mode")
    sim = Hydro1D(p, opt, initial="noise", seed=1)
    sim.step()  # compile / warm up
    reps, nstep = (3, 20) if quick else (7, 60)
    best = math.inf
    for _ in range(reps):
        t0 = time.process_time()
        for _ in range(nstep):
            sim.step()
        best = min(best, (time.process_time() - t0) / nstep)
    ns = best / (5 * n) * 1e9
    spo = 2 * math.pi / sim.stable_dt()
    fast = Hydro1D(p, HydroOptions(L_x=n * H_M, h=H_M, timestep="cfl"), initial="noise", seed=1)
    spo_fast = 2 * math.pi / fast.stable_dt()
    return dict(model=p.model, n=n, h_m=H_M, ns_per_cell_stage=round(ns, 2), steps_per_orbit=round(spo, 1),
                orbits_per_minute=round(60.0 / (spo * best), 2), steps_per_orbit_fast=round(spo_fast, 1),
                orbits_per_minute_fast=round(60.0 / (spo_fast * best), 2))


def run_bench(as_json: bool = False, quick: bool = False, threads=None) -> int:
    """Run the benchmark and print a table (or one JSON object); returns the exit status 0."""
    configs = [_measure(iso, n, quick) for iso in (True, False) for n in (2000, 8000)]
    if as_json:
        print(json.dumps(dict(engine="hydro", quick=bool(quick), numba=numba.__version__, pyfftw=HAVE_PYFFTW,
                              fast_dt_factor=FAST_DT_FACTOR, configs=configs)))
        return 0
    print(f"ringcore hydro benchmark (tau15, sigma0 = 400 kg/m^2, self-gravity, h = {H_M} m; "
          f"fast = 'cfl' f_t = {FAST_DT_FACTOR})")
    print(f"{'model':14s} {'n':>6s} {'ns/cell/stage':>14s} {'steps/orbit':>12s} {'orbits/min':>11s} "
          f"{'steps/orbit fast':>17s} {'orbits/min fast':>16s}")
    for c in configs:
        print(f"{c['model']:14s} {c['n']:6d} {c['ns_per_cell_stage']:14.1f} {c['steps_per_orbit']:12.0f} "
              f"{c['orbits_per_minute']:11.1f} {c['steps_per_orbit_fast']:17.0f} {c['orbits_per_minute_fast']:16.1f}")
    return 0
