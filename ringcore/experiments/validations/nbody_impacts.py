"""The two N-body impact models side by side: instantaneous hard-sphere impacts and the paper's
visco-elastic contacts of finite duration (Dilley 1993; Salo 1995; :mod:`ringcore.nbody.viscoelastic`).

``groundstate``: T, nu = nu_local + nu_nonlocal and c0 (Eq. (12)) of the four parameter sets tau = 1.5, 2
at Omega_z = 3.6, 2 (Bridges law) against Table 2 (Salo et al. 2001).  One state settled with instantaneous
impacts (``--equilibrate`` orbits) starts both models, which settle again (``--resettle``) and then average
over ``--blocks`` blocks of ``--block-orbits``; the error bars are the standard errors of the block means.
``growth``: growth rate and frequency of a seeded m = 1 mode (the set-up of the quick Figure 4 recipe:
L_x = lambda, L_y = 10 m, a 2 R_p Omega seed followed for 12 orbits, only the seeded self-gravity mode)
after ``--settle`` orbits of settling with the model itself (default 10: after the recipe's 3 orbits the
visco-elastic box had not settled: 0.00499 against 0.00748 Omega after 10, T_c = 1e-3 orbit, sigma0 = 0).  Each run prints its cost per step.

Usage: ``ringcore validate nbody-impacts [--what groundstate growth] [--L-x 20 --L-y 20] [--blocks 6]``.
Exit status 1 if a visco-elastic ground state is more than ``--tol`` off the table.
"""
import json
import math
import time

import numpy as np

from ringcore import linear, params
from ringcore.checks import check_int, check_real
from ringcore.nbody import NBodyOptions, ShearingBox, growth

HELP = ("N-body impact models (instantaneous vs visco-elastic): ground states against Salo et al. (2001) with "
        "error bars and linear growth rates, with the cost per step (exit status 1 if a visco-elastic ground "
        "state is off)")
SETS = ("tau15", "tau20", "tau15_oz2", "tau20_oz2")
MODELS = ("instant", "viscoelastic")
QUANTITIES = (("T", "T0", "T [1e-8 m^2/s^2]", 1e8), ("nu", "nu0", "nu [1e-3 m^2/s]", 1e3),
              ("c_eff", "c0", "c0 [mm/s]", 1e3))
DEFAULT = NBodyOptions()


def add_arguments(p) -> None:
    """Options of ``ringcore validate nbody-impacts``."""
    p.add_argument("--what", nargs="+", default=["groundstate", "growth"], choices=["groundstate", "growth"])
    p.add_argument("--sets", nargs="+", default=list(SETS), choices=list(SETS), help="ground-state parameter sets")
    p.add_argument("--L-x", type=float, default=20.0, help="ground-state box, radial [m]")
    p.add_argument("--L-y", type=float, default=20.0, help="ground-state box, azimuthal [m]")
    p.add_argument("--equilibrate", type=float, default=2.0,
                   help="ground-state settling with instantaneous impacts [orbits] (>= 0)")
    p.add_argument("--resettle", type=float, default=0.5, help="settling of each model after that [orbits] (>= 0)")
    p.add_argument("--blocks", type=int, default=6, help="averaging blocks (>= 2; the error bars)")
    p.add_argument("--block-orbits", type=float, default=1.0, help="length of an averaging block [orbits] (> 0)")
    p.add_argument("--contact-duration", type=float, default=DEFAULT.contact_duration,
                   help=f"visco-elastic contact duration [orbits] (default {DEFAULT.contact_duration:g})")
    p.add_argument("--contact-steps", type=int, default=DEFAULT.contact_steps,
                   help=f"time steps per visco-elastic contact (default {DEFAULT.contact_steps})")
    p.add_argument("--lambdas", type=float, nargs="+", default=[100.0], help="growth: wavelengths [m]")
    p.add_argument("--sigma0", type=float, nargs="+", default=[0.0, 350.0], help="growth: surface densities [kg/m^2]")
    p.add_argument("--settle", type=float, default=10.0,
                   help="growth: settling of each model's box before the seed [orbits] (>= 0; default 10)")
    p.add_argument("--tol", type=float, default=0.03, help="allowed relative deviation from the table")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, help="also write the rows to this JSON file")


def _options(a, model, **kw):
    return NBodyOptions(impacts=model, contact_duration=a.contact_duration, contact_steps=a.contact_steps, **kw)


def block_transport(box, blocks: int, block_orbits: float) -> dict:
    """Transport (SI, :meth:`ShearingBox.transport`) averaged over ``blocks`` consecutive blocks of
    ``block_orbits``: the mean of the block values of each quantity and, as ``<key>_err``, the standard
    error of that mean (block values taken as independent; a block is hundreds of collision times)."""
    rows = []
    for _ in range(blocks):
        box.reset_accumulators()
        box.advance(block_orbits)
        rows.append(box.transport())
    out = {}
    for q in ("T", "nu", "c_eff", "collision_frequency", "max_overlap"):
        v = np.array([r[q] for r in rows])
        out[q] = float(v.mean())
        out[q + "_err"] = float(v.std(ddof=1) / math.sqrt(blocks))
    out["unresolved"] = float(sum(r["unresolved"] for r in rows))
    return out


