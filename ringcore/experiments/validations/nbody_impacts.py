"""The two N-body impact models side by side: instantaneous hard-sphere impacts and the paper's
visco-elastic contacts of finite duration (Dilley 1993; Salo 1995; :mod:`ringcore.nbody.viscoelastic`).

``groundstate``: T, nu = nu_local + nu_nonlocal and c0 (Eq. (12)) of the four parameter sets tau = 1.5, 2
at Omega_z = 3.6, 2 (Bridges law) against Table 2 (Salo et al. 2001).
``growth``: growth rate and frequency of a seeded m = 1 mode (the set-up of the quick Figure 4 recipe:
L_x = lambda, L_y = 10 m, 3 orbits of settling, a 2 R_p Omega seed followed for 12 orbits, only the
seeded self-gravity mode).  Each run prints its cost per step.

Usage: ``ringcore validate nbody-impacts [--what groundstate growth] [--L-x 25 --L-y 25] [--orbits 15]``.
Exit status 1 if a visco-elastic ground state is more than ``--tol`` off the table.
"""
import json
import time

from ringcore import linear, params
from ringcore.checks import check_real
from ringcore.nbody import NBodyOptions, ShearingBox, growth

HELP = ("N-body impact models (instantaneous vs visco-elastic): ground states against Salo et al. (2001) and "
        "linear growth rates, with the cost per step (exit status 1 if a visco-elastic ground state is off)")
SETS = ("tau15", "tau20", "tau15_oz2", "tau20_oz2")
MODELS = ("instant", "viscoelastic")


def add_arguments(p) -> None:
    """Options of ``ringcore validate nbody-impacts``."""
    p.add_argument("--what", nargs="+", default=["groundstate", "growth"], choices=["groundstate", "growth"])
    p.add_argument("--sets", nargs="+", default=list(SETS), choices=list(SETS), help="ground-state parameter sets")
    p.add_argument("--L-x", type=float, default=25.0, help="ground-state box, radial [m]")
    p.add_argument("--L-y", type=float, default=25.0, help="ground-state box, azimuthal [m]")
    p.add_argument("--orbits", type=float, default=15.0, help="ground-state averaging interval [orbits] (> 0)")
    p.add_argument("--equilibrate", type=float, default=5.0, help="ground-state settling [orbits] (>= 0)")
    p.add_argument("--contact-duration", type=float, default=1e-3, help="visco-elastic contact duration [orbits]")
    p.add_argument("--lambdas", type=float, nargs="+", default=[100.0], help="growth: wavelengths [m]")
    p.add_argument("--sigma0", type=float, nargs="+", default=[0.0, 350.0], help="growth: surface densities")
    p.add_argument("--tol", type=float, default=0.03, help="allowed relative deviation from the table")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, help="also write the rows to this JSON file")


def _options(a, model, **kw):
    return NBodyOptions(impacts=model, contact_duration=a.contact_duration, **kw)


def _timed(box, orbits):
    t, n = time.perf_counter(), box.steps
    box.advance(orbits)
    return (time.perf_counter() - t) / max(box.steps - n, 1)


def ground_state(a, set_name, model):
    """Transport of one ground state (SI) plus ``us_per_step`` and ``dt_orbit``."""
    box = ShearingBox(params.get(set_name), _options(a, model, L_x=a.L_x, L_y=a.L_y), seed=a.seed)
    box.advance(a.equilibrate)
    box.reset_accumulators()
    cost = _timed(box, a.orbits)
    return dict(box.transport(), us_per_step=1e6 * cost, dt_orbit=box.options.dt_orbit, N=box.N)


def mode_growth(a, lam, sigma0, model):
    """Growth rate and frequency [Omega] of a seeded m = 1 mode of wavelength ``lam`` [m]."""
    p = params.get("tau15", sigma0=sigma0)
    box = ShearingBox(p, _options(a, model, L_x=lam, L_y=10.0, single_mode=1, record_every=1.0, profile_every=0.0),
                      seed=a.seed)
    box.advance(3.0)
    box.seed_mode(1, 2.0)
    t = time.perf_counter()
    r = growth.measure(box, 1, 12.0, skip=1.0)
    d = linear.dispersion(p, [lam])
    return dict(growth_rate=r.growth_rate, growth_rate_err=r.growth_rate_err, frequency=r.frequency,
                hydro_growth_rate=float(d.growth_rate[0]), hydro_frequency=float(d.frequency[0]),
                s_per_orbit=(time.perf_counter() - t) / 12.0, N=box.N)


def run(a) -> int:
    """Run the comparisons and print the tables; 0 if the visco-elastic ground states are within ``--tol``."""
    check_real("--orbits", a.orbits, 0.0, lo_open=True)
    check_real("--equilibrate", a.equilibrate, 0.0)
    check_real("--tol", a.tol, 0.0, lo_open=True)
    out, ok = {}, True
    if "groundstate" in a.what:
        print(f"ground state, {a.L_x:g} m x {a.L_y:g} m, Bridges law, {a.equilibrate:g} + {a.orbits:g} orbits, "
              f"contact duration {a.contact_duration:g} orbits")
        print(f"{'set':<10} {'model':<13} {'N':>5} {'dt [orb]':>9} {'T [1e-8]':>9} {'dev':>7} {'nu [1e-3]':>10} "
              f"{'dev':>7} {'c0 [mm/s]':>10} {'dev':>7} {'omega_c':>8} {'us/step':>8}")
        for s in a.sets:
            p = params.get(s)
            print(f"{s:<10} {'table':<13} {'':>5} {'':>9} {p.T0 * 1e8:9.3f} {'':>7} {p.nu0 * 1e3:10.3f} {'':>7} "
                  f"{p.c0 * 1e3:10.3f}")
            for model in MODELS:
                tr = ground_state(a, s, model)
                out[f"groundstate {s} {model}"] = tr
                devs = [tr[q] / ref - 1 for q, ref in (("T", p.T0), ("nu", p.nu0), ("c_eff", p.c0))]
                if model == "viscoelastic":
                    ok &= all(abs(d) <= a.tol for d in devs)
                print(f"{'':<10} {model:<13} {tr['N']:5d} {tr['dt_orbit']:9.2e} {tr['T'] * 1e8:9.3f} "
                      f"{100 * devs[0]:+6.1f}% {tr['nu'] * 1e3:10.3f} {100 * devs[1]:+6.1f}% {tr['c_eff'] * 1e3:10.3f} "
                      f"{100 * devs[2]:+6.1f}% {tr['collision_frequency']:8.1f} {tr['us_per_step']:8.0f}", flush=True)
    if "growth" in a.what:
        print("linear growth (tau = 1.5, Omega_z = 3.6, Bridges law, L_y = 10 m, m = 1), omega_R and omega_I [Omega]")
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
