"""MP5 reconstruction (Suresh & Huynh 1997) of the split fluxes: the numerical flux of eq. (defnumflux).

:func:`mp5` is the scalar reconstruction at the right interface of a node from its five-point
stencil.  :func:`numerical_flux` applies it to F+ and (mirrored) F- at every interface of the grid.
MP5 keeps the fifth-order linear value unless its accuracy-preserving check fails; only then are the
curvatures d_j = f_{j-1} - 2 f_j + f_{j+1}, their limited averages
``dm4_{j+1/2} = minmod4(4 d_j - d_{j+1}, 4 d_{j+1} - d_j, d_j, d_{j+1})`` and the bounds needed.  In the
app's default box the check fails at 10-16 % of the reconstructions (near extrema of the noise and the
waves), so :func:`numerical_flux` evaluates the check everywhere (vectorized) and the limiter only
where it failed, gathered into contiguous rows so that this part vectorizes too.  Every value is
computed with the same operations in the same order as in :func:`numerical_flux_full`, which
evaluates the whole limiter at every interface (the curvatures shared between neighbouring
interfaces), and as in :func:`mp5` (the curvature of the mirrored F- stencil keeps its own summation
order; minmod4 of the four arguments does not depend on their order), so all three agree bit for bit
(``tests/core/test_hydro_fastpath.py``, ``tests/core/test_hydro_mp5_lazy.py``).

References: eqs. (halfnodes), (defnumflux).
"""
from __future__ import annotations

import numpy as np
from numba import njit

MP5_ALPHA = 4.0  # Suresh & Huynh (1997)
MP5_EPS = 1e-10  # their accuracy-preserving switch

