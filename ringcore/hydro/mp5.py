"""MP5 reconstruction (Suresh & Huynh 1997) of the split fluxes: the numerical flux of Eq. (28).

:func:`mp5` is the scalar reconstruction at the right interface of a node from its five-point
stencil.  :func:`numerical_flux` applies it to F+ and (mirrored) F- at every interface of the grid,
the whole limiter evaluated everywhere in vectorized loops, the curvatures
d_j = f_{j-1} - 2 f_j + f_{j+1} and their limited averages
``dm4_{j+1/2} = minmod4(4 d_j - d_{j+1}, 4 d_{j+1} - d_j, d_j, d_{j+1})`` computed once per node and
shared by neighbouring interfaces.  Every value is computed with the operations of :func:`mp5` in the
same order (the curvature of the mirrored F- stencil keeps its own summation order; minmod4 of the four
arguments does not depend on their order), so both agree bit for bit (``tests/core/test_hydro_mp5.py``).

The minmod functions are written with min, max and a select instead of the textbook
``(sign(a) + sign(b))/2 min(|a|, |b|)``: when all arguments are positive the smallest of them is the one of
smallest magnitude, when all are negative the largest is, otherwise the result is zero -- the same value for
every finite argument, compared bit for bit with the sign form in the tests.  In the limiter the second
minmod has ordered arguments (fmin <= f0 <= fmax), so it needs one comparison each way.  With these the whole
limiter, evaluated at every interface, costs about 0.85 of the textbook form evaluated only where the
accuracy-preserving check fails (the earlier kernel).

References: Eqs. (31), (28).
"""
from __future__ import annotations

from numba import njit

MP5_ALPHA = 4.0  # Suresh & Huynh (1997)
MP5_EPS = 1e-10  # their accuracy-preserving switch

_FM = {"nsz"}  # see ringcore.hydro.kernels: no reassociation, so cached and fresh code agree bit for bit


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _minmod(a, b):
    """minmod(a, b) = (sign(a) + sign(b))/2 min(|a|, |b|) for finite a, b."""
    lo = min(a, b)  # both positive: the smaller is the one of smaller magnitude; both negative: the larger
    hi = max(a, b)
    return lo if lo > 0.0 else (hi if hi < 0.0 else 0.0)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _minmod4(w, x, y, z):
    """minmod of four finite numbers: the smallest magnitude with the common sign, 0 unless all four share it."""
    lo = min(min(w, x), min(y, z))
    hi = max(max(w, x), max(y, z))
    return lo if lo > 0.0 else (hi if hi < 0.0 else 0.0)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _limit(forig, fm1, f0, fp1, dm4m, dm4p):
    """MP5 value from the linear value ``forig``, the centre values and the limited curvatures."""
    fmp = f0 + _minmod(fp1 - f0, MP5_ALPHA * (f0 - fm1))
    ful = f0 + MP5_ALPHA * (f0 - fm1)
    fav = 0.5 * (f0 + fp1)
    fmd = fav - 0.5 * dm4p
    flc = f0 + 0.5 * (f0 - fm1) + (4.0 / 3.0) * dm4m
    fmin = max(min(min(f0, fp1), fmd), min(min(f0, ful), flc))
    fmax = min(max(max(f0, fp1), fmd), max(max(f0, ful), flc))
    # minmod(lo, hi) with lo <= hi (fmin <= f0 <= fmax, and rounding keeps the order): lo, hi or zero
    lo = fmin - forig
    hi = fmax - forig
    flim = forig + (lo if lo > 0.0 else (hi if hi < 0.0 else 0.0))
    return forig if (forig - f0) * (forig - fmp) <= MP5_EPS else flim


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def mp5(fm2, fm1, f0, fp1, fp2):
    """MP5 value at the right interface x_{j+1/2} of node j from f_{j-2} .. f_{j+2}.

    Fifth-order upwind-biased interpolation of the flux primitive (Eq. (31), r = 3)
    with the monotonicity-preserving bounds of Suresh & Huynh (1997), alpha = 4.
    Written branch-free so that loops over nodes vectorize.
    """
    forig = (2.0 * fm2 - 13.0 * fm1 + 47.0 * f0 + 27.0 * fp1 - 3.0 * fp2) * (1.0 / 60.0)
    dm = fm2 - 2.0 * fm1 + f0
    d0 = fm1 - 2.0 * f0 + fp1
    dp = f0 - 2.0 * fp1 + fp2
    dm4p = _minmod4(4.0 * d0 - dp, 4.0 * dp - d0, d0, dp)
    dm4m = _minmod4(4.0 * d0 - dm, 4.0 * dm - d0, d0, dm)
    return _limit(forig, fm1, f0, fp1, dm4m, dm4p)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _curvatures(f, d, q, mirrored):
    """d_j (nodes 1 .. N-2) and dm4_{j+1/2} = q_j (nodes 1 .. N-3) of the row ``f``.

    ``mirrored``: d_j summed as f_{j+1} - 2 f_j + f_{j-1}, the order :func:`mp5` uses on the
    reversed stencil of F-.
    """
    N = f.shape[0]
    fl, fc, fr = f[:N - 2], f[1:N - 1], f[2:]
    dc = d[1:N - 1]
    if mirrored:
        for i in range(N - 2):
            dc[i] = fr[i] - 2.0 * fc[i] + fl[i]
    else:
        for i in range(N - 2):
            dc[i] = fl[i] - 2.0 * fc[i] + fr[i]
    a, b, qc = d[1:N - 2], d[2:N - 1], q[1:N - 2]
    for i in range(N - 3):
        qc[i] = _minmod4(4.0 * a[i] - b[i], 4.0 * b[i] - a[i], a[i], b[i])


