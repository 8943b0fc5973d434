"""The right-hand side and update of an SSPRK stage on numba's threads, in windows of the grid, with the
bits of the single-threaded stage.

The grid's n interior nodes are cut into ``chunks`` windows of equal width w (the last one shifted left
to end at node n, overlapping its neighbour).  A window is copied with its NG ghost nodes on each side
(the neighbouring nodes, or the periodic ghosts at the ends) into its own scratch (``Uc``, ``Wc``, ``Lc``),
and :func:`ringcore.hydro.kernels.compute_rhs` runs on it unchanged: every stencil of the scheme reaches at
most NG nodes, so L at the window's interior nodes is computed from the same numbers by the same
arithmetic as on the whole grid (no fast-math reassociation or contraction, :data:`layout._FM`), i.e. the
same bits.  Each window then updates the nodes it owns; the grid maxima of the time step are maxima
over the windows (exact in any order) and the temperature floor's counts are sums of integers.  So the
states are the same bits for any number of threads and windows (``tests/core/test_hydro_threads.py``).

One parallel region per stage (two in the stage that chooses dt: the maxima come before the update);
the self-gravity FFT, the ghost filling and the final state check stay on one thread.

References: Eqs. (26), (32); Section 4.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from . import kernels as K
from .layout import NG

MIN_NODES_PER_CHUNK = 1000  # smaller grids run on one thread (a parallel launch costs ~ a 1,000-node stage)


def chunks_for(threads: int, n: int) -> int:
    """Windows of a grid of ``n`` nodes for ``threads`` threads (1: the serial stage)."""
    if threads <= 1:
        return 1
    return int(max(1, min(threads, n // MIN_NODES_PER_CHUNK)))


def new_work(chunks: int, n: int, nv: int, n_l: int):
    """``(Uc, Wc, Lc, win, maxes, hits)`` for :func:`stage`: per window its state (nv, w + 2 NG), scratch
    (NW, w + 2 NG) and L slots (n_l, nv, w + 2 NG); ``win`` (chunks, 3) holds each window's first node and
    the first and last + 1 node it owns (interior indices)."""
    w = -(-n // chunks)
    win = np.zeros((chunks, 3), np.int64)
    for c in range(chunks):
        own_lo, own_hi = c * w, min((c + 1) * w, n)
        win[c] = (min(own_lo, n - w), own_lo, own_hi)
    m = w + 2 * NG
    return (np.zeros((chunks, nv, m)), np.zeros((chunks, K.NW, m)), np.zeros((chunks, n_l, nv, m)), win,
            np.zeros((chunks, 3)), np.zeros(chunks, np.int64))


@njit(nogil=True, cache=True, error_model="numpy", parallel=True)
def _rhs(Uin, beta, g, par, li, maxima, Uc, Wc, Lc, win, maxes, update, out, A, a0, B, a1, C, a2, lp, c1, c2,
         use_lp, T_floor, hits):
    """Per window (in parallel): L(Uin) into ``Lc[c, li]``, its grid maxima (``maxima``) into ``maxes[c]``
    and, with ``update``, the stage update of the nodes it owns (as :func:`_owned_update`)."""
    nv = Uin.shape[0]
    m = Uc.shape[2]
    w = m - 2 * NG
    for c in prange(win.shape[0]):
        a = win[c, 0]
        U = Uc[c]
        for k in range(nv):
            src = Uin[k]
            dst = U[k]
            for i in range(m):
                dst[i] = src[a + i]
        vmax, numax, rmax = K.compute_rhs(U, Wc[c], beta[a:a + m], g[a:a + w], par, Lc[c, li], maxima, False)
        maxes[c, 0] = vmax
        maxes[c, 1] = numax
        maxes[c, 2] = rmax
        if update:
            hits[c] = _owned_update(c, out, A, a0, B, a1, C, a2, Lc, li, lp, c1, c2, use_lp, win, T_floor)


@njit(nogil=True, cache=True, error_model="numpy")
def _owned_update(c, out, A, a0, B, a1, C, a2, Lc, li, lp, c1, c2, use_lp, win, T_floor):
    """``out = a0 A + c1 L + a1 B + a2 C + c2 Lprev`` at the nodes window ``c`` owns (as
    :func:`ringcore.hydro.kernels.rk_stage`), then the temperature floor there; returns the floor's count."""
    a, lo, hi = win[c, 0], win[c, 1], win[c, 2]
    off = NG + lo - a
    n = hi - lo
    for k in range(out.shape[0]):
        K._update(out[k][NG + lo:NG + hi], A[k][NG + lo:NG + hi], a0, Lc[c, li, k][off:off + n], c1,
                  B[k][NG + lo:NG + hi], a1, C[k][NG + lo:NG + hi], a2, Lc[c, lp, k][off:off + n], c2, use_lp)
    if T_floor > 0.0:
        return K.apply_temperature_floor(out[:, lo:hi + 2 * NG], T_floor)
    return 0


@njit(nogil=True, cache=True, error_model="numpy", parallel=True)
def _update_all(out, A, a0, B, a1, C, a2, Lc, li, lp, c1, c2, use_lp, win, T_floor, hits):
    for c in prange(win.shape[0]):
        hits[c] = _owned_update(c, out, A, a0, B, a1, C, a2, Lc, li, lp, c1, c2, use_lp, win, T_floor)


@njit(nogil=True, cache=True, error_model="numpy")
def stage(Uin, beta, g, par, li, lp, A, a0, B, a1, C, a2, b1, b2, dt, dt_cap, out, T_floor, tw):
    """One SSPRK stage as :func:`ringcore.hydro.kernels.rk_stage` followed by the temperature floor (if
    ``T_floor`` > 0), in the windows of ``tw`` (:func:`new_work`); returns ``(dt, floor_hits)``."""
    Uc, Wc, Lc, win, maxes, hits = tw
    n = Uin.shape[1] - 2 * NG
    K.fill_ghosts(Uin, n)
    choose = dt <= 0.0
    use_lp = b2 != 0.0
    if not choose:
        _rhs(Uin, beta, g, par, li, False, Uc, Wc, Lc, win, maxes, True, out, A, a0, B, a1, C, a2, lp, dt * b1,
             dt * b2, use_lp, T_floor, hits)
    else:
        _rhs(Uin, beta, g, par, li, True, Uc, Wc, Lc, win, maxes, False, out, A, a0, B, a1, C, a2, lp, 0.0, 0.0,
             use_lp, T_floor, hits)
        vmax = 0.0
        numax = 0.0
        rmax = 0.0
        for c in range(win.shape[0]):
            vmax = max(vmax, maxes[c, 0])
            numax = max(numax, maxes[c, 1])
            rmax = max(rmax, maxes[c, 2])
        dt = min(K.stable_dt(vmax, numax, rmax, par[K.P_H], int(par[K.P_DTMODE]), par[K.P_DTFACTOR]), dt_cap)
        _update_all(out, A, a0, B, a1, C, a2, Lc, li, lp, dt * b1, dt * b2, use_lp, win, T_floor, hits)
    total = 0
    for c in range(win.shape[0]):
        total += hits[c]
    return dt, total
