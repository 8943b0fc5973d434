"""``ringcore bench nbody [--json] [--quick] [--threads 1,2]``: speed of the shearing box, side by side with REBOUND.

Boxes at tau = 1.5, Omega_z = 3.6, Bridges law, 1,000 steps per orbit, of about 1,000,
10,000 and 75,000 particles (the last is the paper's 5 km x 31.4 m box). Each box is first
equilibrated with ringcore; ringcore and (if installed) REBOUND are then timed from the same
state for the same number of steps. On the 1,000-particle box both codes also run on from
that state to compare their steady-state velocity dispersion and viscosity.  With several thread counts
(``--threads 1,2``; default 1 and the cores this process may use) ringcore is timed from the same state at each,
alternated, best of ``REPS`` (wall time: threads share the machine with other jobs, so measure on a quiet
one).  JSON keys are listed in :func:`run_bench`.
"""
from __future__ import annotations

import json
import math
import sys
import time

from .. import params
from .. import threads as TH
from . import kernels as K
from . import rebound_ref
from .box import ShearingBox
from .options import NBodyOptions

# (label, L_x [m], L_y [m]); L_x is a whole multiple of L_y (REBOUND's square root cells)
BOXES = (("1k", 78.0, 26.0), ("10k", 416.0, 52.0), ("75k", 159 * 31.4, 31.4))
#                   equilibrate [orbits], timed steps  (full / quick)
PLAN = {"1k": ((10.0, 3000), (3.0, 1000)), "10k": ((3.0, 1000), (1.0, 300)),
        "75k": ((1.0, 100), (0.2, 50))}
REPS = 3  # timings per thread count (alternated), the best is kept


def _time_ours(box: ShearingBox, nsteps: int):
    box.reset_accumulators()
    t0 = time.perf_counter()
    box._advance_steps(nsteps)
    wall = time.perf_counter() - t0
    return wall, box.acc[K.A_NCOLL]


def _time_rebound(box: ShearingBox, nsteps: int):
    sim = rebound_ref.make_simulation(box)
    sim.steps(1)  # set-up (tree build) outside the timing
    t0 = time.perf_counter()
    sim.steps(nsteps)
    return time.perf_counter() - t0


def _time_threads(box: ShearingBox, nsteps: int, threads: tuple, saved) -> dict:
    """Best wall time [s] of ``nsteps`` steps from ``saved`` per thread count (alternated), and collisions."""
    best, ncoll = {}, 0.0
    for rep in range(REPS if len(threads) > 1 else 1):
        for th in (threads if rep % 2 == 0 else threads[::-1]):
            box.pos, box.vel, box.t = saved[0].copy(), saved[1].copy(), saved[2]
            box.threads = th
            wall, ncoll = _time_ours(box, nsteps)
            best[th] = min(best.get(th, math.inf), wall)
    box.threads = threads[0]
    return best, ncoll


def _bench_box(label, L_x, L_y, quick, log, threads=(1,)):
    eq_orbits, nsteps = PLAN[label][1 if quick else 0]
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=L_x, L_y=L_y, restitution="bridges"), seed=1,
                      threads=max(threads))
    box._advance_steps(2)  # compile outside the timing
    log(f"  {label}: N = {box.N}, equilibrating {eq_orbits:g} orbits ...")
    box._advance_steps(int(round(eq_orbits * 1000)))
    saved = (box.pos.copy(), box.vel.copy(), box.t)
    walls, ncoll = _time_threads(box, nsteps, threads, saved)
    wall = walls[threads[0]]
    row = dict(box=label, N=box.N, L_x_m=L_x, L_y_m=L_y, steps=nsteps, threads=threads[0],
               particle_steps_per_s=box.N * nsteps / wall, collisions_per_s=ncoll / wall,
               orbits_per_minute=nsteps / 1000.0 / wall * 60.0,
               by_threads={str(th): dict(particle_steps_per_s=box.N * nsteps / w, speedup=wall / w)
                           for th, w in walls.items()})
    if rebound_ref.available():
        box.pos, box.vel, box.t = saved[0].copy(), saved[1].copy(), saved[2]
        rw = _time_rebound(box, nsteps)
        row.update(rebound_particle_steps_per_s=box.N * nsteps / rw, rebound_ratio=rw / wall)
    box.pos, box.vel, box.t = saved
    return row, box


