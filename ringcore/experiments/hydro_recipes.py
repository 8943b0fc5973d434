"""Recipes for the hydrodynamic figures without radial self-gravity and the scheme test.

"grates" (Section 4.1.3), "tau15nga", "ekinisonosg", "tau15bufnosg" (Section 5.1.1),
"tau20nonisonosga" (Section 5.1.2).  Quick mode: smaller boxes and fewer orbits,
same physics and scheme; full mode: the paper's boxes, resolutions and durations (cluster).
Non-isothermal long runs use the documented temperature floor T_floor = 0.01 T0 (see README).
"""
from __future__ import annotations


import numpy as np
import xarray as xr

from ..figures._mpl import subplots
from .. import linear, params
from ..analysis import growth_rate, lomb_frequency
from ..hydro import Hydro1D, HydroOptions
from ..units import E_KIN_UNIT
from .recipe_common import finish, hydro_run, pick, series_dataset, strobe_dataset, strobe_psd_figure
from .recipe_base import recipe
from .resolution import resolved_h

GRATES_SIGMAS = (0.0, 350.0, 600.0)


def _grates_growth(p, h, orbits):
    """Growth rates of all modes of a 1-km box seeded with white noise down to 38 m (wire kernel,
    5 replicas, bin correction), from log-linear fits to the Fourier amplitudes (Section 4.1.3)."""
    L = 1000.0
    ms = (1, 2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 25)
    opt = HydroOptions(L_x=L, h=h, timestep="cfl", gravity="wire", replicas=5, bin_correction=True,
                       samples_per_orbit=40, strobe=False, track_modes=ms)
    sim = Hydro1D(p, opt, initial="noise", amplitude=1e-9, lambda_min=38.0, seed=3)
    sim.advance(orbits=orbits)
    a = sim.series()
    g = []
    for j, m in enumerate(ms):
        # split each Fourier coefficient into the left- and right-traveling eigenmodes (c_sigma = a + conj(b),
        # c_u = u_L a - conj(u_L) conj(b)); |a|^2 + |b|^2 grows as exp(2 omega_R t) without the standing-wave beat
        uL = linear.eigenmode(p, L / m).vector[1]
        cs, cu = a["mode_sigma"][:, j], a["mode_u"][:, j]
        left = (cu + np.conj(uL) * cs) / (2 * uL.real)
        right = (uL * cs - cu) / (2 * uL.real)
        g.append(growth_rate(a["t"], np.sqrt(np.abs(left) ** 2 + np.abs(right) ** 2)).value)
    return L / np.array(ms, float), np.array(g)


def _grates_frequency(p, lam, h, orbits):
    """Frequency of one small seeded mode in a box L_x = lambda: Lomb periodogram of u at x = 0."""
    opt = HydroOptions(L_x=lam, h=h, timestep="cfl", gravity="wire", replicas=5, bin_correction=True,
                       samples_per_orbit=40, strobe=False, probes_m=(0.0,), track_modes=(1,))
    sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=1e-6)
    sim.advance(orbits=orbits)
    a = sim.series()
    gr = growth_rate(a["t"], np.abs(a["mode_sigma"][:, 0])).value
    return lomb_frequency(a["t"], a["probe_u"][:, 0] * np.exp(-gr * a["t"]), 0.5, 1.5).value


@recipe("grates", "fig:grates", "Hydro test: linear growth rates and frequencies vs theory (tau15, non-isothermal)",
        "90 s", "1 h")