_FM = {"nsz"}  # see ringcore.hydro.kernels: no reassociation, so cached and fresh code agree bit for bit


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _minmod(a, b):
    return 0.5 * (np.sign(a) + np.sign(b)) * min(abs(a), abs(b))


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _minmod4(w, x, y, z):
    sw = np.sign(w)
    return 0.125 * (sw + np.sign(x)) * abs((sw + np.sign(y)) * (sw + np.sign(z))) * min(
        min(abs(w), abs(x)), min(abs(y), abs(z)))


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
    flim = forig + _minmod(fmin - forig, fmax - forig)
    return forig if (forig - f0) * (forig - fmp) <= MP5_EPS else flim


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def mp5(fm2, fm1, f0, fp1, fp2):
    """MP5 value at the right interface x_{j+1/2} of node j from f_{j-2} .. f_{j+2}.

    Fifth-order upwind-biased interpolation of the flux primitive (eq. halfnodes, r = 3)
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


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def numerical_flux_full(fp, fm, out, dp, qp, dm, qm, lo, m):
    """``out[c] = MP5(F+ from c-2..c+2) + MP5(F- from c+3..c-1)`` for c = lo .. lo+m-1, the whole
    limiter evaluated at every interface (branch-free; the reference for :func:`numerical_flux`).

    Parameters
    ----------
    fp, fm : (N,) float64
        F+ and F- of one conservative variable at every node (ghosts filled).
    out : (N,) float64
        Numerical flux f_{c+1/2}, stored at index c.
    dp, qp, dm, qm : (N,) float64
        Scratch rows (curvatures and their limited averages of F+ and F-).
    lo, m : int
        First interface and number of interfaces (needs 3 <= lo and lo + m + 3 <= N).
    """
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


NSCRATCH = 10  # rows of scratch :func:`numerical_flux` needs


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _q(a, b):
    """dm4_{j+1/2} from a = d_j, b = d_{j+1}, the arguments in the order of :func:`_curvatures`."""
    return _minmod4(4.0 * a - b, 4.0 * b - a, a, b)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _accepted(forig, fm1, f0, fp1):
    """The accuracy-preserving check of :func:`_limit` (the same expressions): True where MP5 keeps ``forig``."""
    fmp = f0 + _minmod(fp1 - f0, MP5_ALPHA * (f0 - fm1))
    return (forig - f0) * (forig - fmp) <= MP5_EPS


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _compact(fa, fb, m):
    """Overwrite the 0/1 flags ``fa[:m]``, ``fb[:m]`` with the indices of their ones; returns both counts."""
    ka = 0
    kb = 0
    for i in range(m):  # branch-free: a flag set at random 1 time in 10 would defeat branch prediction
        ba = fa[i]
        bb = fb[i]
        fa[ka] = i  # ka <= i: flag i has been read
        fb[kb] = i
        ka += ba
        kb += bb
    return ka, kb


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _limited(f, idx, k, g, res, r, lo, mirrored):
    """``r[c] = MP5`` with the limiter for the k interfaces ``c = idx[:k]`` of one side (F+, or F- if ``mirrored``).

    The stencils are first copied into the rows ``g[0..4]`` (in the order f_{j-2} .. f_{j+2} of :func:`mp5`)
    so that the limiter loop runs over contiguous rows and vectorizes; the curvatures and their limited
    averages of each interface are recomputed from its stencil with the operations of :func:`_curvatures`.
    """
    g0, g1, g2, g3, g4 = g[0], g[1], g[2], g[3], g[4]
    one, two, three, four = np.uint64(1), np.uint64(2), np.uint64(3), np.uint64(4)  # unsigned: no wraparound test
    if mirrored:
        fv = f[lo - 1:]  # F- at interface c: f_{c+3}, f_{c+2}, f_{c+1}, f_c, f_{c-1}
        for j in range(k):
            c = np.uint64(idx[j])
            g0[j] = fv[c + four]
            g1[j] = fv[c + three]
            g2[j] = fv[c + two]
            g3[j] = fv[c + one]
            g4[j] = fv[c]
        for j in range(k):
            v0, v1, v2, v3, v4 = g0[j], g1[j], g2[j], g3[j], g4[j]
            fo = (2.0 * v0 - 13.0 * v1 + 47.0 * v2 + 27.0 * v3 - 3.0 * v4) * (1.0 / 60.0)
            ec = v0 - 2.0 * v1 + v2  # d_{c+2}, d_{c+1}, d_c of F-, summed f_{j+1} - 2 f_j + f_{j-1}
            eb = v1 - 2.0 * v2 + v3
            ea = v2 - 2.0 * v3 + v4
            res[j] = _limit(fo, v1, v2, v3, _q(eb, ec), _q(ea, eb))  # dm4m = q_{c+1}, dm4p = q_c
    else:
        fv = f[lo - 2:]  # F+ at interface c: f_{c-2} .. f_{c+2}
        for j in range(k):
            c = np.uint64(idx[j])
            g0[j] = fv[c]
            g1[j] = fv[c + one]
            g2[j] = fv[c + two]
            g3[j] = fv[c + three]
            g4[j] = fv[c + four]
        for j in range(k):
            w0, w1, w2, w3, w4 = g0[j], g1[j], g2[j], g3[j], g4[j]
            fo = (2.0 * w0 - 13.0 * w1 + 47.0 * w2 + 27.0 * w3 - 3.0 * w4) * (1.0 / 60.0)
            da = w0 - 2.0 * w1 + w2  # d_{c-1}, d_c, d_{c+1} of F+
            db = w1 - 2.0 * w2 + w3
            dc = w2 - 2.0 * w3 + w4
            res[j] = _limit(fo, w1, w2, w3, _q(da, db), _q(db, dc))  # dm4m = q_{c-1}, dm4p = q_c
    for j in range(k):
        r[np.uint64(idx[j])] = res[j]


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
        Scratch rows.
    lo, m : int
        First interface and number of interfaces (needs 3 <= lo and lo + m + 3 <= N).

    Notes
    -----
    Pass 1 (vectorized) computes the linear values of both reconstructions, their sum, and flags
    where a check fails; the flags are compacted into index lists and :func:`_limited` recomputes
    those reconstructions with the limiter; their interfaces get the sum again.  Equal bit for bit to
    :func:`numerical_flux_full` (the same check, the same limiter expressions) at 0.8-0.9 of its cost
    in the default box (docs/researcher/hydro.md, "Cost of a step").
    """
    ra, rb, res = S[0], S[1], S[2]
    ia, ib = S[3].view(np.int64), S[4].view(np.int64)
    g = S[5:10]
    o = out[lo:]
    a0, a1, a2, a3, a4 = fp[lo - 2:], fp[lo - 1:], fp[lo:], fp[lo + 1:], fp[lo + 2:]
    b0, b1, b2, b3, b4 = fm[lo - 1:], fm[lo:], fm[lo + 1:], fm[lo + 2:], fm[lo + 3:]
    for i in range(m):
        fa = (2.0 * a0[i] - 13.0 * a1[i] + 47.0 * a2[i] + 27.0 * a3[i] - 3.0 * a4[i]) * (1.0 / 60.0)
        fb = (2.0 * b4[i] - 13.0 * b3[i] + 47.0 * b2[i] + 27.0 * b1[i] - 3.0 * b0[i]) * (1.0 / 60.0)
        ra[i] = fa
        rb[i] = fb
        o[i] = fa + fb
        ia[i] = 0 if _accepted(fa, a1[i], a2[i], a3[i]) else 1
        ib[i] = 0 if _accepted(fb, b3[i], b2[i], b1[i]) else 1
    ka, kb = _compact(ia, ib, m)
    _limited(fp, ia, ka, g, res, ra, lo, False)
    _limited(fm, ib, kb, g, res, rb, lo, True)
    for j in range(ka):
        c = np.uint64(ia[j])
        o[c] = ra[c] + rb[c]
    for j in range(kb):
        c = np.uint64(ib[j])
        o[c] = ra[c] + rb[c]
