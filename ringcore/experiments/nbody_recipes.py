"""Recipes for the N-body figures: "nblin1", "nblin2" (linear growth rates and frequencies vs hydro),
"enbody" (e_kin(t)); "vdispnb", "boxdouble" and "radvar" are in
:mod:`ringcore.experiments.nbody_saturation_recipes` (they use :func:`_overstable_runs` and
:func:`_history_dataset` from here).

Quick: boxes of a few hundred metres and tens to a hundred orbits (same physics: Bridges law,
Omega_z of the parameter set, radial self-gravity Eq. (54)); full: Table 3 boxes and
thousands of orbits.
"""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..figures._mpl import cmap, subplots
from .. import linear, params
from ..nbody import NBodyOptions, ShearingBox, growth
from .recipe_common import finish, pick
from .plan import planned
from .recipe_base import recipe


def _linear_nbody(p, lams, L_y, eq, orbits, single=True):
    """N-body growth rate and frequency of a small m = 1 seed (2 R_p Omega) in boxes L_x = lambda."""
    g, w = [], []
    for lam in lams:
        box = ShearingBox(p, NBodyOptions(L_x=lam, L_y=L_y, single_mode=1 if single else 0, record_every=1.0,
                                          profile_every=0.0), seed=1)
        box.advance(eq)
        box.seed_mode(1, 2.0)
        r = growth.measure(box, 1, orbits, skip=1.0)
        g.append(r.growth_rate)
        w.append(r.frequency)
    return np.array(g), np.array(w)


def _lin_settings(mode):
    return pick(mode, dict(lams=(100.0, 200.0), L_y=10.0, eq=3.0, orbits=12.0),
                dict(lams=tuple(1000.0 / np.arange(1, 26)), L_y=25.0, eq=10.0, orbits=20.0))


@recipe("nblin1", "fig:nblin1", "N-body linear growth rates vs hydro, tau = 1.5, 2 (sigma0 = 0, 350)", "3.6 min", "6 h")
def nblin1(mode, out):
    st = _lin_settings(mode)
    sets = pick(mode, ("tau15", "tau20"), ("tau10", "tau15", "tau20"))
    lams = np.array(st["lams"])
    curve = np.geomspace(40, 1200, 200)
    fig, ax = subplots(figsize=(8, 5.2))
    data = {}
    for name, c in zip(sets, ("C0", "k", "C3")):
        for s, mk in ((0.0, "o"), (350.0, "s")):
            p = params.get(name, sigma0=s)
            g, w = _linear_nbody(p, lams, st["L_y"], st["eq"], st["orbits"])
            ax.semilogx(curve, linear.dispersion(p, curve).growth_rate, "-" if s else "--", color=c, lw=0.9)
            ax.semilogx(lams, g, mk, color=c, mfc=c if s else "none", label=f"{name}, sigma0 = {s:g}")
            data[f"growth_rate_{name}_s{s:g}"] = ("wavelength", g, {"units": "Omega"})
            data[f"frequency_{name}_s{s:g}"] = ("wavelength", w, {"units": "Omega"})
    ax.axhline(0, color="0.6", lw=0.7)
    ax.set_ylim(-0.06, 0.08)
    ax.set_xlabel("wavelength [m]")
    ax.set_ylabel(r"$\omega_R$ [$\Omega$]")
    ax.legend(fontsize=8)
    ax.set_title("Figure 4 (nblin1): N-body (symbols; filled: 350 kg/m^2) vs non-isothermal hydro (lines)", fontsize=9)
    ds = xr.Dataset(data, coords={"wavelength": ("wavelength", lams, {"units": "m"})})
    cap = (f"{mode} run: Omega_z = 3.6, Bridges law, box L_x = lambda, L_y = {st['L_y']:g} m, {st['eq']:g} orbits "
           f"settling, m = 1 radial-velocity seed 2 R_p Omega, self-gravity from this mode only, fit over "
           f"{st['orbits']:g} orbits (growth.measure). Paper: L_x = 1 km, m = 1-25, ~20 orbits.")
    return finish(fig, ds, out, "nblin1", cap, st)


@recipe("nblin2", "fig:nblin2", "N-body linear growth rates and frequencies vs hydro (p_s and 1.4 p_s), tau = 1.5",
        "1.8 min", "5 h")
