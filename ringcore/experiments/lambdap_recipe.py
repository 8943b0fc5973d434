"""Recipe "lambdap" of Section 6: Figure 20's hydrodynamic
panels, lambda_p(sigma0) against 1.4 lambda_zero (Eq. (55)), from the sweeps shipped with the app
(``app/data/saturation_sweep*.nc``, written by ``ringcore sweep``) or from in-process hydro runs.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import xarray as xr

from ..figures._mpl import subplots
from .. import linear, params
from ..analysis import lambda_p_empirical
from ..analysis.saturation import C_EMPIRICAL
from ..io.engines import READ_ENGINE
from .recipe_common import finish, hydro_run, pick
from .recipe_base import recipe
from .resolution import resolved_h
from .sweep import run_sweep, shipped_sweep_files, sweep_points

SWEEP_FILE = Path(__file__).resolve().parents[2] / "app" / "data" / "saturation_sweep.nc"

LAMBDAP_PANELS = (("tau15", False), ("tau20", False), ("tau15", True))  # (set, isothermal) of Figure 20's hydro panels


FULL_SWEEP = dict(lx=5000.0, h=2.5, orbits=5000.0)  # full mode: box [m], node spacing [m], orbits per run
# Full-mode panels that need other settings: tau20 non-isothermal is under-resolved at h = 2.5 m (README,
# "Departures"), and at h = 1.25 m a 5 km, 5,000-orbit run costs ~6 h, so that panel runs 9 sigma0 in 4 km for
# 2,000 orbits (~2.2 worker-hours per run, from the shipped 2 km / 1,000-orbit runs' 1,390-2,165 s).
FULL_PANEL = {("tau20", False): dict(sweep=dict(lx=4000.0, h=resolved_h("tau20", False), orbits=2000.0),
                                     sigma0=tuple(float(v) for v in np.arange(100.0, 901.0, 100.0)))}


def full_settings(set_name: str, isothermal: bool) -> dict:
    """Box, node spacing and length of one panel's full-mode runs: :data:`FULL_SWEEP` or its :data:`FULL_PANEL`."""
    return FULL_PANEL.get((set_name, bool(isothermal)), {}).get("sweep", FULL_SWEEP)


def group_points(ds, src: str, out: dict | None = None) -> dict:
    """The runs of one sweep Dataset (:func:`ringcore.experiments.sweep.sweep_points`) added to ``out`` by
    (set, isothermal): lists (sigma0, lambda_p_m, saturated, source); an unknown ``saturated`` counts as True."""
    out = {} if out is None else out
    for p in sweep_points(ds):
        sig, lp, ok, _ = out.setdefault((p["set"], p["isothermal"]), ([], [], [], src))
        sig.append(p["sigma0"])
        lp.append(p["lambda_p_m"])
        ok.append(p["saturated"] is not False)
    return out


def _as_arrays(points: dict) -> dict:
    return {k: (np.array(a), np.array(b), np.array(c, bool), src) for k, (a, b, c, src) in points.items()}


def shipped_sweeps() -> dict:
    """The shipped sweeps (app/data/saturation_sweep.nc and saturation_sweep_*.nc, plain NetCDF written by
    ``ringcore sweep``), grouped by (set, isothermal): dict of (sigma0, lambda_p_m, saturated, source) arrays
    (:func:`group_points`).  Unreadable files are skipped."""
    out = {}
    for path in shipped_sweep_files(SWEEP_FILE):
        try:
            with xr.open_dataset(path, engine=READ_ENGINE) as ds:
                ds = ds.load()
        except (OSError, ValueError):
            continue
        src = f"sweep file app/data/{path.name} (made by: {ds.attrs.get('command', 'ringcore sweep')})"
        if ds.attrs.get("caveat"):  # plain text for the caption (the file's caveat is HTML for the app)
            src += ". Caveat: " + re.sub(r"<[^>]+>", "", str(ds.attrs["caveat"])).rstrip(". ")
        group_points(ds, src, out)
    return _as_arrays(out)


def full_tasks(set_name: str, isothermal: bool, sigmas) -> list:
    """Tasks of ``ringcore sweep`` (engine hydro) for one panel in full mode (:data:`FULL_SWEEP`, seed 1);
    ValueError for an unknown set or model."""
    params.get(set_name, isothermal=bool(isothermal))  # validates the set and model
    return [dict(engine="hydro", set=set_name, sigma0=float(s), isothermal=bool(isothermal), ps_scale=1.0, seed=1,
                 **full_settings(set_name, isothermal)) for s in sigmas]