def grates(mode, out):
    h = pick(mode, 2.0, 1.0)
    orb_g, orb_f = pick(mode, 15.0, 15.0), pick(mode, 8.0, 30.0)
    lam_f = np.array(pick(mode, [50, 80, 125, 200, 400, 1000], [40, 50, 64, 80, 100, 125, 160, 200, 250, 320,
                                                                   400, 500, 640, 800, 1000]), float)
    curve = np.geomspace(25, 1500, 300)
    data = {}
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 4.8))
    worst_g = worst_f = 0.0
    for s, c in zip(GRATES_SIGMAS, ("k", "C0", "C3")):
        p = params.get("tau15", sigma0=s)
        d = linear.dispersion(p, curve)
        lam_g, g = _grates_growth(p, h, orb_g)
        f = np.array([_grates_frequency(p, lam, lam / round(lam / h), orb_f) for lam in lam_f])
        gl = linear.dispersion(p, lam_g).growth_rate
        fl = linear.dispersion(p, lam_f).frequency
        worst_g = max(worst_g, float(np.max(np.abs(g - gl) / np.maximum(np.abs(gl), 1e-3))))
        worst_f = max(worst_f, float(np.max(np.abs(f / fl - 1))))
        ax1.semilogx(curve, d.growth_rate, "-", color=c, label=f"{s:g}")
        ax1.semilogx(lam_g, g, "o", color=c, mfc="none")
        ax2.semilogx(curve, d.frequency, "-", color=c, label=f"{s:g}")
        ax2.semilogx(lam_f, f, "s", color=c, mfc="none")
        data[f"growth_rate_s{s:g}"] = (("wavelength_growth",), g, {"units": "Omega"})
        data[f"frequency_s{s:g}"] = (("wavelength_frequency",), f, {"units": "Omega"})
        data[f"growth_rate_linear_s{s:g}"] = (("wavelength_growth",), gl, {"units": "Omega"})
        data[f"frequency_linear_s{s:g}"] = (("wavelength_frequency",), fl, {"units": "Omega"})
    ax1.axhline(0, color="0.6", lw=0.7)
    ax1.set_ylim(-0.06, 0.08)
    ax1.set_xlabel("wavelength [m]")
    ax1.set_ylabel(r"$\omega_R$ [$\Omega$]")
    ax1.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=8)
    ax2.set_xlabel("wavelength [m]")
    ax2.set_ylabel(r"$\omega_I$ [$\Omega$]")
    ax2.set_ylim(0.85, 1.15)
    fig.suptitle("Figure 3 (grates): hydro (symbols) vs exact linear theory Eq. (16) (lines), tau15 non-isothermal",
                 fontsize=10)
    ds = xr.Dataset(data, coords={"wavelength_growth": ("wavelength_growth", lam_g, {"units": "m"}),
                                  "wavelength_frequency": ("wavelength_frequency", lam_f, {"units": "m"})})
    ds.attrs.update(max_rel_error_growth=worst_g, max_rel_error_frequency=worst_f)
    cap = (f"{mode} run: growth rates from a 1 km box seeded with white noise down to 38 m (amplitude 1e-9, so that products of the fastest modes stay below the slow ones; modes 1000/m m, m <= 25), "
           f"h = {h:g} m, {orb_g:g} orbits, log-linear fit of the Fourier amplitudes (split into left- and right-traveling eigenmodes); frequencies from one seeded mode in "
           f"L_x = lambda, {orb_f:g} orbits, Lomb periodogram of u(x=0). Wire kernel + 5 replicas + bin correction, "
           f"fast time step. Largest deviation: growth {worst_g:.1%} (relative to max(|omega_R|, 1e-3)), "
           f"frequency {worst_f:.2%}.")
    return finish(fig, ds, out, "grates", cap, dict(h=h, orbits_growth=orb_g, orbits_frequency=orb_f))


def _strobe_recipe(mode, out, name, p, L_q, L_f, orb_q, orb_f, title, buffer_frac=None, seed=1, h=2.5):
    L = pick(mode, L_q, L_f)
    orbits = pick(mode, orb_q, orb_f)
    buffer = (-buffer_frac * L, buffer_frac * L, -0.5) if buffer_frac else None
    sim, status = hydro_run(p, L, h, orbits, initial="noise", seed=seed, buffer=buffer)
    lam_max = L / 4 if buffer else None  # leave out the box-scale buffer/ring density contrast
    fig = strobe_psd_figure(sim, title, lam_max)
    lam_p = float(fig.axes[1].lines[0].get_xdata()[np.argmax(fig.axes[1].lines[0].get_ydata())])
    if buffer:
        for ax in fig.axes[:1]:
            ax.axvspan(buffer[0] / 1e3, buffer[1] / 1e3, color="C0", alpha=0.12)
    ds = strobe_dataset(sim, lam_max=lam_max)
    t, e = sim.e_kin_series()
    ds["e_kin"] = ("t", e, {"units": E_KIN_UNIT})
    ds = ds.assign_coords(t=("t", t, {"units": "orbits"}))
    cap = (f"{mode} run: {p.name} {p.model} (p_s = {p.p_s:g}), sigma0 = {p.sigma0:g} kg/m^2, white noise down to 50 m, "
           f"L_x = {L / 1e3:g} km, h = {h:g} m, {sim.orbits:.0f} orbits, fast time step"
           + (f", buffer zone beta = -0.5 in [{buffer[0]/1e3:g}, {buffer[1]/1e3:g}] km (shaded)" if buffer else "")
           + ("" if p.isothermal else ", T floor 0.01 T0") + f". Final lambda_p = {lam_p:.0f} m"
           + (f" (PSD of wavelengths <= L_x/4: the buffer's box-scale density contrast is left out)." if buffer else ".")
           + ("" if status == "ok" else f" STOPPED: {status}")
           + f" Paper: L_x = {L_f / 1e3:g} km, {orb_f:,} orbits.")
    return finish(fig, ds, out, name, cap, dict(L_x=L, orbits=orbits, status=status))


