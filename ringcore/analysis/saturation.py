"""Saturation wavelength relations of Section "Saturation Wavelength of Viscous Overstability"."""
from __future__ import annotations

import numpy as np

from ..params import RingParams

C_EMPIRICAL = 1.4  # eq. (lambdasigma)


def lambda_p_empirical(p: RingParams, C: float = C_EMPIRICAL) -> float:
    """lambda_p = C lambda_zero(sigma0) [m], eq. (lambdasigma); nan without self-gravity."""
    from ..linear import lambda_zero

    return C * lambda_zero(p)


def lambda_p_approx(p: RingParams, C: float = C_EMPIRICAL, F2: float | None = None) -> float:
    """lambda_p ~ 2 C (p_s - F2) lambda_J [m], eq. (lambdasigmaap) (F2 = 0 for isothermal)."""
    if F2 is None:
        F2 = 0.0 if p.isothermal else p.F2
    return 2.0 * C * (p.p_s - F2) * p.lambda_J


def lagrange_derivative(x, y) -> np.ndarray:
    """dy/dx by 3-point Lagrangian differentiation on a non-uniform grid.

    Interior points use the three-point Lagrange polynomial through (i-1, i, i+1); the end
    points use the same polynomial through the first / last three points
    (Appendix "Group Velocities of Saturated Wave Trains").
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    if x.size < 3 or x.shape != y.shape:
        raise ValueError("lagrange_derivative needs x and y of equal length >= 3")
    d = np.empty_like(y)

    def deriv(x0, x1, x2, y0, y1, y2, at):
        return (y0 * (2 * at - x1 - x2) / ((x0 - x1) * (x0 - x2))
                + y1 * (2 * at - x0 - x2) / ((x1 - x0) * (x1 - x2))
                + y2 * (2 * at - x0 - x1) / ((x2 - x0) * (x2 - x1)))

    d[1:-1] = deriv(x[:-2], x[1:-1], x[2:], y[:-2], y[1:-1], y[2:], x[1:-1])
    d[0] = deriv(x[0], x[1], x[2], y[0], y[1], y[2], x[0])
    d[-1] = deriv(x[-3], x[-2], x[-1], y[-3], y[-2], y[-1], x[-1])
    return d
