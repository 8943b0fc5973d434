"""A whole SSPRK(5,4) step on numba's threads, in windows of the grid, with the bits of the single-threaded
step.

The grid's n interior nodes are cut into ``chunks`` consecutive windows (:func:`widths`).  A window is
copied with its NG neighbouring nodes on each side (periodically wrapped at the ends, as
:func:`ringcore.hydro.kernels.fill_ghosts` fills the ghosts) into its own scratch, and the kernels of
:func:`ringcore.hydro.kernels.compute_rhs` run on it unchanged: every stencil of the scheme reaches at
most NG nodes, so L at the window's nodes is computed from the same numbers by the same arithmetic as on
the whole grid (no fast-math reassociation or contraction, :data:`layout._FM`), i.e. the same bits.  Each
window then updates its nodes; the grid maxima of the time step are maxima over the windows (exact in
any order) and the temperature floor's counts are sums of integers.  So the states are the same bits for
any number of threads and windows (``tests/core/test_hydro_threads.py``).

The step is one parallel region of a team (:mod:`ringcore.hydro.team`; entering a region costs as much
as the work of a few hundred nodes), two phases per stage:

A. the self-gravity FFT of the stage's density with the ghost nodes (one task) beside the fluxes and
   derivatives of every window (:func:`ringcore.hydro.kernels.rhs_fluxes`, one task per window, with the
   grid maxima in the first stage), so the FFT costs no wall time of its own: the member that does it
   has the smallest window (``FFT_SHARE``);
B. per window the flux difference and the sources with the new force
   (:func:`ringcore.hydro.kernels.rhs_sources`), the stage update of its nodes and the floor.  It waits
   for the force and its own window's fluxes only, except in the first stage, whose dt needs every
   window's maxima (every member reduces them alike).  The next stage needs the neighbours' new nodes
   and the whole density: all of phase B.

Member m works on windows m, m + size, ... first, in every stage and step, so a window's data stay in
one core's cache (measured at 4,000 nodes: when any member took any window, the tasks ran 30-100 % longer, from cache misses);
then on what a late team mate left unclaimed.  The final state check stays on one thread (after the
region).

References: Eqs. (26), (32); Section 4.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from . import kernels as K
from . import team
from .fftw import convolve
from .layout import NG

MIN_NODES_PER_CHUNK = 1000  # smaller grids run on one thread (their windows would not pay for the team)
# the self-gravity FFT (with the ghosts) costs about this fraction of phase A's fluxes of the whole grid
# (measured 0.15 at 2,000-4,000 nodes, 0.18-0.20 at 16,000-64,000): the thread that does it gets a
# window smaller by as many nodes
FFT_SHARE = 0.16
PHASES_PER_STAGE = 2
MAX_STAGES = 8  # counters for tableaus of up to this many stages


def chunks_for(threads: int, n: int) -> int:
    """Windows of a grid of ``n`` nodes for ``threads`` threads (1: the serial step)."""
    if threads <= 1:
        return 1
    return int(max(1, min(threads, n // MIN_NODES_PER_CHUNK)))


def widths(chunks: int, n: int, team: int, fft_share: float) -> list:
    """Widths of the ``chunks`` windows of an ``n``-node grid: equal, except that with one window per
    thread (``chunks == team``) and ``fft_share`` > 0 the last window is smaller by the work of the FFT
    (``fft_share`` n nodes' worth of fluxes), which its thread does first."""
    if chunks > 1 and chunks == team and fft_share > 0.0:
        last = max(2 * NG, int(round(n * (1.0 + fft_share) / team - fft_share * n)))
        if last * chunks < n:
            rest = n - last
            return [rest // (chunks - 1) + (1 if c < rest % (chunks - 1) else 0) for c in range(chunks - 1)] + [last]
    return [n // chunks + (1 if c < n % chunks else 0) for c in range(chunks)]


def new_work(chunks: int, n: int, nv: int, n_l: int, threads: int | None = None, fft_share: float = 0.0,
             spins: int = team.SPINS):
    """``(Ub, Wb, Lb, win, maxes, hits, ctr, box)`` for :func:`step`.

    ``win`` (chunks, 3): each window's first node, last node + 1 (interior indices; consecutive windows)
    and width w (:func:`widths`); per window flat storage for its state (nv, w + 2 NG), scratch
    (NW, w + 2 NG) and L slots (n_l, nv, w + 2 NG) (``Ub``, ``Wb``, ``Lb``, row c, viewed in that shape by
    :func:`_views`); the team's counters; ``box``: the step's dt, the team's size (``threads``,
    default one thread per window) and the checks a waiting member spins before it sleeps (``spins``)."""
    team_size = int(threads or chunks)
    w = widths(chunks, n, min(team_size, chunks), fft_share)
    win = np.zeros((chunks, 3), np.int64)
    lo = 0
    for c in range(chunks):
        win[c] = (lo, lo + w[c], w[c])
        lo += w[c]
    m = max(w) + 2 * NG
    return (np.zeros((chunks, nv * m)), np.zeros((chunks, K.NW * m)), np.zeros((chunks, n_l * nv * m)), win,
            np.zeros((chunks, 3)), np.zeros(chunks, np.int64), team.counters(PHASES_PER_STAGE * MAX_STAGES, chunks + 1),
            np.array([0.0, float(team_size), float(spins)]))


@njit(nogil=True, cache=True, error_model="numpy")
def _views(c, Ub, Wb, Lb, win, nv):
    """Window ``c``'s state (nv, m), scratch (NW, m) and L slots (n_l, nv, m), m = w + 2 NG (C-contiguous)."""
    m = win[c, 2] + 2 * NG
    n_l = Lb.shape[1] // (nv * (Ub.shape[1] // nv))
    return (Ub[c, :nv * m].reshape(nv, m), Wb[c, :K.NW * m].reshape(K.NW, m),
            Lb[c, :n_l * nv * m].reshape(n_l, nv, m))


@njit(nogil=True, cache=True, error_model="numpy")
def _window_fluxes(c, Uin, beta, par, maxima, Ub, Wb, Lb, win, maxes):
    """Phase A of window ``c``: copy its nodes (periodic ghosts read from the other end of the grid, as
    :func:`ringcore.hydro.kernels.fill_ghosts` fills them), then fluxes, derivatives and maxima."""
    nv = Uin.shape[0]
    n = Uin.shape[1] - 2 * NG
    a = win[c, 0]
    U, W, _ = _views(c, Ub, Wb, Lb, win, nv)
    m = U.shape[1]
    left = max(0, NG - a)  # copy nodes before the grid's first node: read from its end
    right = max(0, a + m - (NG + n))  # after its last node: read from its start
    for k in range(nv):
        src = Uin[k]
        dst = U[k]
        for i in range(left):
            dst[i] = src[a + i + n]
        mid = dst[left:m - right]
        s_ = src[a + left:a + m - right]
        for i in range(m - left - right):
            mid[i] = s_[i]
        for i in range(m - right, m):
            dst[i] = src[a + i - n]
    vmax, numax, rmax = K.rhs_fluxes(U, W, beta[a:a + m], par, maxima)
    if maxima:  # (only then: a team mate that comes late still finds the step's maxima)
        maxes[c, 0] = vmax
        maxes[c, 1] = numax
        maxes[c, 2] = rmax


@njit(nogil=True, cache=True, error_model="numpy")
def _window_update(c, g, par, out, A, a0, B, a1, C, a2, li, lp, c1, c2, use_lp, Ub, Wb, Lb, win, T_floor):
    """Phase B of window ``c``: flux difference and sources into its L slot ``li``, then ``out = a0 A +
    c1 L + a1 B + a2 C + c2 Lprev`` at its nodes (as :func:`ringcore.hydro.kernels.rk_stage`) and the
    temperature floor there; returns the floor's count."""
    lo, hi = win[c, 0], win[c, 1]
    U, W, Lc = _views(c, Ub, Wb, Lb, win, out.shape[0])
    K.rhs_sources(U, W, g[lo:hi], par, Lc[li])
    for k in range(out.shape[0]):
        K._update(out[k][NG + lo:NG + hi], A[k][NG + lo:NG + hi], a0, Lc[li, k][NG:NG + hi - lo], c1,
                  B[k][NG + lo:NG + hi], a1, C[k][NG + lo:NG + hi], a2, Lc[lp, k][NG:NG + hi - lo], c2, use_lp)
    if T_floor > 0.0:
        return K.apply_temperature_floor(out[:, lo:hi + 2 * NG], T_floor)
    return 0


@njit(nogil=True, cache=True, error_model="numpy")
def _task_a(t, Uin, beta, par, choose, gravity_on, fwd, bwd, G, s, sk, g, tw):
    """Task ``t`` of phase A: 0 the ghosts and the FFT, 1 + c the fluxes of window c."""
    if t == 0:
        K.fill_ghosts(Uin, Uin.shape[1] - 2 * NG)
        if gravity_on:
            convolve(Uin[0, NG:Uin.shape[1] - NG], fwd, bwd, G, s, sk, g)
    else:
        _window_fluxes(t - 1, Uin, beta, par, choose, tw[0], tw[1], tw[2], tw[3], tw[4])


@njit(nogil=True, cache=True, error_model="numpy")
def _member(me, size, U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor,
            tw):
    """What member ``me`` of a team of ``size`` runs: the phases of the step (module docstring).  It does
    its own windows first (c = me, me + size, ...: the same windows in every stage and step, whose data
    stay in its core's cache; the FFT goes with the last, smallest window), then any task still unclaimed
    (a late team mate's)."""
    Ub, Wb, Lb, win, maxes, hits, ctr, box = tw
    nc = win.shape[0]
    fft_owner = (nc - 1) % size
    spins = int(box[2])
    dt = -1.0
    for st in range(stage_i.shape[0]):
        i, li, lp = stage_i[st, 0], stage_i[st, 1], stage_i[st, 2]
        Uin = U[slot[i]]
        choose = dt <= 0.0
        pa = PHASES_PER_STAGE * st
        pb = pa + 1
        for r in range(3):  # the FFT if it is this member's, its own windows, then any unclaimed task
            for t in range(0 if r != 1 else 1 + me, nc + 1, size if r == 1 else 1):
                if (r == 0 and (t > 0 or me != fft_owner)) or not team.take(ctr, pa, t):
                    continue
                _task_a(t, Uin, beta, par, choose, gravity_on, fwd, bwd, G, s, sk, g, tw)
                team.finish(ctr, pa, t)
        if choose:  # dt needs every window's maxima; every member reduces them alike: the same dt
            team.wait(ctr, pa, nc + 1, spins)
            vmax = 0.0
            numax = 0.0
            rmax = 0.0
            for c in range(nc):
                vmax = max(vmax, maxes[c, 0])
                numax = max(numax, maxes[c, 1])
                rmax = max(rmax, maxes[c, 2])
            dt = min(K.stable_dt(vmax, numax, rmax, par[K.P_H], int(par[K.P_DTMODE]), par[K.P_DTFACTOR]), dt_cap)
        out, A, B, C = U[slot[i + 1]], U[slot[stage_i[st, 3]]], U[slot[stage_i[st, 4]]], U[slot[stage_i[st, 5]]]
        a0, a1, a2, b1, b2 = stage_f[st, 0], stage_f[st, 1], stage_f[st, 2], stage_f[st, 3], stage_f[st, 4]
        for r in range(2):  # own windows; then those whose fluxes are done (never one a team mate is still on)
            for c in range(me if r == 0 else 0, nc, size if r == 0 else 1):
                if (r == 1 and not team.finished(ctr, pa, 1 + c)) or not team.take(ctr, pb, c):
                    continue
                team.wait_for(ctr, pa, 0, spins)  # the force
                team.wait_for(ctr, pa, 1 + c, spins)  # the window's fluxes (if a team mate took them)
                hits[c] += _window_update(c, g, par, out, A, a0, B, a1, C, a2, li, lp, dt * b1, dt * b2,
                                          b2 != 0.0, Ub, Wb, Lb, win, T_floor)
                if c == 0:
                    box[0] = dt
                team.finish(ctr, pb, c)
        team.wait(ctr, pb, nc, spins)


@njit(nogil=True, cache=True, error_model="numpy", parallel=True)
def _team_step(U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor, tw, size):
    for me in prange(size):
        _member(me, size, U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor,
                tw)


@njit(nogil=True, cache=True, error_model="numpy")
def step(U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor, tw):
    """The stages of one SSPRK step (arguments as :func:`ringcore.hydro.stepper.ssprk_step`) by the team
    of ``tw`` (:func:`new_work`) in its windows; returns ``(dt, floor_hits)``."""
    hits, ctr = tw[5], tw[6]
    if stage_i.shape[0] > MAX_STAGES:
        raise ValueError("the threaded step has counters for at most MAX_STAGES stages")
    ctr[:] = 0
    hits[:] = 0
    _team_step(U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor, tw,
               max(1, int(tw[7][1])))
    total = 0
    for c in range(hits.shape[0]):
        total += hits[c]
    return tw[7][0], total
