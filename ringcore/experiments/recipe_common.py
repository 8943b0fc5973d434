"""Helpers shared by the hydro, N-body and saturation recipes.

Runs are driven through the engines' public APIs (``Hydro1D``, ``ShearingBox``); what a figure
needs is collected into one ``xarray.Dataset`` per recipe (units as attributes, the caption and
the settings as attributes) and written with :func:`ringcore.io.write_run` (kind ``"recipe"``).

Costs given in the ``@recipe`` decorators: *quick* is the wall time measured with
``scripts/run_quick_recipes.py`` on the shared 2-core development machine at load averages of 4-12
(roughly 2-3x the idle time); *full* is that measured time scaled by the work ratio full/quick, i.e.
the sum over runs of cells x (1/h^2) x orbits (hydro; diffusion-limited time step dt ~ h^2) or
particles x orbits (N-body), for one core.
"""
from __future__ import annotations

import json
import math
import textwrap

import numpy as np
import xarray as xr

from ..analysis import power_spectrum
from ..figures._mpl import subplots
from ..hydro import Hydro1D, HydroBlowUp, HydroOptions
from ..io import save_figure, write_run
from ..units import E_KIN_UNIT
from .recipe_base import RecipeResult


def pick(mode: str, quick, full):
    """``quick`` or ``full`` by recipe mode."""
    return quick if mode == "quick" else full


def caption_fig(fig, caption: str) -> None:
    """Put the caption (what was run) under the axes, leaving room for its lines and the x labels."""
    width = max(60, int(150 * fig.get_figwidth() / 11.0))
    text = textwrap.fill(caption, width)
    line = 7.5 * 1.25 / 72.0 / fig.get_figheight()  # height of one caption line, figure fraction
    bottom = 0.02 + (text.count("\n") + 1) * line + 0.75 / fig.get_figheight()
    fig.subplots_adjust(bottom=bottom, top=0.9, left=0.08, right=0.97, wspace=0.28, hspace=0.35)
    fig.text(0.01, 0.01, text, fontsize=7.5, va="bottom", ha="left", color="0.2")


def finish(fig, ds: xr.Dataset, out, name: str, caption: str, settings: dict | None = None,
           partial: str | None = None) -> RecipeResult:
    """Caption and save the PNG, write the data file; return the RecipeResult.

    ``partial``: a note saying which runs are unfinished (a figure drawn before the last run ended): it is
    written across the figure and into the data file's ``partial`` attribute, and the files are
    ``NAME.partial.png`` / ``NAME.partial.nc``, never the final ones."""
    if settings and settings.get("orbits_changed"):
        caption += f" Run lengths changed from the recipe's to {settings['orbits']:g} orbits (--orbits): a trial."
    if partial:
        caption = partial + ". " + caption
        fig.text(0.5, 0.5, "PARTIAL", fontsize=60, color="C3", alpha=0.25, ha="center", va="center",
                 rotation=25, transform=fig.transFigure)
    caption_fig(fig, caption)
    stem = f"{name}.partial" if partial else name
    png = out / f"{stem}.png"
    save_figure(fig, png, dpi=110)
    ds = ds.copy()
    ds.attrs["caption"] = caption
    ds.attrs["recipe"] = name
    if settings is not None:
        ds.attrs["settings_json"] = json.dumps(settings, default=str)
    if partial:
        ds.attrs["partial"] = partial
    data = write_run(ds, out / f"{stem}.nc", kind="recipe")
    return RecipeResult(png, data, caption)


# ---------------------------------------------------------------------------------------- hydro
def hydro_run(p, L_x, h, orbits, *, initial="noise", seed=1, wavelength=None, amplitude=None, lambda_min=50.0,
              buffer=None, buffer_on_orbit=0.0, spacetime_rows=0, samples_per_orbit=10, T_floor=0.01,
              timestep="cfl", dt_factor=None, track_modes=()):
    """Run a ``Hydro1D`` and return ``(sim, status)``; a blow-up stops the run and is reported in
    ``status`` (the records up to the last good state are kept and plotted)."""
    opt = HydroOptions(L_x=L_x, h=h, timestep=timestep, dt_factor=dt_factor, samples_per_orbit=samples_per_orbit,
                       spacetime_rows_per_orbit=spacetime_rows, strobe=True, buffer=buffer,
                       buffer_on_orbit=buffer_on_orbit, T_floor=0.0 if p.isothermal else T_floor,
                       track_modes=tuple(track_modes), probes_m=(0.0,))
    kw = dict(seed=seed, lambda_min=lambda_min) if initial == "noise" else dict(wavelength=wavelength)
    sim = Hydro1D(p, opt, initial=initial, amplitude=amplitude, **kw)
    status = "ok"
    try:
        sim.advance(orbits=orbits)
    except HydroBlowUp as exc:
        status = str(exc)
    return sim, status