def ground_states(a, set_name) -> dict:
    """Both models' block-averaged transport of one parameter set (SI), with ``us_per_step``, ``dt_orbit``, ``N``."""
    p = params.get(set_name)
    box0 = ShearingBox(p, NBodyOptions(L_x=a.L_x, L_y=a.L_y, record_every=1.0, profile_every=0.0), seed=a.seed)
    box0.advance(a.equilibrate)
    state = (box0.pos.copy(), box0.vel.copy(), box0.t)
    out = {}
    for model in MODELS:
        o = _options(a, model, L_x=a.L_x, L_y=a.L_y, record_every=a.block_orbits, profile_every=0.0)
        box = ShearingBox(p, o, seed=a.seed, state=tuple(np.copy(x) for x in state), ids=box0.ids.copy())
        box.advance(a.resettle)
        t, n = time.perf_counter(), box.steps
        tr = block_transport(box, a.blocks, a.block_orbits)
        tr.update(us_per_step=1e6 * (time.perf_counter() - t) / max(box.steps - n, 1), dt_orbit=o.dt_orbit, N=box.N)
        out[model] = tr
    return out


def mode_growth(a, lam, sigma0, model):
    """Growth rate and frequency [Omega] of a seeded m = 1 mode of wavelength ``lam`` [m]."""
    p = params.get("tau15", sigma0=sigma0)
    box = ShearingBox(p, _options(a, model, L_x=lam, L_y=10.0, single_mode=1, record_every=1.0, profile_every=0.0),
                      seed=a.seed)
    box.advance(a.settle)
    box.seed_mode(1, 2.0)
    t = time.perf_counter()
    r = growth.measure(box, 1, 12.0, skip=1.0)
    d = linear.dispersion(p, [lam])
    return dict(growth_rate=r.growth_rate, growth_rate_err=r.growth_rate_err, frequency=r.frequency,
                hydro_growth_rate=float(d.growth_rate[0]), hydro_frequency=float(d.frequency[0]),
                s_per_orbit=(time.perf_counter() - t) / 12.0, N=box.N)


def run(a) -> int:
    """Run the comparisons and print the tables; 0 if the visco-elastic ground states are within ``--tol``."""
    check_real("--equilibrate", a.equilibrate, 0.0)
    check_real("--resettle", a.resettle, 0.0)
    check_int("--blocks", a.blocks, 2, 10**6)
    check_real("--block-orbits", a.block_orbits, 0.0, lo_open=True)
    check_real("--tol", a.tol, 0.0, lo_open=True)
    check_real("--settle", a.settle, 0.0)
    out, ok = {}, True
    if "groundstate" in a.what:
        print(f"ground state, {a.L_x:g} m x {a.L_y:g} m, Bridges law, {a.equilibrate:g} orbits settling (instantaneous "
              f"impacts) + {a.resettle:g} per model, {a.blocks} blocks of {a.block_orbits:g} orbits (+-: standard "
              f"error); visco-elastic contacts of {a.contact_duration:g} orbits, {a.contact_steps} steps each")
        print(f"{'tau':>4} {'Om_z':>4} {'quantity':<17} {'table':>6} {'instant, dev. from table':>30} "
              f"{'visco-elastic, dev.':>30} {'visco/inst':>10}")
        for s in a.sets:
            p = params.get(s)
            r = ground_states(a, s)
            for model in MODELS:
                out[f"groundstate {s} {model}"] = r[model]
            for q, ref_name, label, scale in QUANTITIES:
                ref = getattr(p, ref_name)
                cells = []
                for model in MODELS:
                    m, e = r[model][q], r[model][q + "_err"]
                    dev = m / ref - 1
                    if model == "viscoelastic":
                        ok &= abs(dev) <= a.tol
                    cells.append(f"{m * scale:8.3f} +-{e * scale:5.3f} {100 * dev:+6.1f} +-{100 * e / ref:3.1f} %")
                diff = r["viscoelastic"][q] / r["instant"][q] - 1
                print(f"{p.tau:4.1f} {p.omega_z:4.1f} {label:<17} {ref * scale:6.3f} {cells[0]:>30} {cells[1]:>30} "
                      f"{100 * diff:+9.1f}%")
            vi, ve = r["instant"], r["viscoelastic"]
            print(f"{'':>9} impacts per particle per orbit {vi['collision_frequency']:.0f} / "
                  f"{ve['collision_frequency']:.0f}; N = {vi['N']}; dt {vi['dt_orbit']:.2e} / {ve['dt_orbit']:.2e} "
                  f"orbits; {vi['us_per_step']:.0f} / {ve['us_per_step']:.0f} us per step; cost per orbit "
                  f"{ve['us_per_step'] * vi['dt_orbit'] / (vi['us_per_step'] * ve['dt_orbit']):.0f} x", flush=True)
    if "growth" in a.what:
        print(f"linear growth (tau = 1.5, Omega_z = 3.6, Bridges law, L_y = 10 m, m = 1, {a.settle:g} orbits settling), "
              "omega_R and omega_I [Omega]")
        print(f"{'lambda':>7} {'sigma0':>7} {'model':<13} {'omega_R':>9} {'+-':>7} {'omega_I':>8} {'hydro w_R':>10} "
              f"{'hydro w_I':>10} {'s/orbit':>8}")
        for lam in a.lambdas:
            for s0 in a.sigma0:
                for model in MODELS:
                    g = mode_growth(a, lam, s0, model)
                    out[f"growth {lam:g} {s0:g} {model}"] = g
                    print(f"{lam:7.0f} {s0:7.0f} {model:<13} {g['growth_rate']:9.5f} {g['growth_rate_err']:7.5f} "
                          f"{g['frequency']:8.4f} {g['hydro_growth_rate']:10.5f} {g['hydro_frequency']:10.4f} "
                          f"{g['s_per_orbit']:8.2f}", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump({k: {q: float(v) for q, v in r.items()} for k, r in out.items()}, f, indent=1)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1