NSCRATCH = 4  # rows of scratch :func:`numerical_flux` needs


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def numerical_flux(fp, fm, out, S, lo, m):
    """``out[c] = MP5(F+ from c-2..c+2) + MP5(F- from c+3..c-1)`` for c = lo .. lo+m-1.

    Parameters
    ----------
    fp, fm : (N,) float64
        F+ and F- of one conservative variable at every node (ghosts filled).
    out : (N,) float64
        Numerical flux f_{c+1/2}, stored at index c.
    S : (NSCRATCH, N) float64
        Scratch rows (curvatures and their limited averages of F+ and F-).
    lo, m : int
        First interface and number of interfaces (needs 3 <= lo and lo + m + 3 <= N).
    """
    dp, qp, dm, qm = S[0], S[1], S[2], S[3]
    _curvatures(fp, dp, qp, False)
    _curvatures(fm, dm, qm, True)
    o = out[lo:]
    a0, a1, a2, a3, a4 = fp[lo - 2:], fp[lo - 1:], fp[lo:], fp[lo + 1:], fp[lo + 2:]
    b0, b1, b2, b3, b4 = fm[lo - 1:], fm[lo:], fm[lo + 1:], fm[lo + 2:], fm[lo + 3:]
    qa_m, qa_p = qp[lo - 1:], qp[lo:]  # F+ at c: dm4m = Q(d_c, d_{c-1}) = q_{c-1}, dm4p = q_c
    qb_p, qb_m = qm[lo:], qm[lo + 1:]  # F- at c (centre c+1): dm4p = Q(d_{c+1}, d_c) = q_c, dm4m = q_{c+1}
    for i in range(m):
        fa = (2.0 * a0[i] - 13.0 * a1[i] + 47.0 * a2[i] + 27.0 * a3[i] - 3.0 * a4[i]) * (1.0 / 60.0)
        fb = (2.0 * b4[i] - 13.0 * b3[i] + 47.0 * b2[i] + 27.0 * b1[i] - 3.0 * b0[i]) * (1.0 / 60.0)
        o[i] = (_limit(fa, a1[i], a2[i], a3[i], qa_m[i], qa_p[i])
                + _limit(fb, b3[i], b2[i], b1[i], qb_m[i], qb_p[i]))
