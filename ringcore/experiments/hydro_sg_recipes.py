"""Recipes for the hydrodynamic figures with radial self-gravity and the appendix integrations.

"ekincompare", "sgstable" (isothermal), "etauhydro", "tau15nonisoweaksg" (non-isothermal),
"boxsizecomp01" (Appendix B.1) and "vgpert" (Appendix C).  Quick: smaller boxes / fewer orbits, same physics; full:
the paper's settings.  Non-isothermal runs use the temperature floor 0.01 T0 (see README).
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..figures._mpl import cmap, subplots
from .. import params
from .nonlinear import group_velocity, hydro_frequency
from .recipe_common import (finish, hydro_run, pick, plot_spacetime, series_dataset,
                            strobe_dataset, strobe_psd_figure)
from .recipe_base import recipe
from .resolution import H_PAPER, resolved_h


def _ekin_panels(mode, out, name, panels, L, orbits, iso, title, paper, grid=None):
    """One e_kin(t) panel per parameter set; panels = {set_name: sigma0 list}.

    ``grid(set_name, sigma0) -> (L_x [m], h [m])`` overrides the common box ``L`` and h = 2.5 m per run.
    """
    grid = grid or (lambda set_name, s: (L, H_PAPER))
    fig, axes = subplots(1, len(panels), figsize=(5.5 * len(panels), 4.8))
    axes = np.atleast_1d(axes)
    all_runs, status, used, grids = {}, {}, set(), {}
    for ax, (set_name, sigmas) in zip(axes, panels.items()):
        cols = cmap("viridis")(np.linspace(0, 0.85, len(sigmas)))
        for s, c in zip(sigmas, cols):
            p = params.get(set_name, sigma0=s, isothermal=iso or None)
            k = f"{set_name} {s:g}"
            # the paper needed ~10x smaller steps for the largest isothermal sigma0 (Section 5.2.1)
            small_dt = iso and mode == "full" and s == max(sigmas)
            L_run, h_run = grid(set_name, s)
            used.add((L_run, h_run))
            grids[k] = [L_run, h_run]
            sim, st = hydro_run(p, L_run, h_run, orbits, initial="noise", seed=1,
                                dt_factor=0.11 if small_dt else None)
            all_runs[k], status[k] = sim, st
            t, e = sim.e_kin_series()
            ax.semilogy(t, e, color="C3" if s == max(sigmas) else c, lw=1,
                        label=f"{s:g} ($\\lambda_p$ = {sim.prevalent_wavelength():.0f} m)" + ("" if st == "ok" else " *"))
        ax.set_xlabel("t [orbits]")
        ax.set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
        ax.set_title(set_name, fontsize=9)
        ax.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=7)
    fig.suptitle(title, fontsize=10)
    bad = {k: v for k, v in status.items() if v != "ok"}
    cap = (f"{mode} run: {'isothermal (p_s = 1)' if iso else 'non-isothermal (T floor 0.01 T0)'}, white noise down to "
           f"50 m, {_grid_text(used)}, {orbits} orbits, fast time step. {paper}"
           + (f" * stopped: {bad}" if bad else ""))
    return finish(fig, series_dataset(all_runs), out, name, cap, dict(L_x=L, orbits=orbits, status=status, grid_m=grids))


def _grid_text(used) -> str:
    """'L_x = 5 km, h = 2.5 m' or, for several grids, each with its own L_x and h."""
    return " / ".join(f"L_x = {L / 1e3:g} km, h = {h:g} m" for L, h in sorted(used))


def etau_grid(mode: str, set_name: str, sigma0: float) -> tuple[float, float]:
    """(L_x [m], h [m]) of one run of recipe "etauhydro".

    Quick: 1 km at h = 2.5 m.  Full, as the paper (Section 5.2.2): 20 km at h = 2.5 m, and 5 km at h = 1 m
    for sigma0 >= 700 kg/m^2; the non-isothermal tau20 model gets at least the grid it needs
    (:func:`~ringcore.experiments.resolution.resolved_h`).
    """
    if mode == "quick":
        return 1000.0, H_PAPER
    if sigma0 >= 700.0:
        return 5000.0, 1.0
    return 20000.0, resolved_h(set_name, False)


@recipe("ekincompare", "fig:ekincompare", "e_kin(t) of isothermal runs with self-gravity (tau15, tau20)",
        "4 min", "20 h")
def ekincompare(mode, out):
    panels = pick(mode, {"tau15": (200.0, 300.0, 400.0, 600.0), "tau20": (250.0, 400.0, 700.0)},
                  {"tau15": (200.0, 250.0, 300.0, 400.0, 600.0), "tau20": (250.0, 300.0, 350.0, 400.0, 500.0, 700.0)})
    return _ekin_panels(mode, out, "ekincompare", panels, pick(mode, 1000.0, 5000.0), pick(mode, 500, 20000), True,
                        "Figure 12 (ekincompare): isothermal with radial self-gravity (red: largest sigma0)",
                        "Paper: L_x = 5 km, ~20,000 orbits, f_t ~ 0.01 for the largest sigma0 (full mode: fast time "
                        "step x 0.1 for it; in quick mode that run may stop with a blow-up, as the paper's did at the "
                        "normal time step).")


# full: timed, not the work ratio (which overrates fine grids): 0.5 us per cell and step as measured in the long
# runs, steps per orbit ~209 x (2.5 m / h) for tau15 and ~657 x (1.25 m / h) for tau20 -> ~100 h of one core
@recipe("etauhydro", "fig:etauhydro", "e_kin(t) of non-isothermal runs with self-gravity (tau15, tau20)",
        "3.7 min", "~100 h, beyond 2 cores")
def etauhydro(mode, out):
    panels = pick(mode, {"tau15": (0.0, 300.0, 500.0, 700.0), "tau20": (300.0, 600.0, 900.0)},
                  {"tau15": (0.0, 100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0),
                   "tau20": (0.0, 200.0, 400.0, 600.0, 700.0, 800.0, 1100.0)})
    return _ekin_panels(mode, out, "etauhydro", panels, pick(mode, 1000.0, None), pick(mode, 400, 10000), False,
                        "Figure 14 (etauhydro): non-isothermal with radial self-gravity",
                        "Paper: L_x = 20 km, h = 2.5 m (5 km, h = 1 m for sigma0 >= 700), ~10,000 orbits.",
                        grid=lambda set_name, s: etau_grid(mode, set_name, s))


@recipe("sgstable", "fig:sgstable", "Snapshots and orbit-resolved space-time diagrams, tau15 isothermal, sigma0 = 250, 400",
        "55 s", "2.5 h")
def sgstable(mode, out):
    L, orbits, rows = pick(mode, 1000.0, 5000.0), pick(mode, 600, 20000), pick(mode, 150, 250)
    fig, axes = subplots(2, 2, figsize=(11, 8.5))
    data, status = {}, {}
    for j, s in enumerate((250.0, 400.0)):
        p = params.get("tau15", sigma0=s, isothermal=True)
        # 50 samples per orbit: the 0.02-orbit rows below are sample times, so each row ends exactly on it
        sim, st = hydro_run(p, L, 2.5, orbits, initial="noise", seed=1, samples_per_orbit=50)
        status[s] = st
        t, st_rows = [], []
        for _ in range(rows):  # orbit-resolved rows every 0.02 orbits
            if st != "ok":
                break
            sim.advance(orbits=0.02)
            t.append(sim.orbits)
            st_rows.append(sim.sigma_dimless)
        sig, u, v, _ = sim.primitives()
        ax = axes[0, j]
        ax.plot(sim.x_m / 1e3, sig, "k-", lw=0.8, label="sigma/sigma0")
        ax.plot(sim.x_m / 1e3, u, "C0-", lw=0.8, label="u/c0")
        ax.plot(sim.x_m / 1e3, v, "C3-", lw=0.8, label="v/c0")
        ax.set_xlabel("x [km]")
        ax.set_title(f"sigma0 = {s:g} kg/m^2 (Q0 = {p.Q0:.1f}), lambda_p = {sim.prevalent_wavelength():.0f} m", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
        if st_rows:
            plot_spacetime(axes[1, j], np.array(t), sim.x_m, np.array(st_rows), "orbit-resolved sigma (0.02 orbit)")
            data[f"spacetime_s{s:g}"] = ((f"t_s{s:g}", "x"), np.array(st_rows, np.float32), {"units": "sigma0"})
            data[f"t_s{s:g}"] = (f"t_s{s:g}", np.array(t), {"units": "orbits"})
        for f, arr in (("sigma", sig), ("u", u), ("v", v)):
            data[f"{f}_s{s:g}"] = ("x", arr, {"units": "sigma0" if f == "sigma" else "c0"})
    fig.suptitle("Figure 13 (sgstable): isothermal tau15 with self-gravity: snapshots (top), space-time (bottom)", fontsize=10)
    ds = xr.Dataset(data, coords={"x": ("x", sim.x_m, {"units": "m"})})
    cap = (f"{mode} run: isothermal (p_s = 1) tau15, sigma0 = 250 and 400 kg/m^2, white noise down to 50 m, "
           f"L_x = {L / 1e3:g} km, h = 2.5 m, {orbits} orbits, then {rows} rows every 0.02 orbits. "
           f"Paper: L_x = 5 km, > 20,000 orbits; lambda ~ 170 m and 120 m. Status: {status}")
    return finish(fig, ds, out, "sgstable", cap, dict(L_x=L, orbits=orbits))


@recipe("tau15nonisoweaksg", "fig:tau15nonisoweaksg", "Space-time diagram and PSD, tau15 non-isothermal, sigma0 = 125",
        "55 s", "1.5 h")
def tau15nonisoweaksg(mode, out):
    L, orbits = pick(mode, 2000.0, 20000.0), pick(mode, 1500, 15000)
    p = params.get("tau15", sigma0=125.0)
    sim, st = hydro_run(p, L, 2.5, orbits, initial="noise", seed=1)
    fig = strobe_psd_figure(sim, "Figure 15 (tau15nonisoweaksg): non-isothermal tau15, sigma0 = 125 kg/m^2")
    cap = (f"{mode} run: non-isothermal tau15, sigma0 = 125 kg/m^2, white noise down to 50 m, L_x = {L / 1e3:g} km, "
           f"h = 2.5 m, {sim.orbits:.0f} orbits, fast time step, T floor 0.01 T0. Final lambda_p = "
           f"{sim.prevalent_wavelength():.0f} m. Paper: L_x = 20 km, > 10,000 orbits." + ("" if st == "ok" else f" {st}"))
    return finish(fig, strobe_dataset(sim), out, "tau15nonisoweaksg", cap, dict(L_x=L, orbits=orbits, status=st))


@recipe("boxsizecomp01", "fig:boxsizecomp01", "Influence of L_x on e_kin and the final PSD at small sigma0 (tau15)",
        "2.4 min", "18 h")
def boxsizecomp01(mode, out):
    sigmas = pick(mode, (0.0, 100.0), (0.0, 50.0, 100.0))
    boxes = pick(mode, (1000.0, 3000.0), (10000.0, 30000.0))
    orbits = pick(mode, 500, 15000)
    fig, axes = subplots(2, len(sigmas), figsize=(5.5 * len(sigmas), 8))
    runs = {}
    data = {}
    for j, s in enumerate(sigmas):
        for L, c in zip(boxes, ("k", "C3")):
            sim, st = hydro_run(params.get("tau15", sigma0=s), L, 2.5, orbits, initial="noise", seed=1)
            k = f"{s:g} {L / 1e3:g}km"
            runs[k] = sim
            t, e = sim.e_kin_series()
            axes[0, j].semilogy(t, e, color=c, lw=1, label=f"L_x = {L / 1e3:g} km" + ("" if st == "ok" else " *"))
            wl, P = sim.psd()
            axes[1, j].semilogx(wl, P, color=c, lw=1, label=f"L_x = {L / 1e3:g} km, lambda_p = {wl[np.argmax(P)]:.0f} m")
            data[f"psd_{s:g}_{L:g}"] = (f"wavelength_{L:g}", P)
            data[f"wavelength_{L:g}"] = (f"wavelength_{L:g}", wl, {"units": "m"})
        axes[0, j].set_title(f"sigma0 = {s:g} kg/m^2", fontsize=9)
        axes[0, j].set_xlabel("t [orbits]")
        axes[0, j].set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
        axes[1, j].set_xlabel("wavelength [m]")
        axes[1, j].set_ylabel("final normalised PSD")
        for ax in axes[:, j]:
            ax.legend(fontsize=7)
    fig.suptitle("Figure 28 (boxsizecomp01): tau15 non-isothermal, two box sizes", fontsize=10)
    ds = series_dataset(runs).merge(xr.Dataset(data))
    cap = (f"{mode} run: non-isothermal tau15, white noise down to 50 m (same seed), h = 2.5 m, {orbits} orbits, "
           f"L_x = {boxes[0] / 1e3:g} and {boxes[1] / 1e3:g} km. Paper: 10 and 30 km, sigma0 = 0, 50, 100.")
    return finish(fig, ds, out, "boxsizecomp01", cap, dict(boxes=boxes, orbits=orbits))


@recipe("vgpert", "fig:vgpert", "Space-time diagram of a saturated wave train with the nonlinear group velocity",
        "2.4 min", "5 h")
def vgpert(mode, out):
    s = 400.0
    L, orbits, extra = pick(mode, 2000.0, 20000.0), pick(mode, 700, 10000), pick(mode, 300, 2000)
    p = params.get("tau15", sigma0=s)
    sim, st = hydro_run(p, L, 2.5, orbits + extra, initial="noise", seed=2)
    lam_p = sim.prevalent_wavelength()
    lams = np.round(np.array([0.8, 1.0, 1.25]) * lam_p)  # integer metres (h = 1 m in full mode)
    kw = pick(mode, dict(nodes=40, orbits=32.0, discard=12.0), dict(nodes=None, h=1.0, orbits=80.0, discard=30.0))
    kw["T_floor"] = 0.01
    w = np.array([hydro_frequency(p, lam, **kw).frequency for lam in lams])
    vg = float(group_velocity(lams, w, p.Omega)[1])  # [m/s] at lambda_p
    a = sim.series()
    ts = a["t_strobe"] / (2 * math.pi)
    sel = ts >= orbits
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 5), gridspec_kw=dict(width_ratios=(2, 1)))
    plot_spacetime(ax1, ts[sel], sim.x_m, a["strobe"][sel], "stroboscopic sigma/sigma0 (saturated stage)")
    v_km_orbit = vg * 2 * math.pi / p.Omega / 1e3
    t0, t1 = ts[sel][0], ts[sel][-1]
    for x0 in np.linspace(-L / 2e3, L / 2e3, 5)[:-1]:
        ax1.plot([x0, x0 + v_km_orbit * (t1 - t0)], [t0, t1], "r-", lw=1.2)
    ax1.set_xlim(-L / 2e3, L / 2e3)
    ax2.plot(lams, w, "ko-")
    ax2.set_xlabel("wavelength [m]")
    ax2.set_ylabel(r"$\omega_I^{nl}$ [$\Omega$]")
    ax2.set_title(f"v_g = {vg * 1e3:.3f} mm/s at lambda_p = {lam_p:.0f} m", fontsize=9)
    fig.suptitle(f"Figure 30 (vgpert): tau15 non-isothermal, sigma0 = {s:g} kg/m^2; red: nonlinear group velocity", fontsize=10)
    ds = strobe_dataset(sim).merge(xr.Dataset({"omega_nl": ("wavelength_nl", w, {"units": "Omega"})},
                                              coords={"wavelength_nl": ("wavelength_nl", lams, {"units": "m"})}))
    ds.attrs.update(group_velocity_m_s=vg, lambda_p_m=lam_p)
    cap = (f"{mode} run: non-isothermal tau15, sigma0 = {s:g} kg/m^2, white noise, L_x = {L / 1e3:g} km, h = 2.5 m, "
           f"{orbits + extra} orbits (last {extra} shown), T floor 0.01 T0. Red lines: v_g = d omega^nl/dk = "
           f"{vg * 1e3:.3f} mm/s by 3-point Lagrange differentiation of nonlinear frequencies at 0.8, 1, 1.25 lambda_p "
           "(boxes L_x = lambda). Paper: 20 km boxes, thousands of orbits." + ("" if st == "ok" else f" {st}"))
    return finish(fig, ds, out, "vgpert", cap, dict(L_x=L, orbits=orbits, extra=extra, status=st))
