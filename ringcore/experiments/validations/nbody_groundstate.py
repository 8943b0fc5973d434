"""Ground-state validation of the N-body shearing box against Table 2
(Salo et al. 2001): T0, nu0 = nu_local + nu_nonlocal, c0 (Eq. (12)), for tau = 1.5 and 2.0
(Omega_z = 3.6, Bridges law) in a 50 m x 25 m box (radially below the overstable band), the
constant eps = 0.5 state, and the time-step halving test (dt = 1e-3 -> 5e-4 orbit).

Usage: ``ringcore validate nbody-groundstate [--orbits 40] [--json out.json]``.
Exit status 1 if a check fails.
"""
import json

from ringcore import params
from ringcore.checks import check_real
from ringcore.nbody import NBodyOptions, ShearingBox

HELP = ("N-body ground state (T0, nu0, c0) against Salo et al. (2001) for tau = 1.5 and 2.0, and the "
        "time-step halving test (exit status 1 if a check fails)")


def add_arguments(p) -> None:
    """Options of ``ringcore validate nbody-groundstate``."""
    p.add_argument("--orbits", type=float, default=40.0, help="averaging interval [orbits] (> 0)")
    p.add_argument("--equilibrate", type=float, default=10.0, help="settling before averaging [orbits] (>= 0)")
    p.add_argument("--json", default=None, help="also write the transport coefficients to this JSON file")


def ground_state(a, set_name, restitution="bridges", dt=1e-3, seed=1):
    p = params.get(set_name)
    box = ShearingBox(p, NBodyOptions(L_x=50, L_y=25, restitution=restitution, dt_orbit=dt), seed=seed)
    box.advance(a.equilibrate)
    box.reset_accumulators()
    box.advance(a.orbits)
    return box.transport()


def run(a) -> int:
    """Run the ground-state checks; 0 if all pass, else 1."""
    check_real("--orbits", a.orbits, 0.0, lo_open=True)
    check_real("--equilibrate", a.equilibrate, 0.0)
    rows, ok = {}, True
    print(f"{'case':<28} {'T [1e-8 m^2/s^2]':>18} {'nu [1e-3 m^2/s]':>16} {'(nu_l + nu_nl)':>16} "
          f"{'c0 [mm/s]':>10} {'c_xx':>6} {'omega_c':>8} {'unres.':>7}")
    for set_name in ("tau15", "tau20"):
        p = params.get(set_name)
        print(f"{set_name + ' table (Salo et al. 2001)':<28} {p.T0 * 1e8:18.3f} {p.nu0 * 1e3:16.3f} {'':>16} {p.c0 * 1e3:10.3f}")
        for law, dt in (("bridges", 1e-3), ("bridges", 5e-4), ("constant", 1e-3), ("constant", 5e-4)):
            if set_name == "tau20" and (law, dt) != ("bridges", 1e-3):
                continue
            tr = ground_state(a, set_name, law, dt)
            key = f"{set_name} {law} dt={dt:g}"
            rows[key] = tr
            print(f"{key:<28} {tr['T'] * 1e8:18.3f} {tr['nu'] * 1e3:16.3f} "
                  f"{'(' + format(tr['nu_local'] * 1e3, '.3f') + ' + ' + format(tr['nu_nonlocal'] * 1e3, '.3f') + ')':>16} "
                  f"{tr['c_eff'] * 1e3:10.3f} {tr['c_eff_xx'] * 1e3:6.3f} {tr['collision_frequency']:8.1f} "
                  f"{tr['unresolved_fraction']:7.3f}", flush=True)
            if law == "bridges" and dt == 1e-3:
                for q, ref in (("T", p.T0), ("nu", p.nu0), ("c_eff", p.c0)):
                    dev = tr[q] / ref - 1
                    ok &= abs(dev) < 0.10
                    print(f"    {q}: {100 * dev:+.1f} % vs table")
    b, h, c = rows["tau15 bridges dt=0.001"], rows["tau15 bridges dt=0.0005"], rows["tau15 constant dt=0.001"]
    dc = (h["T"] / b["T"]) ** 0.5 - 1
    print(f"time-step halving (tau15, Bridges): velocity dispersion T^1/2 changes by {100 * dc:+.2f} %, "
          f"nu by {100 * (h['nu'] / b['nu'] - 1):+.2f} %, c0 by {100 * (h['c_eff'] / b['c_eff'] - 1):+.2f} %; "
          f"unresolved fraction {b['unresolved_fraction']:.3f} -> {h['unresolved_fraction']:.3f}")
    ok &= abs(dc) < 0.05
    hc = rows["tau15 constant dt=0.0005"]
    dcc = (hc["T"] / c["T"]) ** 0.5 - 1
    ok &= abs(dcc) < 0.05
    print(f"time-step halving (tau15, eps = 0.5): T^1/2 changes by {100 * dcc:+.2f} %, nu by "
          f"{100 * (hc['nu'] / c['nu'] - 1):+.2f} %, c0 by {100 * (hc['c_eff'] / c['c_eff'] - 1):+.2f} %; "
          f"unresolved fraction {c['unresolved_fraction']:.3f} -> {hc['unresolved_fraction']:.3f}")
    print(f"constant eps = 0.5 vs Bridges (tau15): nu {100 * (c['nu'] / b['nu'] - 1):+.1f} %, "
          f"c0 {100 * (c['c_eff'] / b['c_eff'] - 1):+.1f} %, T {100 * (c['T'] / b['T'] - 1):+.1f} %")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({k: {q: float(v) for q, v in r.items()} for k, r in rows.items()}, f, indent=1)
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1
