"""Compiled kernels on the conservative state alone (no right-hand side): periodic ghost nodes, the
check for a bad node, the optional temperature floor, primitive -> conservative.  Layout as in
:mod:`ringcore.hydro.layout` (:mod:`ringcore.hydro.kernels` re-exports these kernels).

References: Eqs. (24), (25).
"""
from __future__ import annotations

import math

from numba import njit

from .convert import temperature_nb
from .layout import NG


@njit(nogil=True, cache=True, error_model="numpy")
def fill_ghosts(U, n):
    """Periodic ghost nodes: U[:, :NG] <- last NG interior nodes, U[:, NG+n:] <- first NG."""
    for k in range(U.shape[0]):
        for g in range(NG):
            U[k, g] = U[k, n + g]
            U[k, NG + n + g] = U[k, NG + g]


@njit(nogil=True, cache=True, error_model="numpy")
def check_state(U):
    """First bad interior node: returns (field, index) or (-1, -1) if all is well.

    field 0: sigma not finite or <= 0; 1: u not finite; 2: v not finite; 3: T not finite
    or <= 0 (non-isothermal only).  No fast-math here, so NaN tests are honoured.
    """
    nv, N = U.shape
    n = N - 2 * NG
    s_, mx_, my_ = U[0][NG:NG + n], U[1][NG:NG + n], U[2][NG:NG + n]
    e_ = U[nv - 1][NG:NG + n]
    bad = 0
    for i in range(n):  # branch-free count first (vectorizes); the scan below only after a failure
        s = s_[i]
        u = mx_[i] / s
        good = s > 0.0 and math.isfinite(s) and math.isfinite(u) and math.isfinite(my_[i] / s)
        if nv == 4:
            T = temperature_nb(e_[i] / s, u)
            good = good and T > 0.0 and math.isfinite(T)
        bad += 0 if good else 1
    if bad == 0:
        return -1, -1
    for i in range(NG, NG + n):
        s = U[0, i]
        if not (s > 0.0) or not math.isfinite(s):
            return 0, i - NG
        u = U[1, i] / s
        if not math.isfinite(u):
            return 1, i - NG
        if not math.isfinite(U[2, i] / s):
            return 2, i - NG
        if nv == 4:
            T = temperature_nb(U[3, i] / s, u)
            if not (T > 0.0) or not math.isfinite(T):
                return 3, i - NG
    return -1, -1


@njit(nogil=True, cache=True, error_model="numpy")
def apply_temperature_floor(U, T_min):
    """Raise T to ``T_min`` where it is lower (adds internal energy to e); returns the node count (per RK stage).

    Optional (``HydroOptions.T_floor``, off by default), a departure from the paper: in the
    non-isothermal model the cooling Gamma ~ T^G_T with G_T < 1 drives T to zero in finite
    time wherever the local shear heating vanishes, which an explicit scheme overshoots.
    """
    nv, N = U.shape
    n = N - 2 * NG
    hits = 0
    s_, mx_, e_ = U[0][NG:NG + n], U[1][NG:NG + n], U[3][NG:NG + n]
    for i in range(n):  # branch-free (vectorizes)
        s = s_[i]
        m = mx_[i]
        T = temperature_nb(e_[i] / s, m / s)
        low = T < T_min
        e_[i] = 0.5 * m * m / s + 1.5 * s * T_min if low else e_[i]
        hits += 1 if low else 0
    return hits


@njit(nogil=True, cache=True, error_model="numpy")
def to_conservative(sigma, u, v, T, out):
    """Fill interior nodes of ``out`` (nv, N) from primitive arrays of length n."""
    n = sigma.shape[0]
    nv = out.shape[0]
    for j in range(n):
        i = j + NG
        out[0, i] = sigma[j]
        out[1, i] = sigma[j] * u[j]
        out[2, i] = sigma[j] * v[j]
        if nv == 4:
            out[3, i] = sigma[j] * (0.5 * u[j] * u[j] + 1.5 * T[j])
    fill_ghosts(out, n)


@njit(nogil=True, cache=True, error_model="numpy")
def sample_fields(s_, mx_, my_, e_, T0, prim, w):
    """The primitive fields and the kinetic energy density at the interior nodes, in one pass (a sample of
    the recorder).

    ``s_``, ``mx_``, ``my_``, ``e_`` are the rows sigma, sigma u, sigma v and e of the interior state
    (``e_`` is ignored if ``T0 > 0``: isothermal, T = T0).  ``prim`` (4, n) receives sigma, u, v, T as
    :func:`ringcore.hydro.convert.cons_to_prim` computes them (the same operations), ``w`` (n,) the kinetic
    energy density ``0.5 sigma (u^2 + v^2)`` whose mean is :func:`ringcore.hydro.diagnostics.e_kin_dimless`.
    """
    n = s_.shape[0]
    p0, p1, p2, p3 = prim[0], prim[1], prim[2], prim[3]
    iso = T0 > 0.0
    for i in range(n):
        s = s_[i]
        u = mx_[i] / s
        v = my_[i] / s
        p0[i] = s
        p1[i] = u
        p2[i] = v
        p3[i] = T0 if iso else temperature_nb(e_[i] / s, u)
        w[i] = 0.5 * s * (u * u + v * v)
