"""Saturation summary of a run: the numbers a run file's ``summary_json`` and the sweeps report.

:func:`series_summary` and :func:`strobe_wavelength` work on plain recorded series of either
engine; :func:`summary` applies them to a hydro :class:`ringcore.engine.State` (or to a
:class:`~ringcore.hydro.Hydro1D`, through its ``snapshot()``).

References: Section 6; Eqs. (39), (38).
"""
from __future__ import annotations

import math

import numpy as np

from .. import ranges
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys
from ..engine import State
from ..units import e_kin_rp
from ..units import time_to_orbits
from .spectra import power_spectrum


def _last(t, last_fraction: float):
    """Mask of the samples in the last ``last_fraction`` (0 < f <= 1, by time) of the series ``t``."""
    ranges.check("last_fraction", last_fraction)
    return t >= t[-1] - last_fraction * (t[-1] - t[0])


def series_summary(t, lambda_p, e_kin, last_fraction: float = 0.25) -> dict:
    """``lambda_p_m`` (most frequent finite value [m]), ``lambda_p_mean_m`` [m] and ``e_kin`` (mean,
    units of the input) over the last ``last_fraction`` of the sample times ``t`` (any unit); nan if empty."""
    ranges.check("last_fraction", last_fraction)
    t = np.asarray(t, float)
    out = dict(lambda_p_m=math.nan, lambda_p_mean_m=math.nan, e_kin=math.nan)
    if t.size == 0:
        return out
    sel = _last(t, last_fraction)
    lam = np.asarray(lambda_p, float)[sel]
    lam = lam[np.isfinite(lam)]
    if lam.size:
        vals, counts = np.unique(lam, return_counts=True)
        out.update(lambda_p_m=float(vals[np.argmax(counts)]), lambda_p_mean_m=float(lam.mean()))
    out["e_kin"] = float(np.asarray(e_kin, float)[sel].mean())
    return out


def _mode(x: np.ndarray) -> float:
    vals, counts = np.unique(x, return_counts=True)
    return float(vals[np.argmax(counts)])


def saturation_flag(t, lambda_p, last_fraction: float = 0.25) -> dict:
    """Had the prevalent wavelength stopped growing?  ``saturated`` 1.0 if the most frequent
    lambda_p of the second half of the last ``last_fraction`` (by time) is not larger than that of
    its first half, 0.0 if it is (the waves were still coarsening: lambda_p, which only grows by
    merging, is then a lower bound of the saturated value), nan with fewer than 4 finite samples
    there; ``lambda_p_growth`` the ratio of the two (second / first half).
    """
    t = np.asarray(t, float)
    out = dict(saturated=math.nan, lambda_p_growth=math.nan)
    if t.size == 0:
        return out
    sel = _last(t, last_fraction)
    tt, lam = t[sel], np.asarray(lambda_p, float)[sel]
    ok = np.isfinite(lam)
    tt, lam = tt[ok], lam[ok]
    if lam.size < 4:
        return out
    half = tt >= 0.5 * (tt[0] + tt[-1])
    if half.all() or not half.any():
        return out
    first, second = _mode(lam[~half]), _mode(lam[half])
    growth = second / first
    return dict(saturated=float(growth <= 1.0 + 1e-12), lambda_p_growth=float(growth))


def strobe_wavelength(t_rows, rows, L_x_m: float, last_fraction: float = 0.25) -> float:
    """Peak wavelength [m] of the time-averaged normalised PSD (:func:`ringcore.analysis.power_spectrum`) of the
    stroboscopic rows (sigma/sigma0) in the last ``last_fraction`` of their times; nan with fewer than two rows."""
    t_rows = np.asarray(t_rows, float)
    if t_rows.size <= 1:
        return math.nan
    sel_rows = rows[_last(t_rows, last_fraction)]
    if not sel_rows.shape[0]:
        return math.nan
    wl, P = power_spectrum(np.asarray(sel_rows, float), L_x_m, normalise=True)
    return float(wl[np.argmax(P.mean(axis=0))])


def summary(run, last_fraction: float = 0.25) -> dict:
    """Saturation summary of a hydro run (a ``State`` of kind "hydro" or an engine) over its last
    ``last_fraction`` (by time).

    Keys: ``lambda_p_m`` (also ``lambda_p_most_frequent_m``) most frequent sampled prevalent wavelength [m];
    ``lambda_p_mean_m`` its mean [m]; ``lambda_p_psd_m`` peak of the time-averaged PSD of the
    stroboscopic sigma rows [m] (nan without strobe rows); ``e_kin`` mean kinetic energy density
    [sigma0 (R_p Omega)^2, R_p = 1 m: :data:`ringcore.units.E_KIN_UNIT`, as the N-body box's] and
    ``e_kin_dimless`` the same in sigma0 c0^2 (the old key ``e_kin_rp`` = ``e_kin`` warns once); ``c_mean`` mass-weighted
    mean velocity dispersion sqrt(T) of the final state [m/s]; ``orbits``; ``steps``;
    ``saturated`` and ``lambda_p_growth`` (:func:`saturation_flag`).
    """
    # deferred: ringcore.hydro loads the numba engines (~2 s); ringcore.analysis (via .prevalent) does not
    from ..hydro.convert import cons_to_prim

    ranges.check("last_fraction", last_fraction)
    st = run if isinstance(run, State) else run.snapshot()
    if st.kind != "hydro":
        raise ValueError(f"run of kind {st.kind!r} is not valid here: give a hydro State or engine")
    a, m, p = st.arrays, st.meta, st.params
    out = dict(orbits=time_to_orbits(m["t"]), steps=int(m["steps"]))
    out.update(series_summary(a["rec_t"], a["rec_lambda_p"], a["rec_e_kin"], last_fraction))
    out.update(saturation_flag(a["rec_t"], a["rec_lambda_p"], last_fraction))
    sc = p.scales
    out["e_kin_dimless"] = out["e_kin"]
    out["e_kin"] = out["e_kin_rp"] = float(e_kin_rp(out["e_kin_dimless"], sc.velocity, p.Omega))
    out["lambda_p_most_frequent_m"] = out["lambda_p_m"]  # the name of its method (ringcore.analysis.prevalent)
    out["lambda_p_psd_m"] = strobe_wavelength(a["rec_t_strobe"], a["rec_strobe"], st.options.L_x, last_fraction)
    sig, _, _, T = cons_to_prim(a["U"])
    out["c_mean"] = float(np.sum(sig * np.sqrt(np.maximum(T, 0.0))) / np.sum(sig)) * sc.velocity
    return DeprecatedKeys(out, E_KIN_RP_KEY)