def swept_points(set_name: str, isothermal: bool, sigmas, outdir, n_workers: int = 2):
    """Full mode: one panel's runs with :func:`ringcore.experiments.sweep.run_sweep` on a LocalCluster of
    ``n_workers`` processes (both cores); each run file is kept in ``outdir``, so calling again after an
    interruption skips the finished runs.  Returns (sigma0, lambda_p_m, saturated, source); failed runs
    (blow-ups) have no point and are named in the source."""
    res = run_sweep(full_tasks(set_name, isothermal, sigmas), outdir, n_workers=n_workers, dashboard=False)
    fs = full_settings(set_name, isothermal)
    src = (f"ringcore sweep on {n_workers} workers, L_x = {fs['lx'] / 1e3:g} km, h = {fs['h']:g} m, "
           f"{fs['orbits']:g} orbits ({outdir})")
    if res.failed:
        src += "; failed: " + ", ".join(f"sigma0 = {r.get('sigma0', '?')}" for r in res.failed)
    got = _as_arrays(group_points(res.dataset, src)).get((set_name, bool(isothermal)))
    return got if got is not None else (np.array([]), np.array([]), np.array([], bool), src)


def saturation_points(mode, set_name="tau15", sigmas=(250.0, 400.0, 600.0, 800.0), use_sweep_file=True,
                      isothermal=False, outdir=None):
    """Measured lambda_p(sigma0) of one set and model: ``(sigma0, lambda_p, saturated, source)`` from the shipped
    sweeps (quick, :func:`shipped_sweeps`) if they hold that set; full with ``outdir``: :func:`swept_points` (Dask,
    both cores); else in-process hydro runs (quick: L_x = 2 km, h = 5 m, 1,000 orbits from white noise; full:
    5 km, h = 2.5 m, 5,000 orbits)."""
    if mode == "quick" and use_sweep_file:
        got = shipped_sweeps().get((set_name, bool(isothermal)))
        if got is not None:
            return got
    if mode == "full" and outdir is not None:
        return swept_points(set_name, isothermal, sigmas, outdir)
    L, h, orbits = pick(mode, 2000.0, 5000.0), pick(mode, 5.0, 2.5), pick(mode, 1000, 5000)
    lam_p = []
    for s in sigmas:
        sim, _ = hydro_run(params.get(set_name, sigma0=s, isothermal=isothermal), L, h, orbits, initial="noise",
                           seed=1)
        a = sim.series()
        last = a["lambda_p"][a["t"] >= a["t"][-1] * 0.75]
        vals, counts = np.unique(last, return_counts=True)
        lam_p.append(float(vals[np.argmax(counts)]))
    return (np.array(sigmas), np.array(lam_p), np.ones(len(sigmas), bool),
            f"hydro runs, L_x = {L / 1e3:g} km, h = {h:g} m, {orbits} orbits")


def _panel_label(set_name, iso):
    return f"{set_name} {'isothermal (p_s = 1)' if iso else 'non-isothermal'}"


@recipe("lambdap", "fig:lambdap", "Saturation wavelength lambda_p(sigma0) vs 1.4 lambda_zero (tau15, tau20, isothermal)",
        "22 s", "~17 h")
