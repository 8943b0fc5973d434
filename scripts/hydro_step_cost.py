"""Where the CPU time of the web app's default live hydro box goes, and the least it can cost with its arithmetic.

    .venv/bin/python scripts/hydro_step_cost.py [--base DIR] [--baseline-ms-per-orbit 16.0] [--json FILE]

The box of ``scripts/hydro_step_ab.py`` (tau15 non-isothermal, sigma0 = 400 kg/m^2, L_x = 2 km, h = 2.5 m,
white noise 1e-4 with seed 1, ``timestep="cfl"``, ``T_floor=0.01``, 20 samples per orbit).  Four measurements,
each printed as a table (and written as JSON with ``--json``):

``pieces``  each compiled piece of an RK stage run 20,000 times in a compiled loop on the state after 100
            orbits (data in cache): us per call (the table "Where a step goes" of the hydro guide).
``floor``   the compiled steps alone (:func:`ringcore.hydro.stepper.ssprk_steps`, 1,000 steps in one call, no
            samples, no Python) from the states after 10, 100 and 150 orbits, and the steps of orbits 0-200:
            the CPU per orbit this arithmetic costs with nothing else, and, with ``--baseline-ms-per-orbit``
            (the "A" figure of ``hydro_step_ab.py``), that floor as a fraction of it.
``cells``   us per step inside ``advance`` (samples included) for 200 ... 3,200 cells at the same h (so the same
            steps per orbit), orbits 0-8; a straight-line fit gives the cost per step that does not grow
            with the grid and the cost per cell and RK stage.  With ``--base DIR`` (a folder holding another
            ``ringcore/``, e.g. from ``git archive``) the same for that code, in its own process and numba cache.
``landing`` steps over orbits 0-10 with 20 and with 2 samples per orbit (every sample time is landed on
            exactly, so a step is shortened at each), and the largest difference of the states after 5 orbits.
``phases``  (with ``--phases``, about 90 s) steps and CPU per orbit of one run over orbits 0-160, 160-400, ...
            4,000-6,000 and 6,000-8,000: an orbit costs more steps while the waves grow than once they saturate.

Process CPU time (``time.process_time``); run on a quiet machine.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hydro_step_ab import default_box  # noqa: E402 (the same box as the A/B)
CELLS_L = (500.0, 1000.0, 2000.0, 4000.0, 8000.0)  # m, at h = 2.5 m: 200 ... 3,200 cells


def cells(root: str) -> dict:
    """us per step (median of 3) for each grid of :data:`CELLS_L`, orbits 0-8, and the fit."""
    out = {}
    for L in CELLS_L:
        default_box(root, L).advance(orbits=0.2)  # compile or load the cache
        v = []
        for _ in range(3):
            sim = default_box(root, L)
            sim.on_sample(lambda s, d: None)
            c = time.process_time()
            sim.advance(until=8.0)
            v.append(1e6 * (time.process_time() - c) / sim.steps)
        out[sim.n] = sorted(v)[1]
    n = list(out)
    mx, my = sum(n) / len(n), sum(out.values()) / len(n)
    slope = sum((x - mx) * (out[x] - my) for x in n) / sum((x - mx) ** 2 for x in n)
    return dict(us_per_step=out, fixed_us_per_step=my - slope * mx, ns_per_cell_stage=1e3 * slope / 5)


def pieces(root: str) -> dict:
    """us per call of each piece in a compiled loop (this checkout's kernels)."""
    import numpy as np
    from numba import njit

    from ringcore.hydro import kernels as K
    from ringcore.hydro.fftw import convolve
    sim = default_box(root)
    sim.advance(until=100.0)
    U = sim._Ustack[sim._slot[0]].copy()
    W, beta, par, n, g = sim._W, sim._beta, sim._par, sim.n, sim.gravity
    L = np.zeros_like(U)
    s = slice(K.NG, K.NG + n)
    o, a, ll, Uf = U[0][s].copy(), U[0][s].copy(), L[0][s].copy(), U.copy()
    inv60h, inv180h2 = 1.0 / (60 * par[K.P_H]), 1.0 / (180 * par[K.P_H] ** 2)

    @njit
    def loop(which, r, U, W, beta, gg, par, L, n, o, a, ll, Uf, inv60h, inv180h2):
        for _ in range(r):
            if which == 0:
                K._primitives(U, W, beta, par)
            elif which == 1:
                K._split_fluxes(U, W)
            elif which == 2:
                K._numerical_flux(W, 4, n)
            elif which == 3:
                K._gradients(W, False, inv60h, inv180h2, n)
            elif which == 4:
                K.compute_rhs(U, W, beta, gg, par, L, False)
            elif which == 5:
                K._grid_maxima(U, W, par, n)
            elif which == 6:
                K._update(o, a, 0.5, ll, 0.1, a, 0.3, a, 0.2, ll, 0.05, True)
            elif which == 7:
                K.apply_temperature_floor(Uf, 0.01)
            else:
                K.check_state(Uf)

    @njit
    def grav(r, sig, fwd, bwd, G, s_, sk, g_):
        for _ in range(r):
            convolve(sig, fwd, bwd, G, s_, sk, g_)

    def t(which, reps=20000):
        args = (U, W, beta, g.g, par, L, n, o, a, ll, Uf, inv60h, inv180h2)
        loop(which, 1, *args)
        c = time.perf_counter()
        loop(which, reps, *args)
        return (time.perf_counter() - c) / reps * 1e6
    sig = U[0, s].copy()
    grav(1, sig, *g.kernel_args)
    c = time.perf_counter()
    grav(20000, sig, *g.kernel_args)
    t_grav = (time.perf_counter() - c) / 20000 * 1e6
    res = dict(primitives=t(0), flux_splitting=t(1), mp5=t(2), gradients=t(3), compute_rhs=t(4),
               self_gravity=t_grav, update_one_variable=t(6), temperature_floor=t(7), timestep_maxima=t(5),
               state_check=t(8))
    res["differences_and_sources"] = res["compute_rhs"] - sum(
        res[k] for k in ("primitives", "flux_splitting", "mp5", "gradients"))
    return res


def floor(root: str, baseline_ms: float | None) -> dict:
    """The compiled steps alone from three states, and the floor per orbit over orbits 0-200."""
    from ringcore.hydro.stepper import ssprk_steps
    from ringcore.hydro.stepping import STAGE_F, STAGE_I
    per = {}
    for start in (10.0, 100.0, 150.0):
        sim = default_box(root)
        sim.advance(until=start)
        g = sim.gravity
        tw = (sim._thread_work(),) if hasattr(sim, "_thread_work") else ()  # the code before threads: none
        c = time.process_time()
        t, dt, n, hits, field, j, k = ssprk_steps(
            sim._Ustack, sim._slot, sim._Lstack, sim._W, sim._beta, sim._par, g.enabled, *g.kernel_args,
            STAGE_I, STAGE_F, sim._T_floor, sim.t, math.inf, math.inf, 1000, *tw)
        per[start] = 1e6 * (time.process_time() - c) / n
    sim = default_box(root)
    c = time.process_time()
    sim.advance(until=200.0)
    run_ms = 1e3 * (time.process_time() - c) / 200.0
    us = sum(per.values()) / len(per)
    out = dict(us_per_compiled_step=per, steps_0_200=sim.steps, run_ms_per_orbit=run_ms,
               floor_ms_per_orbit=us * sim.steps / 200.0 / 1e3)
    if baseline_ms:
        out.update(baseline_ms_per_orbit=baseline_ms, floor_over_baseline=out["floor_ms_per_orbit"] / baseline_ms,
                   run_over_baseline=run_ms / baseline_ms,
                   half_budget_us_per_step=0.5 * baseline_ms * 200.0 / sim.steps * 1e3)
    return out


def landing(root: str) -> dict:
    """Steps over orbits 0-10 with 20 and 2 samples per orbit; the state difference after 5 orbits."""
    import numpy as np
    out, U = {}, {}
    for S in (20, 2):
        sim = default_box(root, samples=S)
        sim.advance(until=5.0)
        U[S] = sim.U.copy()
        sim.advance(until=10.0)
        out[f"steps_0_10_with_{S}_samples"] = sim.steps
    d = np.abs(U[20] - U[2]).max(axis=1)
    pert = np.abs(U[20] - U[20].mean(axis=1, keepdims=True)).max(axis=1)
    out["max_abs_difference_after_5_orbits"] = d.tolist()
    out["relative_to_state"] = (d / np.abs(U[20]).max(axis=1)).tolist()
    out["relative_to_perturbation"] = (d / pert).tolist()
    return out


def phases(root: str) -> dict:
    """Steps and ms of CPU per orbit between the orbits of :data:`PHASE_MARKS`."""
    sim, out = default_box(root), {}
    sim.advance(orbits=0.2)
    sim = default_box(root)
    o0, s0, c0 = 0.0, 0, time.process_time()
    for m in PHASE_MARKS:
        sim.advance(until=m)
        c = time.process_time()
        out[f"{o0:g}-{m:g}"] = dict(steps_per_orbit=(sim.steps - s0) / (m - o0), ms_per_orbit=1e3 * (c - c0) / (m - o0))
        o0, s0, c0 = m, sim.steps, c
    return out


PHASE_MARKS = (160.0, 400.0, 1000.0, 2000.0, 4000.0, 6000.0, 8000.0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", help="folder holding another ringcore/ for the 'cells' comparison")
    ap.add_argument("--baseline-ms-per-orbit", type=float, help="CPU per orbit of the code compared against")
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--phases", action="store_true", help="also the cost per orbit of one run to orbit 8,000 (~90 s)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    out_file = None
    if a.json:  # made now (never over an existing file), so that a bad place fails before minutes of measuring
        try:
            out_file = open(a.json, "x")
        except FileExistsError:
            ap.error(f"--json {a.json} exists; give a new file name (results are never overwritten)")
        except OSError as exc:
            ap.error(f"--json {a.json} cannot be written: {exc.strerror}")
    if a.worker:
        print(json.dumps(cells(a.worker)))
        return 0
    res = {}
    if a.base:
        env = dict(os.environ, NUMBA_CACHE_DIR=tempfile.mkdtemp(prefix="hydro_cost_"))
        out = subprocess.run([sys.executable, __file__, "--worker", os.path.abspath(a.base)], env=env,
                             capture_output=True, text=True, check=True)
        res["cells_base"] = json.loads(out.stdout.strip().splitlines()[-1])
    res["cells"] = cells(HERE)
    res["pieces"] = pieces(HERE)
    res["floor"] = floor(HERE, a.baseline_ms_per_orbit)
    res["landing"] = landing(HERE)
    if a.phases:
        res["phases"] = phases(HERE)
    for k in ("cells_base", "cells"):
        if k in res:
            c = res[k]
            print(f"{k}: us per step {', '.join(f'{n}: {v:.1f}' for n, v in c['us_per_step'].items())}; "
                  f"fit: {c['fixed_us_per_step']:.1f} us per step + {c['ns_per_cell_stage']:.1f} ns per cell and stage")
    print("pieces (us per call):", ", ".join(f"{k} {v:.2f}" for k, v in res["pieces"].items()))
    f = res["floor"]
    print(f"floor: compiled steps alone {', '.join(f'orbit {o:g}: {v:.1f}' for o, v in f['us_per_compiled_step'].items())}"
          f" us per step; {f['steps_0_200']} steps over orbits 0-200: {f['floor_ms_per_orbit']:.2f} ms per orbit"
          f" (the run itself {f['run_ms_per_orbit']:.2f})")
    if "floor_over_baseline" in f:
        print(f"  of the baseline {f['baseline_ms_per_orbit']:.2f}: floor {f['floor_over_baseline']:.3f}, "
              f"run {f['run_over_baseline']:.3f}; half of it allows {f['half_budget_us_per_step']:.1f} us per step")
    print("landing:", json.dumps(res["landing"]))
    for k, v in res.get("phases", {}).items():
        print(f"orbits {k}: {v['steps_per_orbit']:.1f} steps and {v['ms_per_orbit']:.2f} ms of CPU per orbit")
    if out_file is not None:
        with out_file:
            json.dump(res, out_file, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
