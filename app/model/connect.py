"""Connect what the student sees: one tab's settings and theory in another tab.

* :func:`carry_values` and :func:`describe` — which of the Linear tab's model settings the hydro or
  N-body runner takes over ("Run this in ...": :mod:`ringlab.tabs.linear.carry`).
* :func:`fastest_allowed_mode` and :func:`slope_line` — the linear growth of e_kin(t) predicted by
  the exact dispersion relation for the fastest-growing wavelength the periodic box allows.
* :func:`allowed_wavelengths` — the wavelengths L_x/n a periodic box can hold, near lambda_p.

References: Eqs. (16), (17), (21), (39), (38).
"""
from __future__ import annotations

import functools
import math

import numpy as np

from ringcore import linear, ranges

from ringlab.model.hydro_settings import toomre_problem

HYDRO_KEYS = ("param_set", "sigma0", "isothermal", "ps_scale", "iso_p_s")  # RingControls -> HydroSettings
NBODY_KEYS = ("param_set", "sigma0")  # the N-body box has no isothermal switch or p_s
KINDS = {"hydro": HYDRO_KEYS, "nbody": NBODY_KEYS}
LABELS = {"hydro": "Hydrodynamics", "nbody": "N-body"}
DOMINANT_FACTOR = 10.0  # the slope line is anchored where e_kin has grown this much above its early minimum


def carry_values(controls, kind: str) -> dict:
    """The settings of a :class:`ringlab.model.controls.RingControls` that the ``kind`` runner ("hydro" or
    "nbody") takes over: parameter set and sigma0, for hydro also the model (isothermal, p_s).

    Raises
    ------
    ValueError
        For an unknown ``kind`` or settings the Linear tab itself rejects.
    """
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r} is unknown: allowed {', '.join(KINDS)}")
    problem = carry_problem(controls, kind)
    if problem:
        raise ValueError(problem)
    return {k: getattr(controls, k) for k in KINDS[kind]}


def carry_problem(controls, kind: str) -> str:
    """Why the ``kind`` runner cannot start a run at the Linear tab's settings ('' if it can): the
    core's sigma0 range (:func:`ringcore.ranges.check_sigma0`), and for hydro also the live run's
    Toomre limit Q0 >= 1 (:func:`ringlab.model.hydro_settings.toomre_problem`).

    Raises ValueError for settings the Linear tab itself rejects (an impossible combination)."""
    p = controls.ring_params()  # raises ValueError for an impossible combination
    try:
        ranges.check_sigma0(p.sigma0, p.Omega, p.c0, set_name=p.name)
    except ValueError as exc:
        return f"{LABELS[kind]} cannot run these settings: {exc}"
    if kind == "hydro":
        why = toomre_problem(p)
        if why:
            return f"{LABELS[kind]} cannot run these settings: {why}"
    return ""


def describe(controls, kind: str) -> str:
    """One line naming what :func:`carry_to` sets (for the message under the buttons)."""
    v = carry_values(controls, kind)
    text = f"{v['param_set']}, σ₀ = {v['sigma0']:g} kg/m²"
    if kind == "hydro":
        text += (f", isothermal (p_s = {v['iso_p_s']:g})" if v["isothermal"] else
                 f", non-isothermal (p_s × {v['ps_scale']:g})")
    elif controls.isothermal or controls.ps_scale != 1.0:
        text += " (the particles have no isothermal switch or p_s: those settings stay in the Linear tab)"
    return text