def nblin2(mode, out):
    st = _lin_settings(mode)
    sigmas = pick(mode, (0.0, 600.0), (0.0, 150.0, 350.0, 600.0, 900.0))
    lams = np.array(st["lams"])
    curve = np.geomspace(40, 1200, 200)
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 4.8))
    cols = cmap("plasma")(np.linspace(0, 0.8, len(sigmas)))
    data = {}
    for s, c in zip(sigmas, cols):
        p = params.get("tau15", sigma0=s)
        g, w = _linear_nbody(p, lams, st["L_y"], st["eq"], st["orbits"])
        d, dm = linear.dispersion(p, curve), linear.dispersion(p.scaled_ps(1.4), curve)
        ax1.semilogx(curve, d.growth_rate, "-", color=c)
        ax1.semilogx(curve, dm.growth_rate, "--", color=c)
        ax1.semilogx(lams, g, "o", color=c, label=f"{s:g}")
        ax2.semilogx(curve, d.frequency, "-", color=c)
        ax2.semilogx(curve, dm.frequency, "--", color=c)
        ax2.semilogx(lams, w, "o", color=c)
        data[f"growth_rate_s{s:g}"] = ("wavelength", g, {"units": "Omega"})
        data[f"frequency_s{s:g}"] = ("wavelength", w, {"units": "Omega"})
    ax1.axhline(0, color="0.6", lw=0.7)
    ax1.set_ylim(-0.06, 0.1)
    ax2.set_ylim(0.8, 1.2)
    ax1.set_ylabel(r"$\omega_R$ [$\Omega$]")
    ax2.set_ylabel(r"$\omega_I$ [$\Omega$]")
    for ax in (ax1, ax2):
        ax.set_xlabel("wavelength [m]")
    ax1.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=8)
    fig.suptitle("Figure 5 (nblin2): tau = 1.5 N-body (o), hydro (solid), hydro with 1.4 p_s (dashed)", fontsize=10)
    ds = xr.Dataset(data, coords={"wavelength": ("wavelength", lams, {"units": "m"})})
    cap = (f"{mode} run: tau = 1.5, Omega_z = 3.6, Bridges law, L_x = lambda, L_y = {st['L_y']:g} m, {st['eq']:g} "
           f"orbits settling, m = 1 seed 2 R_p Omega, single-mode self-gravity, fit over {st['orbits']:g} orbits. "
           "Paper: L_x = 1 km, m = 1-25, sigma0 = 0-900.")
    return finish(fig, ds, out, "nblin2", cap, st)


def _overstable_runs(mode, sigmas, set_name="tau15"):
    """Overstable N-body runs from the uniform state: {sigma0: box}."""
    L, L_y, orbits = pick(mode, 200.0, 5000.0), pick(mode, 10.0, 31.41), pick(mode, 80.0, 5000.0)
    runs = {}
    for s in sigmas:
        box = ShearingBox(params.get(set_name, sigma0=s), NBodyOptions(L_x=L, L_y=L_y, record_every=1.0,
                                                                      profile_every=0.0), seed=1)
        box.advance(orbits)
        runs[s] = box
    return runs, dict(L_x=L, L_y=L_y, orbits=orbits)


def _history_dataset(runs, keys=("ekin", "c_mean", "collision_frequency", "lambda_p")):
    """Records of the runs {sigma0: box} on a common time axis: the longest record's; a shorter record (a
    partial figure: a run not finished) is padded with nan."""
    units = dict(ekin="sigma0 (R_p Omega)^2", c_mean="m s-1", collision_frequency="1/orbit", lambda_p="m")
    sig = list(runs)
    t = np.array(max((runs[s].history["time"] for s in sig), key=len))

    def padded(k):
        rows = np.full((len(sig), t.size), np.nan)
        for i, s in enumerate(sig):
            h = np.asarray(runs[s].history[k], float)
            rows[i, :h.size] = h
        return rows

    data = {k: (("sigma0", "time"), padded(k), {"units": units[k]}) for k in keys}
    return xr.Dataset(data, coords={"sigma0": ("sigma0", np.array(sig), {"units": "kg m-2"}),
                                    "time": ("time", t, {"units": "orbits"})})


def _overstable_tasks(mode, sigmas, set_name="tau15"):
    """The runs of :func:`_overstable_runs` as independent tasks (:mod:`ringcore.experiments.plan`)."""
    L, L_y, orbits = pick(mode, 200.0, 5000.0), pick(mode, 10.0, 31.41), pick(mode, 80.0, 5000.0)
    tasks = [dict(label=f"s{s:g}", engine="nbody", set=set_name, sigma0=float(s), seed=1, orbits=orbits,
                  options=dict(L_x=L, L_y=L_y, record_every=1.0, profile_every=0.0)) for s in sigmas]
    return tasks, dict(L_x=L, L_y=L_y, orbits=orbits)


def _enbody_tasks(mode):
    return _overstable_tasks(mode, pick(mode, (0.0, 800.0),
                                        (0.0, 50.0, 100.0, 150.0, 300.0, 450.0, 600.0, 700.0, 800.0, 900.0)))


@planned("enbody", "fig:enbody", "N-body e_kin(t) for several sigma0 (tau = 1.5)", "65 s", "132 CPU h, 69 h on 2 cores",
         tasks=_enbody_tasks)
def enbody(mode, out, models, st, partial=None):
    runs = {float(m.params.sigma0): m for m in models.values()}
    sigmas = list(runs)
    ds = _history_dataset(runs)
    fig, ax = subplots(figsize=(8, 5.2))
    for i, s in enumerate(sigmas):
        ax.semilogy(ds.time, ds.ekin[i], lw=1, label=f"{s:g} (lambda_p = {runs[s].diagnostics()['lambda_p']:.0f} m)")
    ax.set_xlabel("t [orbits]")
    ax.set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
    ax.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=8)
    ax.set_title("Figure 17 (enbody): N-body, tau = 1.5, Omega_z = 3.6, Bridges law", fontsize=10)
    cap = (f"{mode} run: N-body from the uniform state, L_x = {st['L_x']:g} m, L_y = {st['L_y']:g} m, R_p = 1 m, "
           f"{st['orbits']:g} orbits, self-gravity Eq. (54) with all modes down to 4 R_p. "
           "Paper: L_x = 5 km, L_y = 31.4 m (75,000 particles), ~5,000 orbits, tau = 1.5 and 2.")
    return finish(fig, ds, out, "enbody", cap, st, partial=partial)
