"""Recipes of Section 6.

"nlvg" (hydro nonlinear dispersion relation and
group velocities), "nbvga" (N-body nonlinear dispersion relation), "osfrat" (lambda_zero^nl,
lambda_zero^lin, lambda_p ratios with buffer-zone runs); "lambdap" is in :mod:`.lambdap_recipe`.  The nonlinear frequencies come from
:mod:`ringcore.experiments.nonlinear` (box L_x = lambda, large seeded mode, transient discarded,
Lomb periodogram of u at a fixed point).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from ..figures._mpl import cmap, subplots
from .. import linear, params
from ..checks import check_choice
from ..analysis.saturation import C_EMPIRICAL
from .nonlinear import (frequency_minimum, group_velocity, hydro_frequency, nbody_frequency,
                                  to_arrays)
from ..io import read_run
from .nbody_recipes import _lin_settings, _linear_nbody
from .recipe_common import finish, hydro_run, pick, psd_below
from .recipe_base import recipe



def nonlinear_curve(p, wavelengths, mode, **kw):
    """Nonlinear hydro frequencies at ``wavelengths`` (quick: 40 nodes per wavelength, 32 orbits,
    12 discarded; full: h = 1 m, 80 orbits, 30 discarded)."""
    set_kw = pick(mode, dict(nodes=40, orbits=32.0, discard=12.0), dict(h=None, nodes=None, orbits=80.0, discard=30.0))
    set_kw["T_floor"] = 0.01  # strongly nonlinear non-isothermal waves: T -> 0 in rarefactions (see README)
    res = []
    for lam in wavelengths:
        k = dict(set_kw)
        if mode == "full":
            k.update(nodes=int(round(lam)), h=None)  # h = 1 m
        k.update(kw)
        res.append(hydro_frequency(p, float(lam), **k))
    return to_arrays(res)


NLVG_PANELS = (("a", "tau15", False, "tau15 non-isothermal"),
               ("b", "tau20", False, "tau20 non-isothermal"),
               ("c", "tau15_oz2", False, "tau15, Omega_z = 2, non-isothermal"),
               ("d", "tau15", True, "tau15 isothermal (G_T -> inf, p_s = 1)"))
NLVG_LAMBDAS_QUICK = (60.0, 85.0, 120.0, 170.0, 240.0, 340.0, 480.0)  # panel (a)
# quick: five wavelengths around each set's lambda_zero at its two sigma0; full: 25 geometric between the bounds.
# sigma0 stays low in (c), (d): tau15_oz2 has Q0 = 1.12 at 500 and 0.80 at 700 (there the seeded waves are
# overtaken by short modes of amplitude ~0.8); the isothermal tau15 model has Q0 = 1.14 at 700, where the seeded
# waves of lambda >= 55 m blow up within 4-6 orbits with the fast time step (paper, Section 5.2.1: beyond
# sigma0 ~ 600 its isothermal scheme was unstable unless the time step was cut to f_t ~ 0.01).
NLVG_QUICK = {"b": ((400.0, 700.0), (110.0, 170.0, 260.0, 400.0, 600.0)),
              "c": ((200.0, 400.0), (45.0, 60.0, 80.0, 115.0, 165.0)),
              "d": ((200.0, 400.0), (40.0, 60.0, 90.0, 135.0, 200.0))}
NLVG_FULL = {"a": ((100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0), (40.0, 2000.0)),
             "b": ((100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0), (60.0, 3000.0)),
             "c": ((100.0, 200.0, 300.0, 400.0, 500.0), (20.0, 1000.0)),
             "d": ((100.0, 200.0, 300.0, 400.0, 500.0, 600.0), (25.0, 1200.0))}


def nlvg_params(letter: str, sigma0: float):
    """:class:`~ringcore.params.RingParams` of panel ``letter`` ("a"-"d") of Figure 21 at ``sigma0`` [kg/m^2]."""
    check_choice("panel", letter, tuple(row[0] for row in NLVG_PANELS))
    _, name, iso, _ = next(row for row in NLVG_PANELS if row[0] == letter)
    return params.get(name, sigma0=sigma0, isothermal=iso)


def _wavelength_axis(ax):
    """Log wavelength axis labelled 20, 50, 100, 200 ... [m] (no overlapping minor-tick labels)."""
    ax.xaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("wavelength [m]")


def _nlvg_panel(ax, letter, sigmas, lams, mode, data, axv=None):
    """Measure and draw one frequency panel; fill ``data`` (names prefixed ``"b_"`` ... except for panel a);
    return rows (sigma0, lambda_zero^lin, lambda_zero^nl, omega_min^nl)."""
    pre, dim = ("", "wavelength") if letter == "a" else (f"{letter}_", f"{letter}_wavelength")
    curve = np.geomspace(lams[0] / 1.5, lams[-1] * 1.5, 300)
    cols = cmap("viridis")(np.linspace(0, 0.85, len(sigmas)))
    mins = []
    for s, c in zip(sigmas, cols):
        p = nlvg_params(letter, s)
        r = nonlinear_curve(p, lams, mode)
        d = linear.dispersion(p, curve)
        damped = linear.dispersion(p, lams).growth_rate <= 0  # seed decays: no saturated wave, omega unreliable
        w = np.where(damped, np.nan, r["frequency"])
        lz_nl, w_nl = frequency_minimum(lams, w)
        mins.append((s, linear.lambda_zero(p), lz_nl, w_nl))
        vg = group_velocity(lams, w, p.Omega) if lams.size >= 3 else np.full(lams.size, np.nan)
        ax.semilogx(lams, w, "o-", color=c, label=f"{s:g}")
        lost = ~r["dominant"].astype(bool) & ~damped  # shorter modes took over: open symbols
        ax.plot(lams[lost], w[lost], "o", color="w", mec=c, ms=5)
        ax.plot(lams[damped], r["frequency"][damped], "x", color=c, ms=7)
        ax.semilogx(curve, d.frequency, "--", color=c, lw=0.9)
        if np.isfinite(lz_nl):
            ax.plot(lz_nl, w_nl, "v", color=c, ms=9, mec="k")
        if axv is not None:
            axv.semilogx(lams, vg * 1e3, "o-", color=c, label=f"{s:g}")
            axv.semilogx(curve, d.group_velocity_m_s * 1e3, "--", color=c, lw=0.9)
        for key in ("frequency", "frequency_err", "frequency_phase", "linear_frequency", "seed_amplitude",
                    "amplitude", "dominant", "floor_hits"):
            data[f"{pre}{key}_s{s:g}"] = (dim, r[key].astype(float))
        data[f"{pre}status_s{s:g}"] = (dim, np.where(damped, "linearly damped", r["status"]).astype(str))
        data[f"{pre}group_velocity_s{s:g}"] = (dim, vg, {"units": "m s-1", "long_name": "d omega_I^nl/dk"})
    _wavelength_axis(ax)
    ax.set_ylabel(r"$\omega_I$ [$\Omega$]")
    ax.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=7, title_fontsize=7)
    ax.set_title(f"({letter}) {next(row[3] for row in NLVG_PANELS if row[0] == letter)}", fontsize=9)
    return np.array(mins)


@recipe("nlvg", "fig:nlvg", "Nonlinear hydro dispersion relation (tau15, tau20, Omega_z = 2, isothermal) and "
        "group velocities", "3.5 min", "5-21 h")
def nlvg(mode, out, sigmas=None, wavelengths=None, panels="abcd", panel_sigmas=None, panel_wavelengths=None):
    """Figure 21, panels (a)-(d) (``panels``): ``sigmas``/``wavelengths`` set panel (a),
    ``panel_sigmas``/``panel_wavelengths`` ({letter: tuple}) the others (defaults: ``NLVG_QUICK``,
    ``NLVG_FULL``)."""
    panels = [check_choice("panel", x, tuple(row[0] for row in NLVG_PANELS)) for x in panels]
    quick = dict(NLVG_QUICK, a=((400.0, 700.0), NLVG_LAMBDAS_QUICK))
    grid = {x: pick(mode, quick[x][1], tuple(np.geomspace(*NLVG_FULL[x][1], 25).round())) for x in panels}
    sig = {x: pick(mode, quick[x][0], NLVG_FULL[x][0]) for x in panels}
    grid.update(panel_wavelengths or {})
    sig.update(panel_sigmas or {})
    if "a" in panels:
        grid["a"], sig["a"] = wavelengths or grid["a"], sigmas or sig["a"]
    fig, axes = subplots(3, 2, figsize=(11, 13.5))
    fax = dict(zip("abcd", axes[:2].flat))
    ds, rows, data = xr.Dataset(), {}, {}
    for x in panels:
        lams = np.array(grid[x], float)
        pre = "" if x == "a" else f"{x}_"
        d = {}
        rows[x] = _nlvg_panel(fax[x], x, sig[x], lams, mode, d, axes[2, 0] if x == "a" else None)
        data.update(d)
        part = xr.Dataset(d, coords={f"{pre}wavelength": (f"{pre}wavelength", lams, {"units": "m"})})
        for k in d:
            if k.startswith((f"{pre}frequency", f"{pre}linear_frequency")):
                part[k].attrs["units"] = "Omega"
        m = rows[x]
        part[f"{pre}lambda_zero_linear"] = (f"{pre}sigma0", m[:, 1], {"units": "m"})
        part[f"{pre}lambda_zero_nonlinear"] = (f"{pre}sigma0", m[:, 2], {"units": "m"})
        part[f"{pre}omega_min_nonlinear"] = (f"{pre}sigma0", m[:, 3], {"units": "Omega"})
        part = part.assign_coords({f"{pre}sigma0": (f"{pre}sigma0", m[:, 0], {"units": "kg m-2"})})
        ds = xr.merge([ds, part])
    for x in "abcd":
        if x not in panels:
            fax[x].set_axis_off()
    star = ""
    if "a" in panels:
        cols = cmap("viridis")(np.linspace(0, 0.85, len(sig["a"])))
        star = _overplot_lambda_p(fax["a"], out, sig["a"], cols, np.array(grid["a"], float), data)
    axv = axes[2, 0]
    if "a" in panels:
        axv.axhline(0, color="0.6", lw=0.7)
        axv.set_ylim(-0.5, 0.5)
        _wavelength_axis(axv)
        axv.set_ylabel(r"$v_g$ [mm/s]")
        axv.set_title("(a) group velocity: 3-point Lagrange d omega/dk (o) vs linear Eq. (23) (dashed)", fontsize=8)
    else:
        axv.set_axis_off()
    axr = axes[2, 1]
    for x, mk in zip("abcd", "osD^"):
        if x in rows:
            axr.plot(rows[x][:, 0], rows[x][:, 2] / rows[x][:, 1], mk + "-", label=f"({x})")
    axr.axhline(1.0, color="0.6", lw=0.7)
    axr.set_xlabel(r"$\sigma_0$ [kg m$^{-2}$]")
    axr.set_ylabel(r"$\lambda^{nl}_{zero}/\lambda^{lin}_{zero}$")
    axr.set_title("nonlinear shift of the frequency minimum (v symbols / linear minimum)", fontsize=8)
    axr.legend(fontsize=8)
    fig.suptitle("Figure 21 (nlvg): saturated wave trains in boxes L_x = lambda\nnonlinear (o; open: seeded mode "
                 "overtaken; x: linearly damped, seed decays; v: minimum; *: lambda_p), linear Eq. (16) (dashed)",
                 fontsize=9)
    sett = pick(mode, "40 nodes per wavelength, 32 orbits (first 12 discarded)", "h = 1 m, 80 orbits (30 discarded)")
    sett += ", T floor 0.01 T0 (non-isothermal)"
    cap = (f"{mode} run: one box L_x = lambda per point, seed = linear eigenmode with sigma amplitude 0.3 "
           f"(u <= 5 c0), exact mode self-gravity (infinite wave train), fast time step, {sett}; omega from the "
           f"Lomb periodogram of u(x = 0). Panels: " + "; ".join(
               f"({x}) {len(grid[x])} wavelengths {grid[x][0]:g}-{grid[x][-1]:g} m, sigma0 = "
               + ", ".join(f"{s:g}" for s in sig[x]) for x in panels)
           + ". The paper does not give the optical depth of (c) and (d): tau = 1.5 assumed. Group velocities "
           f"drawn for (a) only (all panels' are in the data file). {star}lambda_zero nonlinear vs linear: "
           + "; ".join(f"({x}) " + ", ".join(f"{s:g}: {n:.0f} m vs {l:.0f} m" for s, l, n, _ in rows[x])
                       for x in panels) + ".")
    settings = dict(panels={x: dict(set=nlvg_params(x, 0.0).name, isothermal=nlvg_params(x, 0.0).isothermal,
                                    wavelengths=list(map(float, grid[x])), sigmas=list(map(float, sig[x])))
                            for x in panels})
    if "a" in panels:
        settings.update(wavelengths=list(map(float, grid["a"])), sigmas=list(map(float, sig["a"])))
    return finish(fig, ds, out, "nlvg", cap, settings)


def _overplot_lambda_p(ax, out, sigmas, cols, lams, data) -> str:
    """Asterisks: lambda_p of large-scale runs (``lambdap.nc`` in the same output folder, if present)
    at the nonlinear frequency interpolated in ln(lambda); returns a caption fragment."""
    path = Path(out) / "lambdap.nc"
    if not path.is_file():
        return "(No lambdap.nc in the output folder: run recipe lambdap first for the asterisks.) "
    sat = read_run(path)
    marked = []
    for s, c in zip(sigmas, cols):
        hit = np.flatnonzero(np.isclose(sat.sigma0.values, s))
        key = f"frequency_s{s:g}"
        if hit.size and key in data:
            lp = float(sat.lambda_p.values[hit[0]])
            w = np.asarray(data[key][1], float)
            ok = np.isfinite(w)
            if ok.sum() >= 2 and lams[ok][0] <= lp <= lams[ok][-1]:
                ax.plot(lp, np.interp(np.log(lp), np.log(lams[ok]), w[ok]), "*", ms=14, color=c, mec="k")
                marked.append(f"{s:g}: {lp:.0f} m")
    return f"Asterisks: lambda_p of the lambdap runs ({'; '.join(marked) or 'none in range'}). "


@recipe("nbvga", "fig:nbvga", "N-body nonlinear and linear dispersion relation vs linear hydro (p_s and 2 p_s), tau15",
        "2.5 min", "3-7 h")
def nbvga(mode, out):
    """Figure 22: filled circles = saturated (nonlinear) N-body frequencies
    (:func:`~ringcore.experiments.nonlinear.nbody_frequency`); open boxes = linear N-body frequencies of a
    small seed at the same wavelengths, measured as in recipe "nblin2" (same function and settings)."""
    sigmas = pick(mode, (350.0, 900.0), (150.0, 350.0, 600.0, 900.0))
    lams = np.array(pick(mode, (80.0, 150.0, 300.0), (50.0, 70.0, 100.0, 140.0, 200.0, 280.0, 400.0, 560.0, 800.0)))
    kw = pick(mode, dict(L_y=10.0, equilibrate=3.0, orbits=25.0, discard=8.0),
              dict(L_y=20.0, equilibrate=10.0, orbits=100.0, discard=40.0))
    st = _lin_settings(mode)  # nblin2's settings of the linear measurement
    curve = np.geomspace(40, 1000, 200)
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 4.8), sharey=True)
    cols = cmap("plasma")(np.linspace(0, 0.8, len(sigmas)))
    data = {}
    for s, c in zip(sigmas, cols):
        p = params.get("tau15", sigma0=s)
        r = to_arrays([nbody_frequency(p, float(lam), **kw) for lam in lams])
        g_lin, w_lin = _linear_nbody(p, lams, st["L_y"], st["eq"], st["orbits"])
        ax1.semilogx(curve, linear.dispersion(p, curve).frequency, "-", color="C3", lw=0.9)
        ax1.semilogx(lams, r["frequency"], "o-", color=c, label=f"{s:g}")
        lost = ~r["dominant"].astype(bool)  # shorter modes took over: open symbols
        ax1.plot(lams[lost], r["frequency"][lost], "o", color="w", mec=c, ms=5)
        ax1.semilogx(lams, w_lin, "s", mfc="none", mec=c, ms=8, mew=1.3)
        ax2.semilogx(curve, linear.dispersion(p, curve).frequency, "-", color="C3", lw=0.9)
        ax2.semilogx(curve, linear.dispersion(p.scaled_ps(2.0), curve).frequency, "--", color="C0", lw=0.9)
        ax2.semilogx(lams, r["frequency"], "o", color=c)
        data[f"frequency_s{s:g}"] = ("wavelength", r["frequency"], {"units": "Omega"})
        data[f"frequency_err_s{s:g}"] = ("wavelength", r["frequency_err"], {"units": "Omega"})
        data[f"amplitude_s{s:g}"] = ("wavelength", r["amplitude"], {"units": "R_p Omega"})
        data[f"linear_frequency_s{s:g}"] = ("wavelength", r["linear_frequency"], {"units": "Omega"})
        data[f"nbody_linear_frequency_s{s:g}"] = ("wavelength", w_lin, {"units": "Omega", "long_name":
                                                  "N-body frequency of a small seed (linear growth phase)"})
        data[f"nbody_linear_growth_rate_s{s:g}"] = ("wavelength", g_lin, {"units": "Omega"})
    for ax in (ax1, ax2):
        ax.set_xlabel("wavelength [m]")
    ax1.set_ylabel(r"$\omega_I$ [$\Omega$]")
    ax1.legend(title=r"$\sigma_0$ [kg m$^{-2}$]", fontsize=8)
    ax1.set_title("N-body nonlinear (o) and linear (open boxes) vs linear hydro (red)", fontsize=9)
    ax2.set_title("nonlinear N-body vs linear hydro (red) and hydro with 2 p_s (blue dashed)", fontsize=9)
    fig.suptitle("Figure 22 (nbvga): tau = 1.5, Omega_z = 3.6, Bridges law", fontsize=10)
    ds = xr.Dataset(data, coords={"wavelength": ("wavelength", lams, {"units": "m"})})
    cap = (f"{mode} run: N-body box L_x = lambda, L_y = {kw['L_y']:g} m, R_p = 1 m, {kw['equilibrate']:g} orbits "
           f"settling, m = 1 radial-velocity seed 10 R_p Omega, self-gravity modes down to 10 m, "
           f"{kw['orbits']:g} orbits ({kw['discard']:g} discarded), Lomb periodogram of Re U_1. Open boxes: "
           f"linear N-body frequencies as recipe nblin2 (new box L_y = {st['L_y']:g} m, {st['eq']:g} orbits "
           f"settling, m = 1 seed 2 R_p Omega, single-mode self-gravity, fit over {st['orbits']:g} orbits). "
           "Paper: 4 sigma0 (150-900), L_x = lambda.")
    return finish(fig, ds, out, "nbvga", cap, dict(kw, linear={k: st[k] for k in ("L_y", "eq", "orbits")}))


@recipe("osfrat", "fig:osfrat", "lambda_zero^nl, lambda_zero^lin and buffer-zone lambda_p ratios (tau15)", "2.6 min",
        "10 h")
def osfrat(mode, out):
    sigmas = pick(mode, (300.0, 500.0, 700.0), (200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0))
    L, orbits = pick(mode, 1500.0, 8000.0), pick(mode, 600, 10000)
    factors = pick(mode, (0.9, 1.15, 1.45, 1.85, 2.4), tuple(np.geomspace(0.8, 3.0, 12)))
    rows = []
    for s in sigmas:
        p = params.get("tau15", sigma0=s)
        lz = linear.lambda_zero(p)
        lams = np.array(factors) * lz
        r = nonlinear_curve(p, lams, mode)
        lz_nl, _ = frequency_minimum(lams, r["frequency"])
        sim, _ = hydro_run(p, L, 2.5, orbits, initial="noise", seed=1, buffer=(-L / 16, L / 16, -0.5))
        a = sim.series()
        rows_ = a["strobe"][a["t_strobe"] >= 0.75 * a["t_strobe"][-1]]
        lp = float(min(wl[np.argmax(P)] for wl, P in (psd_below(r, L, L / 4) for r in rows_)))
        rows.append((s, lz, lz_nl, lp))
    s, lz, lnl, lp = np.array(rows).T
    fig, axes = subplots(2, 2, figsize=(10, 8))
    ax = axes[0, 0]
    ax.plot(s, lnl, "o-", label="nl")
    ax.plot(s, lz, "s-", label="lin")
    ax.plot(s, C_EMPIRICAL * lz, "r--", label=f"{C_EMPIRICAL:g} lin (Eq. (55))")
    ax.plot(s, lp, "k*", ms=10, label=r"$\lambda_p$ (buffer)")
    ax.set_ylabel("wavelength [m]")
    ax.legend(fontsize=8)
    for ax, y, lab in ((axes[0, 1], lnl / lz, r"$\lambda^{nl}_{zero}/\lambda^{lin}_{zero}$"),
                       (axes[1, 0], lp / lnl, r"$\lambda_p/\lambda^{nl}_{zero}$"),
                       (axes[1, 1], lp / lz, r"$\lambda_p/\lambda^{lin}_{zero}$")):
        ax.plot(s, y, "ko-")
        ax.set_ylabel(lab)
        ax.axhline(1.0, color="0.6", lw=0.7)
    axes[1, 1].axhline(C_EMPIRICAL, color="r", ls="--", lw=0.8)
    for ax in axes.flat:
        ax.set_xlabel(r"$\sigma_0$ [kg m$^{-2}$]")
    fig.suptitle("Figure 25 (osfrat): tau15 non-isothermal", fontsize=10)
    ds = xr.Dataset({"lambda_zero_linear": ("sigma0", lz, {"units": "m"}),
                     "lambda_zero_nonlinear": ("sigma0", lnl, {"units": "m"}),
                     "lambda_p_buffer": ("sigma0", lp, {"units": "m"})},
                    coords={"sigma0": ("sigma0", s, {"units": "kg m-2"})})
    cap = (f"{mode} run: lambda_zero^nl from nonlinear frequencies (boxes L_x = lambda, as recipe nlvg) at "
           f"{len(factors)} wavelengths {factors[0]:g}-{factors[-1]:g} lambda_zero^lin; lambda_p = smallest prevalent "
           f"wavelength (PSD of the stroboscopic rows, wavelengths <= L_x/4) over the last quarter of white-noise runs with a buffer zone (beta = -0.5, |x| < L_x/16), "
           f"L_x = {L / 1e3:g} km, h = 2.5 m, {orbits} orbits, T floor 0.01 T0. Paper: L_x = 6-8 km, ~10,000 orbits.")
    return finish(fig, ds, out, "osfrat", cap, dict(L_x=L, orbits=orbits, factors=list(factors)))
