"""Growth rates and oscillation frequencies of modes with stated uncertainties.

References: Section 4.1.3 (linear fit to log Fourier amplitude; Lomb periodogram of u at a point) and
Section 4.2.2 (the N-body box's complex mode amplitude).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..checks import check_real

# scipy.signal, scipy.stats and scipy.optimize are imported in the functions that use them: together they are
# ~1.5 s of import, paid by every process that imports the hydro engine (its diagnostics import this module)
# although only the analyses call them.


@dataclass(frozen=True)
class Fit:
    """A measured value with its 1-sigma uncertainty, in the units of the input time axis."""

    value: float
    stderr: float

    def __iter__(self):
        yield self.value
        yield self.stderr


def _window(t, y, window):
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if t.shape != y.shape or t.ndim != 1:
        raise ValueError(f"t and the signal must be 1-d arrays of equal length, got {t.shape} and {y.shape}")
    if window is not None:
        if isinstance(window, (str, bytes)) or not hasattr(window, "__len__") or len(window) != 2:
            raise ValueError(f"window = {window!r} is not valid: give (t_start, t_end) in the units of t")
        lo = check_real("window start", window[0], allow_str=False)
        hi = check_real("window end", window[1], lo, allow_str=False)
        sel = (t >= lo) & (t <= hi)
        t, y = t[sel], y[sel]
    if t.size < 4:
        raise ValueError(f"window = {window!r} holds {t.size} samples: at least 4 are needed")
    return t, y


def growth_rate(t, amplitude, window=None) -> Fit:
    """Growth rate d ln(A)/dt from a least-squares line through log(amplitude).

    Parameters
    ----------
    t : array_like
        Times (any unit; the rate comes out in 1/that unit).
    amplitude : array_like
        Positive mode amplitudes (e.g. a Fourier amplitude of sigma).
    window : (float, float), optional
        Time interval used for the fit.

    Returns
    -------
    Fit
        Slope and its standard error (scipy.stats.linregress).
    """
    t, a = _window(t, amplitude, window)
    if np.any(~np.isfinite(a)) or np.any(a <= 0):
        raise ValueError("amplitude must be finite and > 0 inside the window")
    from scipy import stats  # deferred: see the module's imports

    r = stats.linregress(t, np.log(a))
    return Fit(float(r.slope), float(r.stderr))


def lomb_frequency(t, y, fmin: float, fmax: float, n: int = 20000) -> Fit:
    """Dominant angular frequency of ``y(t)`` from the normalized Lomb periodogram
    (:func:`ringcore.analysis.lomb.lomb_periodogram`, the estimator of :func:`scipy.signal.lombscargle`).

    Parameters
    ----------
    t, y : array_like
        Sample times (need not be uniform) and signal; the mean is removed.
    fmin, fmax : float
        Angular-frequency search range (rad per unit of t), 0 < fmin < fmax.
    n : int
        Number of trial frequencies (3 to 10^8).

    Returns
    -------
    Fit
        Peak angular frequency (refined by a parabola through the three highest points)
        and an uncertainty: the half width at half maximum of the peak divided by
        sqrt(number of samples) (a conservative resolution-based estimate).
    """
    t, y = _window(t, y, None)
    from .lomb import lomb_periodogram  # deferred: numba, which the lighter analyses never need

    w, P = lomb_periodogram(t, y, fmin, fmax, n)  # checks fmin, fmax and n
    i = int(np.argmax(P))
    wi = w[i]
    if 0 < i < w.size - 1:
        y0, y1, y2 = P[i - 1], P[i], P[i + 1]
        den = y0 - 2 * y1 + y2
        if den != 0:
            wi = w[i] + 0.5 * (y0 - y2) / den * (w[1] - w[0])
    half = P[i] / 2
    lo = i
    while lo > 0 and P[lo] > half:
        lo -= 1
    hi = i
    while hi < w.size - 1 and P[hi] > half:
        hi += 1
    hwhm = 0.5 * (w[hi] - w[lo])
    return Fit(float(wi), float(hwhm / np.sqrt(t.size)))


def _rotating_mode(t, g, w, a, b, c, d):
    """Re U, Im U (concatenated) of exp(g t) (A cos w t + B sin w t) at the times ``t`` (given twice)."""
    n = t.size // 2
    tt = t[:n]
    e = np.exp(g * tt)
    re = e * (a * np.cos(w * tt) + b * np.sin(w * tt))
    im = e * (c * np.cos(w * tt) + d * np.sin(w * tt))
    return np.concatenate([re, im])


def complex_mode_fit(t, U, w_lo: float = 0.7, w_hi: float = 1.5) -> tuple:
    """Growth rate and frequency of a growing, rotating complex mode amplitude ``U(t)``.

    The frequency is first taken from the sum of the normalised Lomb periodograms of Re U and Im U
    (after removing the log-linear envelope), then growth rate and frequency are refined by a least-squares
    fit of Re U, Im U = exp(omega_R t) (A cos omega_I t + B sin omega_I t) (``scipy.optimize.curve_fit``).

    Parameters
    ----------
    t : array_like
        Sample times [1/Omega] (need not be uniform).
    U : array_like of complex
        The mode's complex amplitude at ``t`` (any unit).
    w_lo, w_hi : float
        Angular-frequency search range of the periodogram [Omega].

    Returns
    -------
    tuple
        (omega_R, omega_I, omega_I from the periodogram, 1-sigma error of omega_R, of omega_I), all in Omega.
    """
    from scipy import signal  # deferred: see the module's imports
    from scipy.optimize import curve_fit

    t = np.asarray(t, float)
    U = np.asarray(U, complex)
    t0 = t - t[0]
    w = np.linspace(w_lo, w_hi, 2000)
    env = np.polyfit(t0, np.log(np.abs(U) + 1e-300), 1)[0]
    damp = np.exp(-env * t0)
    p = signal.lombscargle(t0, (U.real * damp) - np.mean(U.real * damp), w, normalize=True) + signal.lombscargle(
        t0, (U.imag * damp) - np.mean(U.imag * damp), w, normalize=True)
    w_lomb = float(w[np.argmax(p)])
    tt = np.concatenate([t0, t0])
    y = np.concatenate([U.real, U.imag])
    a0 = np.abs(U[0])
    popt, pcov = curve_fit(_rotating_mode, tt, y, p0=[env, w_lomb, U[0].real, 0.0, U[0].imag, 0.0 * a0],
                           maxfev=20000)
    err = np.sqrt(np.diag(pcov))
    return float(popt[0]), abs(float(popt[1])), w_lomb, float(err[0]), float(err[1])
