"""Fourier amplitudes (Eq. (38)), the power spectral density (PSD) of a profile and its prevalent wavelength.

The one spectral convention of ringcore (hydro engine, N-body box, run files, command line, recipes and app):

- a profile ``f`` of ``n`` samples on a uniform periodic grid of length ``L_x`` [m] has modes
  m = 1 .. n//2 of wavelength ``L_x / m`` [m] (the mean, m = 0, is left out);
- the amplitude of mode m is U^m in ``f = sum_m U^m cos(k_m x + phi_m)``, Eq. (38): U^m = 2 |F_m| / n
  for 0 < m < n/2 and, for even n, U^m = |F_m| / n for the Nyquist mode m = n/2 (the amplitude of the
  cosine the nodes sample; it has no sine partner, so it is not doubled);
- the power of mode m is its share of the variance of the profile (one-sided, Parseval: the powers sum to
  the variance of the mean-free profile): (U^m)^2 / 2 for 0 < m < n/2 and (U^m)^2 for the Nyquist mode,
  as :func:`scipy.signal.periodogram` with ``scaling="spectrum"``;
- the PSD is that power, or (``normalise=True``) that power divided by its maximum;
- lambda_p is the wavelength of the largest power; equal maxima (e.g. a flat profile) give the longest of
  their wavelengths (the lowest m).

Units: wavelengths in m; power in the squared unit of the profile (sigma/sigma0 profiles: dimensionless).
"""
from __future__ import annotations

import numpy as np

from ..checks import check_int, check_real


def _max_wavelength(value):
    """None (keep every wavelength) for None or +inf, else the checked value [m] (> 0)."""
    if value is None or (isinstance(value, (int, float, np.floating)) and value == np.inf):
        return None
    return check_real("max_wavelength", value, 0.0, np.inf, lo_open=True, unit="m", allow_str=False)


def fourier_amplitudes(field, axis: int = -1) -> np.ndarray:
    """Real amplitudes U^m of Eq. (38), m = 0 .. n//2, along ``axis`` (periodic samples).

    Parameters
    ----------
    field : array_like
        Samples on a uniform periodic grid (any unit).
    axis : int
        Axis of the grid.

    Returns
    -------
    numpy.ndarray
        U^0 (the mean), then U^m = 2|F_m|/n for 0 < m < n/2 and, for even n, U^(n/2) = |F_(n/2)|/n
        (the Nyquist mode, not doubled), in the unit of ``field``.
    """
    f = np.asarray(field, float)
    n = f.shape[axis]
    F = np.abs(np.fft.rfft(f, axis=axis)) / n
    sl = [slice(None)] * F.ndim
    sl[axis] = slice(1, None if n % 2 else -1)
    F[tuple(sl)] *= 2.0
    return F


def power_spectrum(field, L_x: float, *, normalise: bool = False, max_wavelength: float | None = None):
    """One-sided PSD of periodic profiles (the module's convention, Nyquist mode included once).

    Parameters
    ----------
    field : array_like, shape (..., n)
        Samples on a uniform periodic grid (e.g. sigma/sigma0); several profiles along the leading axes.
    L_x : float
        Domain size [m], > 0.
    normalise : bool
        Divide each profile's power by its maximum (a flat profile keeps its zeros).
    max_wavelength : float, optional
        Keep only wavelengths <= ``max_wavelength`` [m] (e.g. L_x/4 to leave out a buffer zone's box-scale
        contrast; None or inf: all); the normalisation then uses the kept modes.

    Returns
    -------
    wavelength_m : numpy.ndarray, shape (k,)
        L_x/m [m] for the kept modes m = 1 .. n//2.
    power : numpy.ndarray, shape (..., k)
        Variance per mode, (U^m)^2 / 2 (the Nyquist mode: (U^m)^2) [unit of ``field`` squared], or that
        divided by its maximum.
    """
    L_x = check_real("L_x", L_x, 0.0, np.inf, lo_open=True, unit="m", allow_str=False)
    f = np.asarray(field, float)
    A = fourier_amplitudes(f)
    m = np.arange(1, A.shape[-1])
    P = 0.5 * A[..., 1:] ** 2
    if f.shape[-1] % 2 == 0 and P.shape[-1]:
        P[..., -1] *= 2.0  # the Nyquist mode: all of its variance is in the cosine
    lam = L_x / m
    max_wavelength = _max_wavelength(max_wavelength)
    if max_wavelength is not None:
        keep = lam <= max_wavelength
        lam, P = lam[keep], P[..., keep]
    if normalise and P.shape[-1]:
        top = P.max(axis=-1, keepdims=True)
        P = np.divide(P, top, out=np.zeros_like(P), where=top > 0)
    return lam, P


