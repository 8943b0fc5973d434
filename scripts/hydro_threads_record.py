"""Where a hydro step goes, what a thread synchronisation costs, and the 2-thread speed-up per grid size.

    .venv/bin/python scripts/hydro_threads_record.py [--cells 1000,2000,4000,16000,64000] [--rt]
        [--record docs/benchmarks/data/hydro_threads.json]

1. The parts of a step of the non-isothermal tau15 box (sigma0 = 400 kg/m^2, h = 2.5 m, self-gravity) at
   4,000 nodes on one thread, best of many calls: the FFT self-gravity, the fluxes (primitives, flux
   splitting, MP5, derivatives), the sources, the stage update, the state check.
2. Synchronisation: entering an empty numba parallel region of 2 threads, back to back and after 300 us of
   other work (the waiting OpenMP threads sleep); the team's spin hand-over.
3. Per grid size: wall time per step on 1 and 2 threads (bursts of about 20,000 node-steps, alternated,
   best burst) and whether the states are the same bits.

``--rt``: every timed burst runs at real-time priority (SCHED_FIFO 1, all threads of the process; needs the
right to set it), followed by a sleep ten times as long at normal priority: on a machine shared with other
jobs this measures what a quiet machine would, while taking under 10 % of the machine.  Without it the
bursts run at normal priority (on a loaded machine the 2-thread figures then say little).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np
from numba import njit, prange

from ringcore import params
from ringcore import threads as TH
from ringcore.hydro import Hydro1D, HydroOptions, threaded
from ringcore.hydro import kernels as K
from ringcore.hydro.fftw import convolve

RT = False


def _policy(on: bool) -> None:
    if not RT:
        return
    for t in os.listdir("/proc/self/task"):
        try:
            os.sched_setscheduler(int(t), os.SCHED_FIFO if on else os.SCHED_OTHER, os.sched_param(1 if on else 0))
        except OSError:
            pass


def _best(fn, reps):
    b = math.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        fn()
        b = min(b, time.perf_counter() - t0)
    return b * 1e6


def _sim(n, th):
    p = params.get("tau15", sigma0=400.0, isothermal=False)
    return Hydro1D(p, HydroOptions(L_x=n * 2.5, h=2.5), initial="noise", seed=1, threads=th)


def profile(n=4000) -> dict:
    sim = _sim(n, 1)
    sim.step()
    U, W, L, NG = sim._U[0], sim._W, sim._L[0], K.NG
    ka = sim.gravity.kernel_args
    o = sim._U[1]
    _policy(True)
    try:
        out = dict(
            step=_best(sim.step, 100),
            fft=_best(lambda: convolve(U[0, NG:NG + n], *ka), 300),
            fluxes=_best(lambda: K.rhs_fluxes(U, W, sim._beta, sim._par, False), 300),
            maxima_extra=_best(lambda: K.rhs_fluxes(U, W, sim._beta, sim._par, True), 300),
            sources=_best(lambda: K.rhs_sources(U, W, sim.gravity.g, sim._par, L), 300),
            update=_best(lambda: [K._update(o[k], U[k], 0.3, L[k], 0.1, U[k], 0.2, U[k], 0.1, L[k], 0.1, True)
                                  for k in range(4)], 300),
            check=_best(lambda: K.check_state(U), 300))
    finally:
        _policy(False)
    out["maxima_extra"] -= out["fluxes"]
    return {k: round(v, 1) for k, v in out.items()}


@njit(parallel=True, nogil=True)
def _empty(a):
    for c in prange(a.shape[0]):
        a[c] += 1.0


def sync() -> dict:
    TH.use(2)
    a = np.zeros(2)
    _empty(a)
    _policy(True)
    back = [_best(lambda: _empty(a), 1) for _ in range(2000)]
    after = []
    for _ in range(300):
        t = time.perf_counter() + 300e-6
        while time.perf_counter() < t:
            pass
        after.append(_best(lambda: _empty(a), 1))
    _policy(False)
    return dict(region_back_to_back_min_us=round(min(back), 1), region_back_to_back_median_us=round(float(np.median(back)), 1),
                region_after_300us_min_us=round(min(after), 1), region_after_300us_median_us=round(float(np.median(after)), 1))


def scaling(cells) -> list:
    rows = []
    for n in cells:
        sims = {1: _sim(n, 1), 2: _sim(n, 2)}
        forced = threaded.chunks_for(2, n) < 2
        if forced:  # below the default's threshold: the windows forced, to show why
            s = sims[2]
            s._tw = threaded.new_work(2, n, s.nv, s._Lstack.shape[0], fft_share=threaded.FFT_SHARE)
        for s in sims.values():
            s.step()
        k = max(2, 20000 // n)
        best = {1: math.inf, 2: math.inf}
        for r in range(30 if n < 30000 else 8):
            for th in ((1, 2) if r % 2 == 0 else (2, 1)):
                s = sims[th]
                s._thread_work()
                _policy(True)
                t0 = time.perf_counter()
                for _ in range(k):
                    s.step()
                dt = (time.perf_counter() - t0) / k
                _policy(False)
                best[th] = min(best[th], dt)
                if RT:
                    time.sleep(max(0.02, 10 * dt * k))
        row = dict(cells=n, one_us=round(best[1] * 1e6, 1), two_us=round(best[2] * 1e6, 1),
                   speedup=round(best[1] / best[2], 2), windows_forced=forced,
                   same_bits=sims[1].snapshot().checksum() == sims[2].snapshot().checksum())
        print(row, flush=True)
        rows.append(row)
    return rows


def main(argv=None) -> int:
    global RT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", default="1000,2000,4000,16000,64000")
    ap.add_argument("--rt", action="store_true", help="timed bursts at SCHED_FIFO priority, duty cycle < 10 %%")
    ap.add_argument("--record", default=None, help="write the JSON here")
    a = ap.parse_args(argv)
    RT = a.rt
    load0 = os.getloadavg()[0]
    d = dict(profile_4000=profile(), sync=sync(), spins=threaded.team.SPINS, fft_share=threaded.FFT_SHARE,
             min_nodes_per_window=threaded.MIN_NODES_PER_CHUNK)
    print(json.dumps(d), flush=True)
    d["scaling"] = scaling([int(x) for x in a.cells.split(",")])
    d.update(rt=RT, load_before=round(load0, 1), load_after=round(os.getloadavg()[0], 1),
             recorded=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), cores=TH.available())
    if a.record:
        with open(a.record, "w") as f:
            json.dump(d, f, indent=1)
    print(json.dumps(d))
    return 0


if __name__ == "__main__":
    sys.exit(main())
