"""Growth rate and frequency of seeded linear overstable modes (tau = 1.5, sigma0 = 0, Omega_z = 3.6,
Bridges law) against the non-isothermal hydrodynamic prediction (Eq. (16); paper's Figures 4, 5). One wavelength per box (m = 1), box L_x = lambda x L_y, equilibrated for
EQ orbits, then a radial velocity wave of AMP R_p Omega is seeded and followed for ORBITS orbits.

Usage: ``ringcore validate nbody-linear [--lambdas 100 150 200] [--L-y 25] [--orbits 40]``.
"""
import json
import time

from ringcore import linear, paperrefs, params
from ringcore.checks import check_int, check_real
from ringcore.nbody import NBodyOptions, ShearingBox, growth

HELP = (f"N-body growth rates and frequencies of seeded modes against the hydrodynamic prediction "
        f"({paperrefs.fig('nblin1')}, {paperrefs.fig('nblin2')}; prints the table)")


def add_arguments(ap) -> None:
    """Options of ``ringcore validate nbody-linear``."""
    ap.add_argument("--lambdas", type=float, nargs="+", default=[100.0, 150.0, 200.0], help="wavelengths [m]")
    ap.add_argument("--L-y", type=float, default=25.0, help="azimuthal box size [m]")
    ap.add_argument("--orbits", type=float, default=40.0, help="orbits followed after seeding")
    ap.add_argument("--eq", type=float, default=8.0, help="orbits of settling before seeding")
    ap.add_argument("--amp", type=float, default=2.0, help="seeded radial velocity amplitude [R_p Omega]")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1], help="random seeds")
    ap.add_argument("--json", default=None, help="also write the table to this JSON file")


def run(a) -> int:
    """Run the seeded modes and print the table (always 0: the comparison is read, not judged)."""
    for lam in a.lambdas:
        check_real("--lambdas", lam, 0.0, lo_open=True, unit="m")
    check_real("--L-y", a.L_y, 0.0, lo_open=True, unit="m")
    check_real("--orbits", a.orbits, 0.0, lo_open=True)
    check_real("--eq", a.eq, 0.0)
    check_real("--amp", a.amp, 0.0, lo_open=True)
    for seed in a.seeds:
        check_int("--seeds", seed, 0)
    p = params.get("tau15")
    out = []
    print(f"{'lambda [m]':>10} {'seed':>4} {'N':>6} {'omega_R N-body':>15} {'hydro':>8} {'omega_I N-body':>15} "
          f"{'Lomb':>7} {'hydro':>7}   [Omega]")
    for lam in a.lambdas:
        d = linear.dispersion(p, [lam])
        for seed in a.seeds:
            t0 = time.time()
            box = ShearingBox(p, NBodyOptions(L_x=lam, L_y=a.L_y, restitution="bridges"), seed=seed)
            box.advance(a.eq)
            box.seed_mode(1, a.amp)
            g = growth.measure(box, 1, a.orbits)
            r = dict(wavelength_m=lam, seed=seed, N=box.N, growth_rate=g.growth_rate, frequency=g.frequency,
                     frequency_lomb=g.frequency_lomb, hydro_growth_rate=float(d.growth_rate[0]),
                     hydro_frequency=float(d.frequency[0]), wall_s=time.time() - t0)
            out.append(r)
            print(f"{lam:10.0f} {seed:4d} {box.N:6d} {g.growth_rate:15.5f} {d.growth_rate[0]:8.5f} "
                  f"{g.frequency:15.4f} {g.frequency_lomb:7.4f} {d.frequency[0]:7.4f}", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0
