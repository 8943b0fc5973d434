"""Recipes for the saturated N-body figures: "vdispnb" (velocity dispersion and collision frequency,
with the hydro points), "boxdouble" (box-size tests: a tiled saturated box, and two box sizes) and
"radvar" (saturation wavelength vs particle radius, periodic and spreading boundaries, Eq. (56)).

Quick: boxes of a few hundred metres and tens to a hundred orbits (same physics: Bridges law,
Omega_z of the parameter set, radial self-gravity Eq. (54)); full: Table 3 boxes and
thousands of orbits.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..figures._mpl import subplots
from .. import params
from ..analysis import lambda_p_approx, power_spectrum
from ..hydro import HydroBlowUp
from ..nbody import NBodyOptions, ShearingBox
from .nbody_recipes import _history_dataset, _overstable_runs
from .recipe_common import finish, hydro_run, pick
from .plan import planned
from .recipe_base import recipe


# ---------------------------------------------------------------------------------------- helpers
def hydro_dispersion(p, L_x, orbits, *, h=2.5, initial="noise", seed=1):
    """Velocity dispersion <c> of a hydro run, as the N-body <c>: mass-weighted sqrt(T) [m/s].

    <c> = sum(sigma sqrt(T)) / sum(sigma) c0 (T in units of c0^2, Eq. (3)), sampled over the second
    half of ``orbits`` (the saturated wave train; Figure 19's hydro points).  This is the
    local (translational) dispersion; the nonlocal pressure, part of c0 (Eq. (12)), is not in it.

    Returns ``(c_mean [m/s], status, sim)``; ``status`` is ``"ok"`` or the blow-up message (then
    the mean is over the samples before it, nan if none).
    """
    sim, status = hydro_run(p, L_x, h, 0.5 * orbits, initial=initial, seed=seed)
    vals = []

    def sample(s, _):
        sig, _u, _v, T = s.primitives()
        vals.append(float(np.sum(sig * np.sqrt(np.maximum(T, 0.0))) / np.sum(sig)) * p.c0)

    if status == "ok":
        sim.on_sample(sample)
        try:
            sim.advance(orbits=0.5 * orbits)
        except HydroBlowUp as exc:
            status = str(exc)
    return (float(np.mean(vals)) if vals else math.nan), status, sim


def run_box(p, L_x, L_y, orbits, *, R_p=1.0, record_every=0.5, profile_every=0.0, fill_fraction=1.0, seed=1):
    """An N-body box of ``L_x`` x ``L_y`` [m] run ``orbits`` from the uniform state (boxdouble, radvar)."""
    box = ShearingBox(p, NBodyOptions(L_x=L_x, L_y=L_y, R_p=R_p, record_every=record_every,
                                      profile_every=profile_every, fill_fraction=fill_fraction), seed=seed)
    box.advance(orbits)
    return box


def final_psd(box):
    """(wavelength [m], PSD normalised to max 1) of the box's radial surface number density profile
    (zones of ~5 R_p; the inset of Figure 18, right)."""
    return power_spectrum(box.profiles().sigma, box.options.L_x, normalise=True)


def most_frequent(values) -> float:
    """The most frequent finite value (ties: the smallest), nan if none (lambda_p over a record)."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if not v.size:
        return math.nan
    vals, counts = np.unique(v, return_counts=True)
    return float(vals[np.argmax(counts)])


def filled_from(times, sigma_rows, fill, threshold=0.5) -> float:
    """First profile time [orbits] at which the zones outside the initially filled strip
    |x| < ``fill`` L_x / 2 hold on average at least ``threshold`` x the box-mean count (the spreading
    ring has filled the box; single zones may still empty in the troughs of the saturated waves);
    nan if it never does (``sigma_rows``: one row of zone counts / mean count per time)."""
    rows = np.nan_to_num(np.asarray(sigma_rows, float), nan=0.0)
    n = rows.shape[1]
    outer = np.abs(2.0 * (np.arange(n) + 0.5) / n - 1.0) > fill
    ok = rows[:, outer].mean(axis=1) >= threshold
    return float(np.asarray(times, float)[np.argmax(ok)]) if ok.any() else math.nan


# ---------------------------------------------------------------------------------------- vdispnb
@recipe("vdispnb", "fig:vdispnb", "N-body <c>(sigma0) and collision frequency, with hydro points "
        "(tau = 1.5, Omega_z = 3.6 and 2)", "3.7 min", "~265 CPU h, beyond 2 cores")
def vdispnb(mode, out):
    sigmas = pick(mode, (0.0, 800.0), (0.0, 100.0, 200.0, 300.0, 450.0, 600.0, 700.0, 800.0, 900.0))
    sets = pick(mode, ("tau15",), ("tau15", "tau15_oz2"))
    hyd = pick(mode, dict(tau15=(1000.0, 400.0)), dict(tau15=(20000.0, 10000.0), tau15_oz2=(10000.0, 10000.0)))
    fig, (ax1, ax2) = subplots(1, 2, figsize=(11, 4.8))
    data, status = {}, {}
    for name, mk, hmk, c in zip(sets, ("*", "+"), ("s", "^"), ("k", "C0")):
        runs, st = _overstable_runs(mode, sigmas, name)
        ds = _history_dataset(runs)
        n = ds.sizes["time"]
        cm = ds.c_mean[:, n // 2:].mean("time") * 1e3
        ax1.plot(ds.sigma0, cm, mk, ms=11, color=c, label=f"N-body {name}")
        ch = []
        for s in sigmas:
            v, status[f"{name} {s:g}"], _ = hydro_dispersion(params.get(name, sigma0=s), *hyd[name])
            ch.append(v * 1e3)
        ax1.plot(sigmas, ch, hmk, ms=8, mfc="none", color=c, label=f"hydro {name} (non-isothermal)")
        ax1.axhline(np.sqrt(params.get(name).T0) * 1e3, ls="--", color=c, lw=0.8, alpha=0.6)
        for i, s in enumerate(sigmas):
            ax2.plot(ds.time, ds.collision_frequency[i], lw=1, label=f"{name} {s:g}")
        data[f"c_mean_{name}"] = ("sigma0", cm.values, {"units": "mm s-1"})
        data[f"c_mean_hydro_{name}"] = ("sigma0", np.array(ch), {"units": "mm s-1"})
        data[f"collision_frequency_{name}"] = (("sigma0", "time"), ds.collision_frequency.values, {"units": "1/orbit"})
    ax1.set_xlabel(r"$\sigma_0$ [kg m$^{-2}$]")
    ax1.set_ylabel(r"$\langle c\rangle$ [mm/s]")
    ax1.legend(fontsize=8)
    ax2.set_xlabel("t [orbits]")
    ax2.set_ylabel(r"$\omega_c$ [1/orbit]")
    ax2.legend(fontsize=7)
    fig.suptitle("Figure 19 (vdispnb): velocity dispersion (time mean of the second half) and collision frequency", fontsize=10)
    ds = xr.Dataset(data, coords={"sigma0": ("sigma0", np.array(sigmas), {"units": "kg m-2"}),
                                  "time": ("time", ds.time.values, {"units": "orbits"})})
    bad = {k: v for k, v in status.items() if v != "ok"}
    hs = "; ".join(f"{k}: L_x = {v[0] / 1e3:g} km, {v[1]:g} orbits" for k, v in hyd.items())
    cap = (f"{mode} run: N-body tau = 1.5 ({', '.join(sets)}), Bridges law, L_x = {st['L_x']:g} m, L_y = {st['L_y']:g} m, "
           f"{st['orbits']:g} orbits from the uniform state. Open symbols: non-isothermal hydro from white noise "
           f"(h = 2.5 m, T floor 0.01 T0; {hs}). Both <c> are the mass-weighted local dispersion sqrt(T) averaged "
           "over the second half (the nonlocal pressure, part of the table's c0, is in neither); dashed: ground-state "
           "sqrt(T0) of the table. Paper: N-body L_x = 5 km (Omega_z = 3.6, epsilon = 0.5) and 2 km (Omega_z = 2), "
           ">= 100 orbits averaging; hydro as Figure etauhydro (Omega_z = 3.6) and L_x = 10 km (Omega_z = 2)."
           + (f" Hydro stopped: {bad}" if bad else ""))
    return finish(fig, ds, out, "vdispnb", cap, dict(nbody=st, hydro=hyd))


# ---------------------------------------------------------------------------------------- boxdouble
@recipe("boxdouble", "fig:boxdouble", "N-body box-size tests: a saturated box tiled to twice its size; "
        "two box sizes (x4) at sigma0 = 300", "5.8 min", "~22 CPU h, beyond 2 cores")
def boxdouble(mode, out):
    L, L_y, t1, t2 = pick(mode, 150.0, 2000.0), pick(mode, 10.0, 10.0), pick(mode, 50.0, 5000.0), pick(mode, 25.0, 3000.0)
    sizes, t3 = pick(mode, (150.0, 600.0), (2000.0, 8000.0)), pick(mode, 60.0, 5000.0)
    units = {"units": "sigma0 (R_p Omega)^2"}
    base = run_box(params.get("tau15", sigma0=150.0), L, L_y, t1)
    snap = base.to_dataset()
    fig, (ax, axr) = subplots(1, 2, figsize=(11, 5.2))
    ax.semilogy(base.history["time"], base.history["ekin"], "k-", lw=1, label=f"L_x = {L:g} m, sigma0 = 150")
    data = {"ekin_base": ("time_base", np.array(base.history["ekin"]), units)}
    for s, c in ((150.0, "k"), (0.0, "C0"), (600.0, "C3")):
        big = ShearingBox.from_dataset(snap, sigma0=s, tile_x=True)
        h0 = len(big.history["time"])
        big.advance(t2)
        t = np.array(big.history["time"][h0:])
        e = np.array(big.history["ekin"][h0:])
        ax.semilogy(t, e, "-", color=c, lw=1, label=f"tiled to {2 * L:g} m, sigma0 = {s:g}")
        data[f"ekin_tiled_s{s:g}"] = ("time_tiled", e, units)
    ax.axvline(base.orbits, color="0.5", ls=":")
    ax.set_title("left: tau = 1.5, Omega_z = 3.6, tiled box", fontsize=9)
    # right panel: the same run in two box sizes (ratio 4), e_kin(t) and the final PSD (inset)
    ins = axr.inset_axes([0.55, 0.1, 0.42, 0.35])
    for Lx, c in zip(sizes, ("k", "C1")):
        box = run_box(params.get("tau15", sigma0=300.0), Lx, L_y, t3)
        lam, P = final_psd(box)
        axr.semilogy(box.history["time"], box.history["ekin"], "-", color=c, lw=1,
                     label=f"L_x = {Lx:g} m (final lambda_p = {lam[np.argmax(P)]:.0f} m)")
        ins.semilogx(lam, P, "-", color=c, lw=0.9)
        data[f"ekin_L{Lx:g}"] = ("time_sizes", np.array(box.history["ekin"]), units)
        data[f"psd_L{Lx:g}"] = (f"wavelength_L{Lx:g}", P, {"units": "normalised to max 1"})
        data[f"wavelength_L{Lx:g}"] = (f"wavelength_L{Lx:g}", lam, {"units": "m"})
    ins.set_xlabel("wavelength [m]", fontsize=7)
    ins.set_ylabel("PSD", fontsize=7)
    ins.tick_params(labelsize=6)
    axr.set_title("right: sigma0 = 300 kg/m^2, two box sizes; inset: final PSD", fontsize=9)
    for a in (ax, axr):
        a.set_xlabel("t [orbits]")
        a.set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
        a.legend(fontsize=7, loc="upper left")
    fig.suptitle("Figure 18 (boxdouble): box-size tests, tau = 1.5, Omega_z = 3.6, Bridges law", fontsize=10)
    ds = xr.Dataset(data, coords={"time_base": ("time_base", np.array(base.history["time"]), {"units": "orbits"}),
                                  "time_tiled": ("time_tiled", t, {"units": "orbits"}),
                                  "time_sizes": ("time_sizes", np.array(box.history["time"]), {"units": "orbits"})})
    cap = (f"{mode} run: N-body, L_y = {L_y:g} m. Left: sigma0 = 150 kg/m^2 in L_x = {L:g} m for {t1:g} orbits; the "
           f"final state tiled radially (x2) and continued {t2:g} orbits with sigma0 = 150, 0, 600 kg/m^2. Right: "
           f"sigma0 = 300 kg/m^2 from the uniform state in L_x = {sizes[0]:g} and {sizes[1]:g} m for {t3:g} orbits; "
           "inset: PSD of the final radial surface number density. Paper: 2 km -> 4 km at 5,000 orbits (left), "
           "2 km vs 8 km (right; its duration is not given, 5,000 orbits assumed in full mode).")
    return finish(fig, ds, out, "boxdouble", cap, dict(L_x=L, L_y=L_y, orbits_base=t1, orbits_tiled=t2,
                                                       sizes=sizes, orbits_sizes=t3))


# ---------------------------------------------------------------------------------------- radvar
def _radvar_settings(mode):
    return dict(radii=pick(mode, (1.0, 1.5, 2.0), (1.0, 1.5, 2.0, 2.5, 3.0, 4.0)),
                sb_radii=pick(mode, (1.0, 1.5), (1.0, 2.0)), L_x=pick(mode, 150.0, 2000.0),
                L_y=pick(mode, 6.0, 10.0), orbits=pick(mode, 60.0, 5000.0), fill_fraction=0.75,
                orbits_sb=pick(mode, 80.0, 5000.0))


def _radvar_task(R, L1, Ly1, orbits, fill=1.0):
    """One radvar run: L_x = L1 (R_p/1 m)^2, L_y = Ly1 (R_p/1 m), tau15 at sigma0 = 900.

    Spreading boundaries (``fill`` < 1): the central strip holds all particles at tau / fill; the box's
    self-gravity normalises the density to the box mean, so sigma0 is the box mean (the strip has
    sigma0 / fill) and the filled box is the periodic-boundary system (tau, sigma0)."""
    task = dict(label=f"{'sb' if fill < 1 else 'pb'}_R{R:g}", engine="nbody", set="tau15", sigma0=900.0, seed=1,
                orbits=orbits, options=dict(L_x=L1 * R**2, L_y=Ly1 * R, R_p=R, record_every=1.0,
                                            profile_every=1.0 if fill < 1 else 0.0, fill_fraction=fill))
    if fill < 1:
        task["tau"] = params.get("tau15").tau / fill
    return task


def _radvar_tasks(mode):
    st = _radvar_settings(mode)
    pb = [_radvar_task(R, st["L_x"], st["L_y"], st["orbits"]) for R in st["radii"]]
    sb = [_radvar_task(R, st["L_x"], st["L_y"], st["orbits_sb"], st["fill_fraction"]) for R in st["sb_radii"]]
    return pb + sb, dict(L_x=st["L_x"], L_y=st["L_y"], orbits=st["orbits"], fill_fraction=st["fill_fraction"],
                         orbits_sb=st["orbits_sb"])


def _radvar_result(box, fill):
    """(lambda_p [m], <c> [m/s], t_fill) of a finished radvar run (partial: of its last checkpoint)."""
    h = box.history
    t = np.array(h["time"])
    t_fill = 0.0 if fill >= 1 else filled_from(box.profile_history["time"], box.profile_history["sigma"], fill)
    # lambda_p over the second half, and only once the box is filled (spreading boundaries)
    keep = t >= max(0.5 * t[-1], t_fill if math.isfinite(t_fill) else t[-1])
    return most_frequent(np.array(h["lambda_p"])[keep]), float(np.mean(np.array(h["c_mean"])[keep])), t_fill


@planned("radvar", "fig:radvar", "N-body saturation wavelength vs particle radius, sigma0 = 900, periodic and "
         "spreading boundaries (Eq. (56))", "2.7 min", "40 CPU h, 21 h on 2 cores", tasks=_radvar_tasks)
def radvar(mode, out, models, st, partial=None):
    pb_lab = [k for k in models if k.startswith("pb_")]
    sb_lab = [k for k in models if k.startswith("sb_")]
    radii = np.array([models[k].options.R_p for k in pb_lab])
    sb_radii = np.array([models[k].options.R_p for k in sb_lab])
    L1, Ly1, orbits, fill, sb_orbits = st["L_x"], st["L_y"], st["orbits"], st["fill_fraction"], st["orbits_sb"]
    p = params.get("tau15", sigma0=900.0)
    pb = np.array([_radvar_result(models[k], 1.0) for k in pb_lab], float).reshape(-1, 3)
    sb = np.array([_radvar_result(models[k], fill) for k in sb_lab], float).reshape(-1, 3)
    # c0 ~ R_p => lambda_J ~ R_p^2; Eq. (56) with the sign of Eq. (22), 2C(p_s + F2) lambda_J
    # (the paper prints p_s - F2; see ringcore.analysis.saturation.lambda_p_approx)
    approx = np.array([lambda_p_approx(p) * R**2 for R in radii])
    fig, ax = subplots(figsize=(7, 5))
    ax.plot(radii, pb[:, 0], "*", ms=12, color="k", label="N-body, periodic boundaries (PB)")
    filled = np.isfinite(sb[:, 2])
    ax.plot(sb_radii[filled], sb[filled, 0], "D", ms=8, color="C3", label="N-body, spreading boundaries (SB)")
    if (~filled).any():
        ax.plot(sb_radii[~filled], sb[~filled, 0], "D", ms=8, mfc="none", color="C3", label="SB, box not yet filled")
    ax.plot(radii, approx, "k--", label=r"Eq. (56), $2C(p_s+F_2)\lambda_J \times (R_p/1\,$m$)^2$")
    ax.set_xlabel(r"$R_p$ [m]")
    ax.set_ylabel(r"$\lambda_p$ [m]")
    ax.legend(fontsize=8)
    ax.set_title("Figure 26 (radvar): tau = 1.5, Omega_z = 3.6, sigma0 = 900 kg/m^2", fontsize=10)
    ds = xr.Dataset({"lambda_p": ("R_p", pb[:, 0], {"units": "m"}), "c_mean": ("R_p", pb[:, 1], {"units": "m s-1"}),
                     "lambda_p_approx": ("R_p", approx, {"units": "m"}),
                     "lambda_p_sb": ("R_p_sb", sb[:, 0], {"units": "m"}), "c_mean_sb": ("R_p_sb", sb[:, 1], {"units": "m s-1"}),
                     "filled_orbit_sb": ("R_p_sb", sb[:, 2], {"units": "orbits"})},
                    coords={"R_p": ("R_p", radii, {"units": "m"}), "R_p_sb": ("R_p_sb", sb_radii, {"units": "m"})})
    cap = (f"{mode} run: N-body with L_x = {L1:g} m (R_p/1 m)^2, L_y = {Ly1:g} m (R_p/1 m), Bridges law unchanged "
           f"(v_c = 0.077 mm/s), tau, sigma0 unchanged; PB: {orbits:g} orbits; SB: all particles in the central {fill:g} "
           f"of the box (tau = {1.5 / fill:g}, sigma = {900 / fill:g} kg/m^2 there; filled, the box is the PB system), "
           f"{sb_orbits:g} orbits (filled: the initially empty zones hold >= 0.5 x the box-mean count from orbit "
           f"{', '.join(f'{v:.0f}' for v in sb[:, 2])}). lambda_p = most frequent prevalent wavelength of the second "
           "half (SB: once filled). Dashed: Eq. (56) as 2C(p_s + F2) lambda_J (R_p/1 m)^2, the sign that "
           "follows from Eq. (22) (the paper prints p_s - F2; at sigma0 = 900, Q0 = 0.9, the estimate is rough "
           "either way). Paper: L_x = 2 km (R_p/1 m)^2, R_p = 1-4 m, thousands of orbits, two SB runs (radii not "
           "given).")
    return finish(fig, ds, out, "radvar", cap, st, partial=partial)
