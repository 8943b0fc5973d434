"""Where an N-body step goes: the cost of each phase of :func:`ringcore.nbody.integrator.advance`, measured
by calling its kernels one at a time on an equilibrated box, with the floor of each part.

    .venv/bin/python scripts/nbody_phase_cost.py [--boxes 10k,75k] [--reps 5] [--threads 1,2]

Boxes of ``ringcore bench nbody`` (tau = 1.5, Omega_z = 3.6, Bridges law, 1,000 steps per orbit), each first
equilibrated (0.3 orbits from the bench's seed; the collision rate is then within a few per cent of steady).
Per phase: microseconds per step and nanoseconds per particle (min over ``--reps`` repeats of a few steps,
wall time), and for reference a floor: a pure memory pass over vel (``copy``).  Phases: drift (both halves)
and wrap (serial and, with threads, in blocks), cell list, the entries' coordinate copy, impacts (search
and response: the reference kernel :func:`ringcore.nbody.kernels.resolve_collisions` of the code before, and
:func:`ringcore.nbody.pairs.resolve_strips` at each thread count), sort (its cost per step: every 20th
step), local stress sample; the whole step from :func:`advance` at each thread count for comparison.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time


sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from ringcore import params  # noqa: E402
from ringcore.nbody import NBodyOptions, ShearingBox  # noqa: E402
from ringcore.nbody import integrator as I  # noqa: E402
from ringcore.nbody import blocks as B  # noqa: E402
from ringcore.nbody import kernels as K  # noqa: E402
from ringcore.nbody import pairs as P  # noqa: E402
from ringcore import threads as TH  # noqa: E402
from ringcore.nbody.bench import BOXES  # noqa: E402


def _best(fn, reps, n):
    best = math.inf
    for _ in range(reps):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def phases(label: str, reps: int, threads=(1,)) -> dict:
    L_x, L_y = {b[0]: b[1:] for b in BOXES}[label]
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=L_x, L_y=L_y, restitution="bridges"), seed=1)
    box._advance_steps(300)
    fpar, ipar = box._params()
    w = box._work
    pos, vel, N = box.pos, box.vel, box.N
    dt, L_x, L_y = box.dt, box.L_x, box.L_y
    D = K.shear_offset(box.t, L_x, L_y)
    mode, eps, v_c = int(ipar[I.I_MODE]), fpar[I.P_EPS], fpar[I.P_VC]
    n_cx, n_cy = box.n_cx, box.n_cy
    acc = K.new_accumulators()
    nstep = max(3, 200_000 // N)
    out = {}
    v0 = vel.copy()
    p0 = pos.copy()

    def cells():
        return K.build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, w[I.W_GPOS], w[I.W_GSRC], w[I.W_CELL_START],
                                 w[I.W_CELL_ENTRIES], w[I.W_CELL_OF])

    def impacts_ref():
        vel[:] = v0  # the same impacts every repeat (the copy is timed as "copy" and subtracted)
        K.resolve_collisions(pos, vel, w[I.W_GPOS], w[I.W_GSRC], w[I.W_CELL_START], w[I.W_CELL_ENTRIES],
                             n_cx, n_cy, L_x, L_y, dt, mode, eps, v_c, acc)

    def impacts(th):
        vel[:] = v0
        P.resolve_strips(th, P.n_strips(n_cx), w[I.W_EC], vel, w[I.W_GSRC], w[I.W_CELL_START], w[I.W_CELL_ENTRIES], N, n_cx, n_cy,
                         L_x, L_y, dt, mode, eps, v_c, w[I.W_ACCS], acc)

    def copy():
        vel[:] = v0

    ng = cells()
    out["drift (2 halves)"] = 2 * _best(lambda: K.drift_epicycle(pos, vel, 0.5 * dt, 3.6), reps, nstep)
    pos[:], vel[:] = p0, v0
    out["wrap"] = _best(lambda: K.wrap_shear_periodic(pos, vel, L_x, L_y, D, 1e9), reps, nstep)
    counts = B.new_counts(max(threads))
    for th in threads:
        if th > 1:
            TH.use(th)
            nb = B.blocks_for(th, 10**9)
            out[f"drift + wrap, {th} threads"] = _best(
                lambda: B.drift_wrap_blocks(pos, vel, 0.5 * dt, 3.6, L_x, L_y, D, 1e9, True, nb, counts), reps, nstep)
    pos[:], vel[:] = p0, v0
    out["cell list"] = _best(cells, reps, nstep)
    out["entry coordinates"] = _best(lambda: P.entry_coords(pos, w[I.W_GPOS], w[I.W_CELL_ENTRIES], N + ng, w[I.W_EC]),
                                     reps, nstep)
    t_copy = _best(copy, reps, nstep)
    acc[:] = 0.0
    out["impacts, reference kernel (before)"] = _best(impacts_ref, reps, nstep) - t_copy
    for th in threads:
        TH.use(th)
        out[f"impacts, strips, {th} threads"] = _best(lambda: impacts(th), reps, nstep) - t_copy
    out["stress sample"] = _best(lambda: K.sample_local_stress(pos, vel, acc), reps, nstep)
    sp, sv, si = w[I.W_SPOS], w[I.W_SVEL], w[I.W_SIDS]
    ids = box.ids

    def sort():
        K.sort_by_cell(pos, vel, ids, w[I.W_CELL_ENTRIES], N + ng, sp, sv, si)
    out["sort (per step, 1/20)"] = _best(sort, reps, nstep) / 20.0
    out["floor: copy of vel"] = t_copy
    vel[:] = v0
    state = (pos.copy(), vel.copy(), box.ids.copy(), box.acc.copy(), box._steps)
    for th in threads:
        TH.use(th)
        box.threads = th
        fpar, ipar = box._params()

        def whole():
            box.pos[:], box.vel[:], box.ids[:], box.acc[:] = state[:4]
            I.advance(box.pos, box.vel, box.ids, box.acc, fpar, ipar, w, state[4], 20)
        out[f"advance, {th} threads (20 steps, per step)"] = _best(whole, reps, 1) / 20.0
    pos[:], vel[:] = p0, v0
    acc[:] = 0.0
    impacts(1)
    print(f"{label}: N = {N}, cells {n_cx} x {n_cy}, {P.n_strips(n_cx)} strips, {acc[K.A_NCOLL]:.0f} "
          f"impacts and {acc[K.A_NOVERLAP]:.0f} overlapping pairs in the step measured")
    for k, v in out.items():
        print(f"  {k:40s} {v * 1e6:10.1f} us/step {v / N * 1e9:8.1f} ns/particle")
    return dict(box=label, N=N, strips=P.n_strips(n_cx), reps=reps, seconds=out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--boxes", default="10k,75k")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--threads", default="1", help="thread counts, e.g. 1,2")
    ap.add_argument("--record", metavar="JSON", help="merge the result into this record (key 'phases'), e.g. "
                    "docs/benchmarks/data/nbody_phases.json")
    a = ap.parse_args(argv)
    rows = [phases(label, a.reps, tuple(TH.check(int(t)) for t in a.threads.split(",")))
            for label in a.boxes.split(",")]
    if a.record:
        from bench_merge import record
        record(a.record, "phases", rows, sys.argv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