@recipe("tau15nga", "fig:tau15nga", "Stroboscopic space-time diagram and final PSD, tau15 isothermal, no SG",
        "50 s", "1 h")
def tau15nga(mode, out):
    p = params.get("tau15", sigma0=0.0, isothermal=True)
    return _strobe_recipe(mode, out, "tau15nga", p, 2000.0, 10000.0, 1500, 20000,
                          "Figure 7 (tau15nga): isothermal tau15, sigma0 = 0")


@recipe("tau15bufnosg", "fig:tau15bufnosg", "Buffer zone (beta = -0.5): space-time diagram and PSD, tau15 iso, no SG",
        "100 s", "2 h")
def tau15bufnosg(mode, out):
    p = params.get("tau15", sigma0=0.0, isothermal=True)
    return _strobe_recipe(mode, out, "tau15bufnosg", p, 2000.0, 10000.0, 1500, 20000,
                          "Figure 9 (tau15bufnosg): isothermal tau15, sigma0 = 0, buffer zone", buffer_frac=0.125)


@recipe("tau20nonisonosga", "fig:tau20nonisonosga", "Space-time diagram and PSD, tau20 non-isothermal, no SG",
        "~15 min", "5.2 h")
def tau20nonisonosga(mode, out):
    """h = 1.25 m: at 2.5 m the tau20 non-isothermal model is under-resolved (e_kin grows without bound and the
    10 km run blows up at orbit 2,436; README, "Departures").  Full mode is the long run noniso_tau20_h125."""
    p = params.get("tau20", sigma0=0.0)
    return _strobe_recipe(mode, out, "tau20nonisonosga", p, 2000.0, 10000.0, 1500, 14000,
                          "Figure 11 (tau20nonisonosga): non-isothermal tau20, sigma0 = 0",
                          h=resolved_h("tau20", False))


@recipe("ekinisonosg", "fig:ekinisonosg", "e_kin(t) and lambda_p(t), isothermal, no SG (tau15, tau20, st99)",
        "90 s", "8 h")
def ekinisonosg(mode, out):
    L, orbits = pick(mode, 1000.0, 10000.0), pick(mode, 600, 20000)
    runs, status = {}, {}
    for name in ("tau15", "tau20"):
        p = params.get(name, sigma0=0.0, isothermal=True)
        runs[f"{name} noise"], status[f"{name} noise"] = hydro_run(p, L, 2.5, orbits, initial="noise", seed=1)
    for name in ("tau15", "tau20", "st99"):
        p = params.get(name, sigma0=0.0, isothermal=True)
        k = f"{name} 100 m"
        runs[k], status[k] = hydro_run(p, L, 2.5, orbits, initial="mode", wavelength=100.0, amplitude=1e-3)
    ds = series_dataset(runs)
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 4.8))
    for k in runs:
        i = list(runs).index(k)
        col = "C3" if "noise" in k else "k"
        ax1.semilogy(ds.time[i], ds.e_kin[i], color=col, lw=1)
        ax1.text(float(ds.time[i][np.isfinite(ds.time[i])][-1]), float(ds.e_kin[i][np.isfinite(ds.e_kin[i])][-1]),
                 " " + k, fontsize=7, color=col)
        if "100 m" in k:
            ax2.plot(ds.time[i], ds.lambda_p[i], lw=1, label=k)
    for lst in (233, 455, 659):
        ax2.axhline(lst, color="0.5", ls="--", lw=0.8)
    ax1.set_xlabel("t [orbits]")
    ax1.set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
    ax2.set_xlabel("t [orbits]")
    ax2.set_ylabel(r"$\lambda_p$ [m]")
    ax2.legend(fontsize=8)
    fig.suptitle("Figure 8 (ekinisonosg): isothermal, sigma0 = 0 (red: white noise; black: 100 m mode); "
                 "dashed: lambda_st = 233, 455, 659 m (LO2009)", fontsize=9)
    bad = {k: v for k, v in status.items() if v != "ok"}
    cap = (f"{mode} run: isothermal (p_s = 1) tau15, tau20, st99, sigma0 = 0, L_x = {L / 1e3:g} km, h = 2.5 m, "
           f"{orbits} orbits each, fast time step; white noise (amplitude 1e-4, down to 50 m) or a 100 m mode "
           f"(amplitude 1e-3). Paper: L_x = 10 km, ~20,000 orbits." + (f" Stopped runs: {bad}" if bad else ""))
    return finish(fig, ds, out, "ekinisonosg", cap, dict(L_x=L, orbits=orbits, status=status))