def _steady_state(box: ShearingBox, orbits: float) -> dict:
    """Both codes from the same equilibrated state for ``orbits``: T, c, nu (SI)."""
    state = (box.pos.copy(), box.vel.copy(), box.t)
    nsteps = int(round(orbits * 1000))
    out = {"orbits": orbits}
    if rebound_ref.available():
        sim = rebound_ref.make_simulation(box)
        r = rebound_ref.run_and_measure(sim, nsteps, box.Omega)
        out["rebound"] = dict(T=r["T"], c=math.sqrt(r["T"]), nu=r["nu"], nu_nonlocal=r["nu_nonlocal"])
    box.pos, box.vel, box.t = state
    box.reset_accumulators()
    box._advance_steps(nsteps)
    tr = box.transport()
    out["ringcore"] = dict(T=tr["T"], c=math.sqrt(tr["T"]), nu=tr["nu"], nu_nonlocal=tr["nu_nonlocal"],
                           c_eff=tr["c_eff"], collision_frequency=tr["collision_frequency"],
                           unresolved_fraction=tr["unresolved_fraction"])
    return out


def _app_speed(quick: bool) -> dict:
    """Orbits per wall-clock second of the default box and of a 3,000-particle box."""
    out = {}
    for name, opts in (("default", NBodyOptions()), ("3k", NBodyOptions(L_x=100.0, L_y=63.0))):
        box = ShearingBox(params.get("tau15"), opts, seed=2)
        box.advance(0.5 if quick else 2.0)  # settle (and compile)
        t0 = time.perf_counter()
        box.advance(1.0 if quick else 3.0)
        out[name] = dict(N=box.N, orbits_per_s=(1.0 if quick else 3.0) / (time.perf_counter() - t0))
    return out


def run_bench(as_json: bool = False, quick: bool = False, threads=None) -> int:
    """Run the benchmark; print a table, or with ``as_json`` one JSON object with keys

    ``particle_steps_per_s``, ``collisions_per_s``, ``orbits_per_minute`` (at the first of ``threads``; default
    1 and :func:`ringcore.threads.available`), ``by_threads`` (per thread count: ``particle_steps_per_s``,
    ``speedup`` over the first) and (REBOUND installed)
    ``rebound_particle_steps_per_s``, ``rebound_ratio`` for the 1,000-particle box; ``boxes``
    (the same per box: ``box``, ``N``, ``L_x_m``, ``L_y_m``, ``steps`` ...); ``steady_state``
    (``ringcore`` / ``rebound``: ``T`` [m^2/s^2], ``c`` [m/s], ``nu`` [m^2/s] ...); ``app``
    (orbits per second of the default and a 3,000-particle box); ``rebound_available``, ``quick``.
    """
    log = (lambda s: print(s, file=sys.stderr)) if as_json else print
    threads = tuple(dict.fromkeys(TH.check(t, "--threads") for t in (threads or (1, TH.available()))))
    have_rb = rebound_ref.available()
    log(f"ringcore bench nbody ({'quick' if quick else 'full'}; REBOUND {'found' if have_rb else 'not installed'})")
    rows, first = [], None
    for label, L_x, L_y in BOXES:
        row, box = _bench_box(label, L_x, L_y, quick, log, threads)
        rows.append(row)
        first = first or box
    steady = _steady_state(first, 2.0 if quick else 10.0)
    app = _app_speed(quick)
    result = dict(rows[0])
    result.pop("box")
    result.update(boxes=rows, steady_state=steady, app=app, rebound_available=have_rb, quick=quick,
                  threads_timed=list(threads))
    if as_json:
        print(json.dumps(result))
        return 0
    print(f"{'box':>4} {'N':>7} {'steps':>6} {'particle-steps/s':>17} {'collisions/s':>13} "
          f"{'orbits/min':>10} {'REBOUND p-steps/s':>18} {'ratio':>6}")
    for r in rows:
        rb = (f"{r['rebound_particle_steps_per_s']:18.3g} {r['rebound_ratio']:6.2f}"
              if "rebound_ratio" in r else f"{'-':>18} {'-':>6}")
        print(f"{r['box']:>4} {r['N']:7d} {r['steps']:6d} {r['particle_steps_per_s']:17.3g} "
              f"{r['collisions_per_s']:13.3g} {r['orbits_per_minute']:10.3g} {rb}")
    if len(threads) > 1:
        print("threads (wall time, best of %d, from the same state): particle-steps/s and speed-up" % REPS)
        for r in rows:
            print(f"{r['box']:>4} " + "  ".join(f"{th}: {v['particle_steps_per_s']:.3g} ({v['speedup']:.2f}x)"
                                                for th, v in r["by_threads"].items()))
    print(f"steady state ({steady['orbits']:g} orbits from the same state, 1k box):")
    for code in ("ringcore", "rebound"):
        if code in steady:
            s = steady[code]
            print(f"  {code:8s} T = {s['T']:.3e} m^2/s^2  c = {s['c'] * 1e3:.4f} mm/s  nu = {s['nu']:.3e} m^2/s")
    for k, a in app.items():
        print(f"app box {k}: N = {a['N']}, {a['orbits_per_s']:.2f} orbits per wall-clock second")
    return 0
