"""Slow validation (Section 4.1.3, Figure 3): growth rates and frequencies of seeded
single modes versus the exact linear theory, tau15, sigma0 = 0, 350, 600 kg/m^2, h = 1 m,
wavelengths 50 m .. 1 km, non-isothermal and isothermal, fast time step (f_t = 1.1) and
self-gravity by the mode method and by the wire kernel (5 replicas + bin correction, box of
5 wavelengths up to 200 m).

Usage: ``ringcore validate hydro-linear [--quick]``.
Prints one line per mode and the largest relative errors; exit status 1 if any exceeds 1 %
(growth-rate errors relative to max(|omega_R|, 2e-4 Omega), so modes near the stability
boundary are not judged by a relative error of a number close to zero).
"""
import json

import numpy as np

from ringcore import linear, paperrefs, params
from ringcore.analysis import growth_rate, lomb_frequency
from ringcore.hydro import Hydro1D, HydroOptions

WAVELENGTHS = [50, 64, 80, 100, 128, 160, 200, 250, 400, 500, 800, 1000]


def measure(p, lam, gravity="mode", nwave=1, orbits=5.0):
    L = lam * nwave
    opt = HydroOptions(L_x=L, h=1.0, track_modes=(nwave,), probes_m=(0.0,), samples_per_orbit=40,
                       timestep="cfl", gravity=gravity, replicas=5, bin_correction=True)
    sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=1e-6)
    sim.advance(orbits=orbits)
    a = sim.series()
    t = a["t"]
    gr = growth_rate(t, np.abs(a["mode_sigma"][:, 0])).value
    fr = lomb_frequency(t, a["probe_u"][:, 0] * np.exp(-gr * t), 0.5, 1.5, n=20001).value
    return gr, fr


HELP = (f"hydro growth rates and frequencies of seeded modes against the exact linear theory "
        f"({paperrefs.fig('grates')}; exit status 1 above 1 per cent)")


def add_arguments(p) -> None:
    """Options of ``ringcore validate hydro-linear``."""
    p.add_argument("--quick", action="store_true", help="every third wavelength only")
    p.add_argument("--json", default=None, metavar="FILE", help="also write the table to this JSON file")


def run(args) -> int:
    """Run the validation; 0 if every mode is within 1 % of linear theory, else 1."""
    quick = args.quick
    lams = WAVELENGTHS[::3] if quick else WAVELENGTHS
    worst_g = worst_f = 0.0
    rows = []
    print(f"{'model':8s} {'sigma0':>6s} {'grav':>4s} {'lambda':>7s} {'omega_R hydro':>14s} {'linear':>12s} "
          f"{'err':>9s} {'omega_I hydro':>14s} {'linear':>10s} {'err':>9s}")
    for iso in (False, True):
        for s0 in (0.0, 350.0, 600.0):
            p = params.get("tau15", sigma0=s0, isothermal=iso)
            for grav in (("mode", "wire") if s0 > 0 else ("mode",)):
                for lam in lams:
                    if grav == "wire" and lam > 200:
                        continue
                    gr, fr = measure(p, lam, grav, nwave=5 if grav == "wire" else 1)
                    d = linear.dispersion(p, [lam])
                    g0, f0 = d.growth_rate[0], d.frequency[0]
                    eg = abs(gr - g0) / max(abs(g0), 2e-4)
                    ef = abs(fr / f0 - 1)
                    worst_g, worst_f = max(worst_g, eg), max(worst_f, ef)
                    rows.append(dict(model=p.model, sigma0=s0, gravity=grav, wavelength_m=lam, growth_rate=gr,
                                     growth_rate_linear=float(g0), frequency=fr, frequency_linear=float(f0)))
                    print(f"{p.model[:8]:8s} {s0:6.0f} {grav:>4s} {lam:7.1f} {gr:14.6e} {g0:12.6e} {eg:9.2e} "
                          f"{fr:14.6f} {f0:10.6f} {ef:9.2e}", flush=True)
    print(f"largest relative error: growth rate {worst_g:.2e}, frequency {worst_f:.2e}")
    if getattr(args, "json", None):
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0 if max(worst_g, worst_f) < 0.01 else 1