@functools.lru_cache(maxsize=64)
def fastest_allowed_mode(params, L_x_m: float, n_cells: int) -> dict:
    """The fastest-growing wavelength a periodic box can hold, from the exact dispersion relation.

    Parameters
    ----------
    params : ringcore.params.RingParams
        The run's parameters (sigma0, isothermal model and p_s included).
    L_x_m : float
        Box size [m]; the box holds the wavelengths L_x/n, n = 1 .. n_cells/2.
    n_cells : int
        Grid cells (the shortest resolved wavelength is two cells).

    Returns
    -------
    dict
        ``wavelength_m`` [m], ``n`` (waves in the box), ``growth_rate`` omega_R [Omega] of the
        amplitude (Eq. (21); exact, Eq. (17)) and ``slope_per_orbit`` = 2 omega_R * 2 pi,
        the growth rate of ln e_kin per orbit (e_kin ~ amplitude^2, Eq. (39)).  Memoized (a
        fresh dict per call is not needed: treat it as read-only).
    """
    n = np.arange(1, max(1, int(n_cells) // 2) + 1)
    lam = L_x_m / n
    rate = linear.dispersion(params, lam).growth_rate
    i = int(np.nanargmax(rate))
    g = float(rate[i])
    return dict(wavelength_m=float(lam[i]), n=int(n[i]), growth_rate=g, slope_per_orbit=4.0 * math.pi * g)


def orbit_means(t, e_kin) -> tuple[np.ndarray, np.ndarray]:
    """Means of e_kin over whole orbits [floor(t), floor(t) + 1) and their mean times (t in orbits);
    over as many whole orbits as give at least 3 samples when the series is sparser than that.

    e_kin oscillates within an orbit (energy passes between the wave's motion and its compression
    at about twice the orbital frequency), so growth is read from orbit means.  Positive finite
    values only; orbits with fewer than 3 samples are left out.
    """
    t = np.asarray(t, float)
    e = np.asarray(e_kin, float)
    ok = np.isfinite(e) & (e > 0) & np.isfinite(t)
    t, e = t[ok], e[ok]
    if t.size == 0:
        return t, e
    # a long live run's series is thinned (fewer samples per orbit): bins of several whole orbits then
    w = max(1, math.ceil(3.0 * float(np.median(np.diff(t))) - 1e-9)) if t.size > 1 else 1
    k = np.floor(t / w + 1e-9).astype(np.int64)
    keys, start, counts = np.unique(k, return_index=True, return_counts=True)
    sums_e = np.add.reduceat(e, start)
    sums_t = np.add.reduceat(t, start)
    keep = counts >= 3
    return sums_t[keep] / counts[keep], sums_e[keep] / counts[keep]


def slope_line(t, e_kin, slope_per_orbit: float, factor: float = DOMINANT_FACTOR) -> dict:
    """A straight line on the log e_kin axis with the linear-theory slope, through the run's early e_kin.

    Works on orbit means (:func:`orbit_means`).  The anchor is the first orbit after the early
    minimum (white noise first loses its damped modes) whose mean e_kin has grown ``factor`` times
    above it — by then the fastest-growing mode dominates — or the latest orbit while none has.
    The line runs from the level of that minimum through the anchor until the latest sample time or
    until it passes 3 x the largest orbit mean so far (it shows where the run leaves linear growth).

    Returns ``dict(t=[t0, t1], e_kin=[e0, e1], anchor_t=..., anchor_e=...)`` (t in orbits); empty
    lists (and nan) before two whole orbits or without growth.
    """
    tm, em = orbit_means(t, e_kin)
    empty = dict(t=[], e_kin=[], anchor_t=math.nan, anchor_e=math.nan)
    if tm.size < 2 or not slope_per_orbit > 0:
        return empty
    early = tm <= tm[0] + 0.5 * (tm[-1] - tm[0])
    i0 = int(np.argmin(np.where(early, em, np.inf)))
    above = np.nonzero(em[i0:] >= factor * em[i0])[0]
    ia = i0 + int(above[0]) if above.size else tm.size - 1
    ta, ea = float(tm[ia]), float(em[ia])
    t_last = float(np.nanmax(np.asarray(t, float)))
    t_end = max(ta, min(t_last, ta + math.log(3.0 * em.max() / ea) / slope_per_orbit))
    t_start = max(float(tm[i0]), ta - math.log(ea / em[i0]) / slope_per_orbit)  # where it meets the minimum
    ts = np.array([t_start, t_end])
    es = ea * np.exp(slope_per_orbit * (ts - ta))
    return dict(t=ts.tolist(), e_kin=es.tolist(), anchor_t=ta, anchor_e=ea)


def measured_slope(t, e_kin, t0: float, t1: float) -> float:
    """Least-squares slope of ln e_kin per orbit of the orbit means (:func:`orbit_means`) in [t0, t1]."""
    tm, em = orbit_means(t, e_kin)
    sel = (tm >= t0) & (tm <= t1)
    if sel.sum() < 3:
        return math.nan
    return float(np.polyfit(tm[sel], np.log(em[sel]), 1)[0])


def allowed_wavelengths(L_x_m: float, lambda_p_m: float, each_side: int = 3, span=(),
                        max_marks: int = 30) -> list[tuple[int, float]]:
    """The wavelengths L_x/n [m] a periodic box holds next to ``lambda_p_m``: (n, L_x/n), longest first.

    The ``each_side`` values of n below and above the n nearest to L_x/lambda_p (n >= 1), widened to
    cover the wavelengths in ``span`` (e.g. the lambda_p values the run has had), at most ``max_marks``
    values of n, those nearest to lambda_p's.
    """
    if not (math.isfinite(lambda_p_m) and lambda_p_m > 0 and L_x_m > 0):
        return []
    n0 = max(1, int(round(L_x_m / lambda_p_m)))
    lo, hi = max(1, n0 - each_side), n0 + each_side
    span = np.asarray(span, float)
    span = span[np.isfinite(span) & (span > 0)]
    if span.size:
        lo = max(1, min(lo, int(round(L_x_m / span.max()))))
        hi = max(hi, int(round(L_x_m / span.min())))
    ns = sorted(range(lo, hi + 1), key=lambda n: (abs(n - n0), n))[:max_marks]
    return [(n, L_x_m / n) for n in sorted(ns)]


def theory_mode(params, L_x_m: float, n_cells: int, initial: str = "noise", wavelength_m: float = math.nan) -> dict:
    """The mode whose linear growth e_kin(t) should follow: the seeded wavelength of a single-mode
    run (``initial == "mode"``), else :func:`fastest_allowed_mode` (white noise seeds every mode).
    Same keys as :func:`fastest_allowed_mode`."""
    if initial == "mode" and math.isfinite(wavelength_m) and wavelength_m > 0:
        g = float(linear.dispersion(params, np.array([wavelength_m])).growth_rate[0])
        return dict(wavelength_m=float(wavelength_m), n=int(round(L_x_m / wavelength_m)), growth_rate=g,
                    slope_per_orbit=4.0 * math.pi * g)
    return fastest_allowed_mode(params, float(L_x_m), int(n_cells))
