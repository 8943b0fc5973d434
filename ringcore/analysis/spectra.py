"""Fourier amplitudes (eq. fourier), power spectral density and prevalent wavelength lambda_p."""
from __future__ import annotations

import numpy as np

from ..checks import check_real


def fourier_amplitudes(field, axis: int = -1) -> np.ndarray:
    """Real amplitudes U^m of eq. (fourier), m = 0 .. n/2, along ``axis`` (periodic samples).

    ``field = sum_m U^m cos(k_m x + phi_m)``: U^0 is the mean, U^m = 2|F_m|/n for 0 < m < n/2.
    """
    f = np.asarray(field, float)
    n = f.shape[axis]
    F = np.abs(np.fft.rfft(f, axis=axis)) / n
    sl = [slice(None)] * F.ndim
    sl[axis] = slice(1, None if n % 2 else -1)
    F[tuple(sl)] *= 2.0
    return F


def power_spectrum(field, L_x: float):
    """One-sided PSD of a periodic profile.

    Parameters
    ----------
    field : array_like, shape (..., n)
        Samples on a uniform periodic grid (e.g. sigma/sigma0).
    L_x : float
        Domain size [m].

    Returns
    -------
    wavelength_m : ndarray, shape (n//2,)
        L_x/m for m = 1 .. n//2.
    power : ndarray, shape (..., n//2)
        Squared Fourier amplitudes (U^m)^2 of the mean-free field.
    """
    L_x = check_real("L_x", L_x, 0.0, np.inf, lo_open=True, unit="m", allow_str=False)
    A = fourier_amplitudes(field)
    m = np.arange(1, A.shape[-1])
    return L_x / m, A[..., 1:] ** 2


def prevalent_wavelength(field, L_x: float) -> float:
    """lambda_p [m]: wavelength of the largest Fourier amplitude of a periodic profile."""
    lam, P = power_spectrum(field, L_x)
    if P.ndim != 1:
        raise ValueError("prevalent_wavelength takes one profile (1-d array)")
    return float(lam[int(np.argmax(P))])