def lambdap(mode, out):
    """Figure 20's hydro panels: tau15 and tau20 non-isothermal, tau15 isothermal (p_s = 1).  Quick: the shipped
    sweeps (app/data/saturation_sweep*.nc, 22 s); a panel without a shipped sweep: tau15 an in-process sweep of
    four 2 km runs (5.4 min measured at load 5), the others left out (say so in the caption).  Full: 19 sigma0
    per panel, 5 km, h = 2.5 m, 5,000 orbits (tau20 non-isothermal: :data:`FULL_PANEL`, 9 sigma0, 4 km, h = 1.25 m,
    2,000 orbits), with ``ringcore sweep`` on 2 worker processes (OUT/lambdap_runs/, resumable): ~17 h on 2 cores
    from the shipped sweeps' run times (tau15 ~10 worker-hours, isothermal ~3, tau20 ~20)."""
    sigmas = pick(mode, (250.0, 400.0, 600.0, 800.0), tuple(np.arange(100.0, 1001.0, 50.0)))
    panels, srcs = [], []
    for set_name, iso in LAMBDAP_PANELS:
        panel_sigmas = FULL_PANEL.get((set_name, iso), {}).get("sigma0", sigmas) if mode == "full" else sigmas
        shipped = mode == "quick" and (set_name, iso) in shipped_sweeps()
        if mode == "quick" and not shipped and (set_name, iso) != ("tau15", False):
            continue  # quick: only shipped data for the extra panels
        sig, lam_p, sat, src = saturation_points(mode, set_name, panel_sigmas, isothermal=iso,
                                                 outdir=out / "lambdap_runs" / f"{set_name}{'_iso' if iso else ''}")
        panels.append((set_name, iso, sig, lam_p, sat))
        srcs.append(f"{_panel_label(set_name, iso)}: {src}")
    s = np.linspace(25, 1000, 80)
    fig, axes = subplots(1, len(panels), figsize=(5.2 * len(panels) + 0.6, 5.2), squeeze=False)
    data, coords, ratios = {}, {}, []
    for ax, (set_name, iso, sig, lam_p, sat) in zip(axes[0], panels):
        base = params.get(set_name, isothermal=iso)
        emp = np.array([lambda_p_empirical(base.with_sigma0(v)) for v in s])
        fast = np.array([linear.max_growth(base.with_sigma0(v))[0] for v in s])
        ax.plot(s, emp, "k--", label=f"{C_EMPIRICAL:g} $\\lambda_{{zero}}$, Eq. (55)")
        ax.plot(s, fast, "k:", label="fastest-growing (linear)")
        ax.plot(sig[sat], lam_p[sat], "o", color="C3", label=r"measured $\lambda_p$ (Hydro)")
        if (~sat).any():
            ax.plot(sig[~sat], lam_p[~sat], "^", color="C3", mfc="w", ms=8, label="not saturated (lower bound)")
        ax.set_yscale("log")
        ax.set_xlabel(r"$\sigma_0$ [kg m$^{-2}$]")
        ax.set_ylabel(r"$\lambda_p$ [m]")
        ax.set_title(_panel_label(set_name, iso), fontsize=10)
        ax.legend(fontsize=7)
        ref = np.array([lambda_p_empirical(base.with_sigma0(v)) for v in sig])
        pre = "" if (set_name, iso) == ("tau15", False) else f"{set_name}{'_iso' if iso else ''}_"
        dim = "sigma0" if not pre else f"{pre}sigma0"
        coords[dim] = (dim, sig, {"units": "kg m-2"})
        data[f"{pre}lambda_p"] = (dim, lam_p, {"units": "m"})
        data[f"{pre}lambda_p_empirical"] = (dim, ref, {"units": "m", "long_name": "1.4 lambda_zero"})
        data[f"{pre}ratio"] = (dim, lam_p / ref)
        data[f"{pre}saturated"] = (dim, sat.astype(np.int8))
        ratios.append(f"{_panel_label(set_name, iso)}: " + ", ".join(
            f"{r:.2f}{'' if ok else ' (lower bound)'} at {v:g}" for r, ok, v in zip(lam_p / ref, sat, sig)))
    fig.suptitle("Figure 20 (lambdap): hydrodynamic panels", fontsize=10)
    ds = xr.Dataset(data, coords=coords)
    missing = [_panel_label(*k) for k in LAMBDAP_PANELS if k not in [(a, b) for a, b, *_ in panels]]
    cap = (f"{mode} run: lambda_p (largest Fourier amplitude of sigma, most frequent value over the last quarter) "
           f"from {'; '.join(srcs)}; white noise down to 50 m, fast time step, T floor 0.01 T0 (non-isothermal). "
           f"lambda_p / (1.4 lambda_zero) [kg m-2]: " + "; ".join(ratios) + ". "
           + (f"Not shown (no shipped sweep): {', '.join(missing)}. " if missing else "")
           + "Paper: L_x = 5-20 km, thousands of orbits, 19 values of sigma0. Short runs are not yet "
           "saturated at small sigma0, where the wavelength grows slowly (staircase), so lambda_p lies below the curve.")
    return finish(fig, ds, out, "lambdap", cap, dict(sources=srcs))


# Figure 21 panels: (letter, parameter set, isothermal, label).  The paper names the tau15 and tau20 sets for
# (a), (b) and only "Omega_z = 2" (non-isothermal) and "isothermal" for (c), (d), without their optical depth:
# tau = 1.5 is assumed there, as in panel (a) (sets tau15_oz2 and tau15 in the isothermal limit, p_s = 1).
