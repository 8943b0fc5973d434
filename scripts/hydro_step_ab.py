"""A/B cost of the web app's default live hydro box: two checkouts of ``ringcore`` in one script.

    git archive main ringcore | tar -x -C /tmp/base          # the code before (A)
    .venv/bin/python scripts/hydro_step_ab.py --base /tmp/base [--orbits 200] [--reps 4]

Runs the default box of ``app/hydro_settings.py`` (tau15 non-isothermal, sigma0 = 400 kg/m^2, L_x = 2 km,
h = 2.5 m, white noise 1e-4 with seed 1, ``timestep="cfl"``, ``T_floor=0.01``, 20 samples per orbit, a
sample callback) from orbit 0 to ``--orbits`` in fresh processes, A (``--base``) and B (this checkout)
alternated A B B A ..., each with its own numba cache directory, after a warm-up run in the same process.
Reports process CPU time (``time.process_time``; other jobs on a shared machine do not count) per orbit
over orbits 0-1, 1-35, 35-100 and 100-end, per step and per cell and RK stage, median [min-max], and the
state checksum (both must take the same steps; the states differ in the last bits when the FFT library
differs, README "Cost of a step").  ``--reference`` runs B on its reference step path.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def default_box(root: str, L_x: float = 2000.0, samples: int = 20):
    """The app's default live box (``L_x`` [m] and ``samples`` per orbit may differ) as a new
    :class:`~ringcore.hydro.Hydro1D`, with ``ringcore`` imported from ``root`` (also used by
    ``scripts/hydro_step_cost.py``)."""
    sys.path.insert(0, root)
    import ringcore
    from ringcore import params
    from ringcore.hydro import Hydro1D, HydroOptions
    if not ringcore.__file__.startswith(os.path.abspath(root)):
        raise SystemExit(f"ringcore imported from {ringcore.__file__}, not from {root}")
    p = params.get("tau15", sigma0=400.0, isothermal=False)
    opt = HydroOptions(L_x=L_x, h=2.5, timestep="cfl", T_floor=0.01, samples_per_orbit=samples,
                       spacetime_rows_per_orbit=0, strobe=True, probes_m=(0.0,))
    return Hydro1D(p, opt, initial="noise", seed=1, amplitude=1e-4, max_samples=20000, max_rows=2000)


def measure(root: str, orbits: float, reference: bool) -> dict:
    """One run in this process with ``ringcore`` imported from ``root``."""
    import hashlib

    import numpy as np

    def make():
        sim = default_box(root)
        if reference:
            sim.fast_step = False
        return sim
    make().advance(orbits=0.2)  # compile or load the cache
    sim = make()
    sim.on_sample(lambda s, d: None)
    marks = [m for m in (1.0, 35.0, 100.0) if m < orbits] + [orbits]
    seg, o0, s0 = [], 0.0, 0
    for m in marks:
        t = time.process_time()
        sim.advance(until=m)
        seg.append(dict(o0=o0, o1=m, cpu_s=time.process_time() - t, steps=sim.steps - s0))
        o0, s0 = m, sim.steps
    return dict(seg=seg, cpu_s=sum(s["cpu_s"] for s in seg), steps=sim.steps, n=sim.n,
                sha1=hashlib.sha1(np.ascontiguousarray(sim.U).tobytes()).hexdigest()[:16])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", required=True, help="folder holding the 'before' ringcore package")
    ap.add_argument("--orbits", type=float, default=200.0)
    ap.add_argument("--reps", type=int, default=4)
    ap.add_argument("--reference", action="store_true", help="B on its reference step path")
    ap.add_argument("--worker", nargs=2, metavar=("ROOT", "MODE"), help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker:
        print(json.dumps(measure(a.worker[0], a.orbits, a.worker[1] == "ref")))
        return 0
    caches = tempfile.mkdtemp(prefix="hydro_ab_")
    sides = {"A": (os.path.abspath(a.base), "fast"), "B": (HERE, "ref" if a.reference else "fast")}
    res = {"A": [], "B": []}
    for r in range(a.reps):
        for k in ("AB" if r % 2 == 0 else "BA"):
            root, mode = sides[k]
            env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(caches, k))
            out = subprocess.run([sys.executable, __file__, "--base", a.base, "--orbits", str(a.orbits),
                                  "--worker", root, mode], env=env, capture_output=True, text=True, cwd=caches)
            if out.returncode:
                print(out.stderr, file=sys.stderr)
                return 1
            res[k].append(json.loads(out.stdout.strip().splitlines()[-1]))
            print(k, round(res[k][-1]["cpu_s"], 3), "s", flush=True)

    def fmt(v):
        return f"{statistics.median(v):.2f} [{min(v):.2f}-{max(v):.2f}]"
    for k in "AB":
        L = res[k]
        n, steps = L[0]["n"], L[0]["steps"]
        print(f"{k} ({sides[k][0]}): {steps} steps, state sha1 {L[0]['sha1']}")
        print(f"  ms/orbit 0-{a.orbits:g}: {fmt([1e3 * d['cpu_s'] / a.orbits for d in L])}; "
              f"us/step: {fmt([1e6 * d['cpu_s'] / d['steps'] for d in L])}; "
              f"ns/cell/stage: {fmt([1e9 * d['cpu_s'] / d['steps'] / (5 * n) for d in L])}")
        for i, s in enumerate(L[0]["seg"]):
            print(f"  orbits {s['o0']:g}-{s['o1']:g} ({s['steps']} steps): ms/orbit "
                  f"{fmt([1e3 * d['seg'][i]['cpu_s'] / (s['o1'] - s['o0']) for d in L])}")
    ratio = statistics.median([d["cpu_s"] for d in res["B"]]) / statistics.median([d["cpu_s"] for d in res["A"]])
    print(f"B / A (median CPU over orbits 0-{a.orbits:g}): {ratio:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
