"""Conservative <-> primitive variables: the one place the temperature formula is written.

``e = sigma (u^2/2 + 3T/2)`` (Eq. (25)), hence ``T = (2/3) (e/sigma - u^2/2)``.
:func:`temperature` takes the specific energy ``e/sigma`` so callers keep their own
(fast) way of dividing by sigma; :func:`temperature_nb` is the same function compiled
for inlining into the kernels of :mod:`ringcore.hydro.kernels`, :func:`cons_to_prim` the
numpy version for whole states.

References: Eqs. (24), (25).
"""
from __future__ import annotations

import numpy as np
from numba import njit


def temperature(eps, u):
    """T [c0^2] from the specific energy ``eps = e/sigma`` [c0^2] and u [c0], Eq. (25)."""
    return (2.0 / 3.0) * (eps - 0.5 * u * u)


temperature_nb = njit(cache=True, error_model="numpy", inline="always")(temperature)


def cons_to_prim(U, T0: float = 1.0):
    """(sigma, u, v, T) from conservative variables ``U`` of shape (nv, ...), nv = 3 or 4.

    Dimensionless (sigma0, c0, c0^2 scalings).  With nv = 3 (isothermal) T is ``T0`` everywhere.
    Division by zero gives inf/nan (no warning), as the blow-up diagnostics need.
    """
    U = np.asarray(U, float)
    s = U[0]
    with np.errstate(all="ignore"):
        u, v = U[1] / s, U[2] / s
        T = temperature(U[3] / s, u) if U.shape[0] == 4 else np.full_like(s, T0)
    return s.copy(), u, v, T
