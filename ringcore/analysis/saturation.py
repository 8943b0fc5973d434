"""Saturation wavelength relations of Section 6."""
from __future__ import annotations

import numpy as np

from ..checks import check_real
from ..linear import lambda_zero
from ..params import RingParams

C_EMPIRICAL = 1.4  # Eq. (55)


def lambda_p_empirical(p: RingParams, C: float = C_EMPIRICAL) -> float:
    """lambda_p = C lambda_zero(sigma0) [m], Eq. (55); nan without self-gravity."""
    return _C(C) * lambda_zero(p)


def _C(C) -> float:
    """The factor C of Eq. (55), > 0 (the paper: 1.4)."""
    return check_real("C", C, 0.0, 100.0, lo_open=True, allow_str=False)


def _F2(p: RingParams, F2: float | None) -> float:
    if F2 is not None:
        return check_real("F2", F2, -100.0, 100.0, allow_str=False)
    return 0.0 if p.isothermal else p.F2


def lambda_zero_approx(p: RingParams, F2: float | None = None) -> float:
    """lambda_zero ~ 2 (p_s + F2) lambda_J [m]: Eq. (22) for Q0 >> 1.

    The zero of the group velocity d omega_I/dk of the k^2 approximation Eq. (22),
    omega_I = 1 - k/Q0 + (p_s + F2 - 1/Q0^2) k^2 / 2, is k = 1/(Q0 (p_s + F2) - 1/Q0) in the
    paper's units (length c0/Omega), i.e. lambda_zero -> 2 (p_s + F2) lambda_J with
    lambda_J = c0^2/(G sigma0) (Eq. (57)) for Q0 >> 1.  Agrees with the exact lambda_zero of
    Eq. (16) (:func:`ringcore.linear.lambda_zero`) within 0.1 % for the non-isothermal sets at
    Q0 >= 20 with the tabulated F2 (tau20: 0.4 %, its tabulated F2 = 0.08 against the exact 0.09);
    the isothermal sets (F2 = 0) within 1 % at Q0 >= 32.

    Parameters
    ----------
    p : RingParams
        Parameter set with sigma0 > 0 (lambda_J is inf without self-gravity).
    F2 : float, optional
        Thermal correction of Eq. (22); default the tabulated value (0 if isothermal).

    Returns
    -------
    float
        Wavelength [m].
    """
    return 2.0 * (p.p_s + _F2(p, F2)) * p.lambda_J


def lambda_p_approx(p: RingParams, C: float = C_EMPIRICAL, F2: float | None = None) -> float:
    """lambda_p ~ 2 C (p_s + F2) lambda_J [m]: Eq. (56) with the sign of Eq. (22).

    The paper prints Eq. (56) as 2 C (p_s - F2) lambda_J, but it says the relation
    "follows directly from Eq. (22) for Q0 >> 1", and Eq. (22) gives
    lambda_zero ~ 2 (p_s + F2) lambda_J (:func:`lambda_zero_approx`).  The "+" form is the one
    that agrees with C times the exact lambda_zero (tau15, Q0 = 32: exact lambda_zero 1,892 m,
    "+" 1,892 m, printed "-" 2,387 m, +26 %).  For the isothermal model F2 = 0 and both agree.

    Parameters
    ----------
    p : RingParams
        Parameter set with sigma0 > 0.
    C : float
        Factor of Eq. (55) (1.4).
    F2 : float, optional
        Thermal correction of Eq. (22); default the tabulated value (0 if isothermal).

    Returns
    -------
    float
        Wavelength [m].
    """
    return _C(C) * lambda_zero_approx(p, F2)


def lagrange_derivative(x, y) -> np.ndarray:
    """dy/dx by 3-point Lagrangian differentiation on a non-uniform grid.

    Interior points use the three-point Lagrange polynomial through (i-1, i, i+1); the end
    points use the same polynomial through the first / last three points
    (Appendix C).
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
