"""``ringcore bench hydro [--json] [--quick] [--threads 1,2] [--cells 1000,4000]``: speed of the 1D hydro scheme.

For the isothermal and the non-isothermal model (tau15, sigma0 = 400 kg/m^2, self-gravity by
the FFT mode method, h = 2.5 m) at n = 2,000 and 8,000 nodes: nanoseconds per node per RK
stage (full steps including the FFTs; CPU time of the process, best of several repeats, so that
other jobs on a shared machine do not inflate it; the code is single-threaded), time steps per orbit of
the paper's criterion (f_t = 0.1) and of the fast "cfl" option, both for the weakly perturbed
initial state (nonlinear states need more), and simulated orbits per wall-clock minute; these on one
thread.  Then the threads: the non-isothermal 10 km box at h = 2.5 m (4,000 nodes), wall time per step
at each of ``threads`` (default 1 and the cores this process may use), alternated, best of several
repeats, and the speed-up over the first (the states are the same bits; measure on a quiet machine).

JSON (one object): ``{"engine": "hydro", "quick": bool, "numba": str, "pyfftw": bool,
"configs": [{"model", "n", "h_m", "ns_per_cell_stage", "steps_per_orbit",
"orbits_per_minute", "steps_per_orbit_fast", "orbits_per_minute_fast"}, ...],
"threads": {"n": 4000, "h_m": 2.5, "by_threads": {"1": {"us_per_step", "speedup"}, ...}}}``.
"""
from __future__ import annotations

import json
import math
import time

import numba

from .. import params
from .. import threads as TH
from .gravity import HAVE_PYFFTW
from .options import HydroOptions
from .solver import Hydro1D
from .timestep import FAST_DT_FACTOR

H_M = 2.5  # [m]


def _measure(iso: bool, n: int, quick: bool) -> dict:
    p = params.get("tau15", sigma0=400.0, isothermal=iso)
    opt = HydroOptions(L_x=n * H_M, h=H_M, gravity="mode")
    sim = Hydro1D(p, opt, initial="noise", seed=1, threads=1)
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


def _threads(threads: tuple, quick: bool, n: int = 4000) -> dict:
    """Wall time per step of the non-isothermal n-node box at h = 2.5 m per thread count: bursts of a few
    steps (about 20,000 node-steps) per thread count in turn, best burst of many, and the process's CPU
    time per step over all bursts; ``same_bits``: the states agree after the same steps."""
    p = params.get("tau15", sigma0=400.0, isothermal=False)
    sims = {th: Hydro1D(p, HydroOptions(L_x=n * H_M, h=H_M), initial="noise", seed=1, threads=th) for th in threads}
    for sim in sims.values():
        sim.step()  # compile / warm up
    k = max(2, 20000 // n)
    reps = max(4, (12 if quick else 40) * 4000 // max(n, 4000))
    best = {th: math.inf for th in threads}
    cpu = {th: 0.0 for th in threads}
    for r in range(reps):
        for th in (threads if r % 2 == 0 else threads[::-1]):
            c0 = time.process_time()
            t0 = time.perf_counter()
            for _ in range(k):
                sims[th].step()
            best[th] = min(best[th], (time.perf_counter() - t0) / k)
            cpu[th] += time.process_time() - c0
    first = best[threads[0]]
    sums = {sim.snapshot().checksum() for sim in sims.values()}
    return dict(n=n, h_m=H_M, same_bits=len(sums) == 1,
                by_threads={str(th): dict(us_per_step=round(b * 1e6, 1), speedup=round(first / b, 3),
                                          cpu_us_per_step=round(cpu[th] / (reps * k) * 1e6, 1),
                                          windows=int(sims[th]._tw[3].shape[0]))
                            for th, b in best.items()})


def _print_threads(rows: list) -> None:
    print(f"threads, non-isothermal tau15, h = {H_M} m, self-gravity; wall time per step (best burst), "
          "CPU time per step (all threads), windows (1: one-thread step)")
    print(f"{'cells':>7s} {'threads':>7s} {'windows':>7s} {'us/step':>10s} {'speed-up':>9s} {'CPU us/step':>12s}  same bits")
    for row in rows:
        for th, v in row["by_threads"].items():
            print(f"{row['n']:7d} {th:>7s} {v['windows']:7d} {v['us_per_step']:10.1f} {v['speedup']:8.2f}x "
                  f"{v['cpu_us_per_step']:12.1f}  {row['same_bits']}")


def run_bench(as_json: bool = False, quick: bool = False, threads=None, cells=None) -> int:
    """Run the benchmark and print a table (or one JSON object); returns the exit status 0.  With ``cells``
    (node counts) only the thread scaling at those grid sizes is measured."""
    threads = tuple(dict.fromkeys(TH.check(t, "--threads") for t in (threads or (1, TH.available()))))
    if cells:
        rows = [_threads(threads, quick, int(n)) for n in cells]
        if as_json:
            print(json.dumps(dict(engine="hydro", quick=bool(quick), numba=numba.__version__, scaling=rows)))
        else:
            _print_threads(rows)
        return 0
    configs = [_measure(iso, n, quick) for iso in (True, False) for n in (2000, 8000)]
    thr = _threads(threads, quick)
    if as_json:
        print(json.dumps(dict(engine="hydro", quick=bool(quick), numba=numba.__version__, pyfftw=HAVE_PYFFTW,
                              fast_dt_factor=FAST_DT_FACTOR, configs=configs, threads=thr)))
        return 0
    print(f"ringcore hydro benchmark (tau15, sigma0 = 400 kg/m^2, self-gravity, h = {H_M} m; "
          f"fast = 'cfl' f_t = {FAST_DT_FACTOR})")
    print(f"{'model':14s} {'n':>6s} {'ns/cell/stage':>14s} {'steps/orbit':>12s} {'orbits/min':>11s} "
          f"{'steps/orbit fast':>17s} {'orbits/min fast':>16s}")
    for c in configs:
        print(f"{c['model']:14s} {c['n']:6d} {c['ns_per_cell_stage']:14.1f} {c['steps_per_orbit']:12.0f} "
              f"{c['orbits_per_minute']:11.1f} {c['steps_per_orbit_fast']:17.0f} {c['orbits_per_minute_fast']:16.1f}")
    _print_threads([thr])
    return 0