def series_dataset(runs: dict) -> xr.Dataset:
    """e_kin(t) and lambda_p(t) of several hydro runs {label: sim} on a common run dimension (nan-padded)."""
    labels = list(runs)
    tt = [runs[k].e_kin_series() for k in labels]  # e_kin in sigma0 (R_p Omega)^2 (Figure 8 units)
    n = max(len(t) for t, _ in tt)
    T = np.full((len(labels), n), np.nan)
    E = np.full_like(T, np.nan)
    L = np.full_like(T, np.nan)
    for i, k in enumerate(labels):
        t, e = tt[i]
        T[i, :t.size], E[i, :t.size] = t, e
        L[i, :t.size] = runs[k].series()["lambda_p"]
    return xr.Dataset({"time": (("run", "sample"), T, {"units": "orbits"}),
                       "e_kin": (("run", "sample"), E, {"units": E_KIN_UNIT}),
                       "lambda_p": (("run", "sample"), L, {"units": "m"})},
                      coords={"run": ("run", np.array(labels, dtype=object))})


def strobe_dataset(sim, prefix: str = "", lam_max=None) -> xr.Dataset:
    """Stroboscopic sigma rows, final sigma profile and final normalised PSD (wavelengths <= lam_max)."""
    a = sim.series()
    wl, P = psd_below(sim.sigma_dimless, sim.options.L_x, lam_max)
    tname, lname = prefix + "t_strobe", prefix + "wavelength"
    return xr.Dataset({prefix + "strobe_sigma": ((tname, prefix + "x"), a["strobe"], {"units": "sigma0"}),
                       prefix + "sigma_final": ((prefix + "x",), sim.sigma_dimless, {"units": "sigma0"}),
                       prefix + "psd_final": ((lname,), P, {"units": "normalised to max 1"})},
                      coords={tname: (tname, a["t_strobe"] / (2 * math.pi), {"units": "orbits"}),
                              prefix + "x": (prefix + "x", sim.x_m, {"units": "m"}),
                              lname: (lname, wl, {"units": "m"})})


def plot_spacetime(ax, t, x_m, rows, title="", cmap="gray", vmax_q=99.0):
    """Space-time diagram of sigma rows (time upward, x in km)."""
    rows = np.asarray(rows, float)
    lo, hi = np.percentile(rows, [100 - vmax_q, vmax_q]) if rows.size else (0, 1)
    ax.imshow(rows, origin="lower", aspect="auto", cmap=cmap, vmin=lo, vmax=hi,
              extent=[x_m[0] / 1e3, x_m[-1] / 1e3, t[0], t[-1] if len(t) > 1 else t[0] + 1])
    ax.set_xlabel("x [km]")
    ax.set_ylabel("t [orbits]")
    if title:
        ax.set_title(title, fontsize=9)


def psd_below(sigma, L_x, lam_max=None):
    """(wavelength [m], PSD normalised to max 1) of a sigma profile, keeping wavelengths <= lam_max [m]
    (:func:`ringcore.analysis.power_spectrum`).

    With a buffer zone the box-scale density contrast between buffer and ring (m = 1, 2, ...) carries
    most of the power; ``lam_max`` (e.g. L_x/4) leaves it out so that lambda_p is the waves' wavelength."""
    return power_spectrum(np.asarray(sigma, float), L_x, normalise=True, max_wavelength=lam_max)


def plot_psd(ax, wl, P, title="final PSD of sigma"):
    ax.semilogx(wl, P, "k-", lw=1)
    ax.set_xlabel("wavelength [m]")
    ax.set_ylabel("normalised PSD")
    j = int(np.argmax(P))
    ax.axvline(wl[j], color="C3", ls=":", lw=1)
    ax.text(wl[j], 0.95, f" $\\lambda_p$ = {wl[j]:.0f} m", color="C3", fontsize=8, va="top")
    ax.set_title(title, fontsize=9)


def strobe_psd_figure(sim, suptitle: str, lam_max=None):
    """Figure 7-type: stroboscopic space-time diagram (left) and final PSD (right)."""
    a = sim.series()
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 5))
    plot_spacetime(ax1, a["t_strobe"] / (2 * math.pi), sim.x_m, a["strobe"], "stroboscopic (1/orbit) sigma/sigma0")
    wl, P = psd_below(sim.sigma_dimless, sim.options.L_x, lam_max)
    plot_psd(ax2, wl, P, "final PSD of sigma" + (f" (lambda <= {lam_max:.0f} m)" if lam_max else ""))
    fig.suptitle(suptitle, fontsize=10)
    return fig