def prevalent_mode(field, *, max_mode: int | None = None):
    """The mode number m (1 .. n//2) of the largest PSD power of a periodic profile (or of each profile).

    Parameters
    ----------
    field : array_like, shape (n,) or (..., n)
        Samples on a uniform periodic grid, n >= 2.
    max_mode : int, optional
        Consider only modes m <= ``max_mode`` (default all).

    Returns
    -------
    int or numpy.ndarray
        m (dimensionless; wavelength L_x/m); equal maxima give the lowest m.
    """
    f = np.asarray(field, float)
    if f.ndim < 1 or f.shape[-1] < 2:
        raise ValueError(f"field of shape {f.shape} is not valid: allowed at least 2 samples along the last axis")
    _, P = power_spectrum(f, 1.0)
    if max_mode is not None:
        P = P[..., :check_int("max_mode", max_mode, 1, 2**62)]
    j = np.argmax(P, axis=-1) + 1
    return int(j) if P.ndim == 1 else j


def prevalent_wavelength(field, L_x: float, *, max_wavelength: float | None = None):
    """lambda_p [m]: the wavelength of the largest PSD power of a periodic profile (or of each profile).

    Parameters
    ----------
    field : array_like, shape (n,) or (..., n)
        Samples on a uniform periodic grid (e.g. sigma/sigma0).
    L_x : float
        Domain size [m], > 0.
    max_wavelength : float, optional
        Consider only wavelengths <= ``max_wavelength`` [m].

    Returns
    -------
    float or numpy.ndarray
        lambda_p [m] (a float for one profile, an array over the leading axes otherwise); equal maxima give
        the longest of their wavelengths; nan when no mode is kept.
    """
    L_x = check_real("L_x", L_x, 0.0, np.inf, lo_open=True, unit="m", allow_str=False)
    f = np.asarray(field, float)
    max_wavelength = _max_wavelength(max_wavelength)
    if f.ndim == 1 and f.shape[0] >= 2 and max_wavelength is None:
        return _prevalent_wavelength_1d(f, L_x)
    lam = L_x / np.arange(1, f.shape[-1] // 2 + 1) if f.ndim else np.zeros(0)
    kept = lam <= max_wavelength if max_wavelength is not None else np.ones(lam.size, bool)
    if not kept.any():
        return np.nan if f.ndim <= 1 else np.full(f.shape[:-1], np.nan)
    m_lo = int(np.argmax(kept)) + 1  # the longest kept wavelength's mode (kept modes are m >= m_lo)
    _, P = power_spectrum(f, L_x)
    j = np.argmax(P[..., m_lo - 1:], axis=-1) + m_lo
    return L_x / int(j) if P.ndim == 1 else L_x / j


def _prevalent_wavelength_1d(f: np.ndarray, L_x: float) -> float:
    """:func:`prevalent_wavelength` of one float64 profile ``f`` (n >= 2) over all modes, without the
    argument checks (the hydro recorder's sample, 20 per orbit): the same arithmetic, the same value."""
    n = f.shape[0]
    A = np.abs(np.fft.rfft(f)) / n
    A[1:None if n % 2 else -1] *= 2.0
    P = 0.5 * A[1:] ** 2
    if n % 2 == 0:
        P[-1] *= 2.0
    return L_x / int(np.argmax(P) + 1)
