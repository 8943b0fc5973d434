"""Saturation summary of a run: the numbers a run file's ``summary_json`` and the sweeps report.

:func:`series_summary` and :func:`strobe_wavelength` work on plain recorded series of either
engine; :func:`summary` of a hydro :class:`ringcore.engine.State` (or of a :class:`~ringcore.hydro.Hydro1D`,
through its ``snapshot()``) is the hydro engine's :func:`ringcore.hydro.summary.summary`.

References: Section 6; Eqs. (39), (38).
"""
from __future__ import annotations

import math

import numpy as np

from .. import ranges
from ..contract import State
from ..plugins import engine_plugin
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
    ``last_fraction`` (by time): :func:`ringcore.hydro.summary.summary` (the keys are listed there), reached
    through the engine's plug-in module (:mod:`ringcore.plugins`; this layer imports no engine)."""
    ranges.check("last_fraction", last_fraction)
    st = run if isinstance(run, State) else run.snapshot()
    if st.kind != "hydro":
        raise ValueError(f"run of kind {st.kind!r} is not valid here: give a hydro State or engine")
    return engine_plugin(st.kind).state_summary(st, last_fraction)
