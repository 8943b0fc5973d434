"""Impact search and response of the shearing box over the cell list, fast and split into column strips
for threads, with results that do not depend on the number of threads.

Kernel units and arrays as in :mod:`ringcore.nbody.kernels`.  The pairs are visited in the order of
:func:`ringcore.nbody.kernels.resolve_collisions` (the reference): cell by cell, column-major, each
particle against the rest of its cell, the three cells of the next column (rows cy-1, cy, cy+1) and the
next cell of its column.  The search reads the entries' coordinates from a copy in cell-list order
(``ec``, shape (N + cap, 3), made by :func:`entry_coords`), so the inner loop streams through
contiguous memory and touches the velocities only for the few overlapping pairs (about 2 % of the
candidates at tau = 1.5); the three cells of the next column are one contiguous range.

Threads: a box of at least ``MIN_STRIPS`` strips of ``STRIP_COLS`` columns is cut into those strips.
A strip changes the velocities of the particles of its own columns and of the first column of the next
strip only, so all even strips run at once, then all odd ones; the last strip also reaches column 0
through the ghosts, so if it is even it runs alone after them.  Each strip sums its impacts into its own
row of accumulators, added in strip order afterwards.  The order of the impacts, and so every bit of the
result, depends on the box only, never on the number of threads (boxes of fewer strips are one strip:
exactly the reference order, the results of the single-threaded code before strips).

References: Eq. (48).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .kernels import (A_MAXDEPTH, A_NCOLL, A_NOVERLAP, A_NRECEDE, A_NUNRES, A_PXX_NL, A_PXY_NL, A_PYY_NL,
                      A_PZZ_NL, N_ACC, add_impulse, coefficient_of_restitution, normal_speed)

STRIP_COLS = 16  # cell columns per strip (32 R_p)
MIN_STRIPS = 5  # boxes of fewer strips (n_cx <= 64 columns, L_x < 130 R_p) are searched as one strip
SUMMED = (A_NCOLL, A_NRECEDE, A_NUNRES, A_PXX_NL, A_PXY_NL, A_PYY_NL, A_PZZ_NL, A_NOVERLAP)


def n_strips(n_cx: int) -> int:
    """Strips of the impact search for ``n_cx`` cell columns (1: the reference order)."""
    ns = -(-n_cx // STRIP_COLS)
    return ns if ns >= MIN_STRIPS else 1


@njit(nogil=True, cache=True)
def entry_coords(pos, gpos, cell_entries, n_entries, ec):
    """Copy the coordinates of the cell-list entries (particles and ghosts) into ``ec`` in entry order."""
    N = pos.shape[0]
    for k in range(n_entries):
        e = cell_entries[k]
        if e < N:
            ec[k, 0] = pos[e, 0]
            ec[k, 1] = pos[e, 1]
            ec[k, 2] = pos[e, 2]
        else:
            ec[k, 0] = gpos[e - N, 0]
            ec[k, 1] = gpos[e - N, 1]
            ec[k, 2] = gpos[e - N, 2]


@njit(nogil=True, cache=True, inline="always")
def _respond(ia, b, dx, dy, dz, r2, vel, gsrc, N, L_x, dt, mode, eps_const, v_c, acc):
    """Impact of real particle ``ia`` with entry ``b`` (real or ghost) at overlap r2 < 4 (as
    :func:`ringcore.nbody.kernels._collide` past its distance test, the same arithmetic)."""
    if b < N:
        ib = b
        vshift = 0.0
    else:
        ib = gsrc[b - N]
        vshift = -1.5 * L_x
    r = math.sqrt(r2)
    depth = 2.0 - r
    acc[A_NOVERLAP] += 1.0
    if depth > acc[A_MAXDEPTH]:
        acc[A_MAXDEPTH] = depth
    if r == 0.0:
        return
    nx = dx / r
    ny = dy / r
    nz = dz / r
    vn = normal_speed(vel, ia, ib, vshift, nx, ny, nz)
    if vn >= 0.0:
        acc[A_NRECEDE] += 1.0
        return
    if depth > -vn * dt * 1.000001 + 1e-12:
        acc[A_NUNRES] += 1.0
    eps = coefficient_of_restitution(-vn, mode, eps_const, v_c)
    j = -0.5 * (1.0 + eps) * vn  # > 0, velocity change of ia along +n (equal masses)
    add_impulse(vel, ia, ib, j, nx, ny, nz, dx, dy, dz, acc)
    acc[A_NCOLL] += 1.0


@njit(nogil=True, cache=True, inline="always")
def _scan(a, xa, ya, za, k0, k1, ec, cell_entries, vel, gsrc, N, L_x, L_y, dt, mode, eps_const, v_c, acc):
    """Particle ``a`` at (xa, ya, za) against the entries k0 <= k < k1."""
    hy = 0.5 * L_y
    for kb in range(k0, k1):
        dx = xa - ec[kb, 0]
        dz = za - ec[kb, 2]
        dy = ya - ec[kb, 1]
        if dy > hy:
            dy -= L_y
        elif dy < -hy:
            dy += L_y
        r2 = dx * dx + dy * dy + dz * dz
        if r2 < 4.0:
            _respond(a, cell_entries[kb], dx, dy, dz, r2, vel, gsrc, N, L_x, dt, mode, eps_const, v_c, acc)


@njit(nogil=True, cache=True)
def resolve_columns(cx0, cx1, ec, vel, gsrc, cell_start, cell_entries, N, n_cy, L_x, L_y, dt, mode, eps_const,
                    v_c, acc):
    """Resolve the impacts of the particles in the columns cx0 <= cx < cx1 (< n_cx) with their half stencil."""
    for cx in range(cx0, cx1):
        base = (cx + 1) * n_cy
        for cy in range(n_cy):
            c = cx * n_cy + cy
            k_end = cell_start[c + 1]
            up = cx * n_cy + (cy + 1) % n_cy
            for ka in range(cell_start[c], k_end):
                a = cell_entries[ka]
                xa = ec[ka, 0]
                ya = ec[ka, 1]
                za = ec[ka, 2]
                _scan(a, xa, ya, za, ka + 1, k_end, ec, cell_entries, vel, gsrc, N, L_x, L_y, dt, mode,
                      eps_const, v_c, acc)
                if cy >= 1 and cy + 1 < n_cy:  # rows cy-1, cy, cy+1 of the next column: one range
                    _scan(a, xa, ya, za, cell_start[base + cy - 1], cell_start[base + cy + 2], ec, cell_entries,
                          vel, gsrc, N, L_x, L_y, dt, mode, eps_const, v_c, acc)
                else:
                    for s in range(1, 4):
                        r = base + (cy + s - 2) % n_cy
                        _scan(a, xa, ya, za, cell_start[r], cell_start[r + 1], ec, cell_entries, vel, gsrc, N,
                              L_x, L_y, dt, mode, eps_const, v_c, acc)
                _scan(a, xa, ya, za, cell_start[up], cell_start[up + 1], ec, cell_entries, vel, gsrc, N, L_x,
                      L_y, dt, mode, eps_const, v_c, acc)


@njit(nogil=True, cache=True, parallel=True)
def _phase(first, step, count, ns, n_cx, ec, vel, gsrc, cell_start, cell_entries, N, n_cy, L_x, L_y, dt, mode,
           eps_const, v_c, accs):
    """Strips first, first + step, ... (``count`` of them) at once, each into its row of ``accs``."""
    for j in prange(count):
        s = first + j * step
        cx1 = min((s + 1) * STRIP_COLS, n_cx)
        resolve_columns(s * STRIP_COLS, cx1, ec, vel, gsrc, cell_start, cell_entries, N, n_cy, L_x, L_y, dt,
                        mode, eps_const, v_c, accs[s])


@njit(nogil=True, cache=True)
def resolve_strips(threads, ns, ec, vel, gsrc, cell_start, cell_entries, N, n_cx, n_cy, L_x, L_y, dt, mode,
                   eps_const, v_c, accs, acc):
    """Resolve all impacts once in ``ns`` strips (:func:`n_strips`; 1: the reference order) as the module
    docstring says; ``threads`` > 1 runs a phase's strips on numba's threads, 1 runs them one after another
    (the same bits).  ``accs`` (>= ns, N_ACC) is scratch; the sums go to ``acc``."""
    if ns <= 1:
        resolve_columns(0, n_cx, ec, vel, gsrc, cell_start, cell_entries, N, n_cy, L_x, L_y, dt, mode,
                        eps_const, v_c, acc)
        return
    for s in range(ns):
        for q in range(N_ACC):
            accs[s, q] = 0.0
    last_even = (ns - 1) % 2 == 0
    n_even = (ns + 1) // 2 - (1 if last_even else 0)
    plan = ((0, 2, n_even), (1, 2, ns // 2), (ns - 1, 1, 1 if last_even else 0))
    for first, step, count in plan:
        if count == 0:
            continue
        if threads > 1 and count > 1:
            _phase(first, step, count, ns, n_cx, ec, vel, gsrc, cell_start, cell_entries, N, n_cy, L_x, L_y, dt,
                   mode, eps_const, v_c, accs)
        else:
            for j in range(count):
                s = first + j * step
                resolve_columns(s * STRIP_COLS, min((s + 1) * STRIP_COLS, n_cx), ec, vel, gsrc, cell_start,
                                cell_entries, N, n_cy, L_x, L_y, dt, mode, eps_const, v_c, accs[s])
    for s in range(ns):
        for q in SUMMED:
            acc[q] += accs[s, q]
        if accs[s, A_MAXDEPTH] > acc[A_MAXDEPTH]:
            acc[A_MAXDEPTH] = accs[s, A_MAXDEPTH]


def new_strip_accumulators(n_cx: int) -> np.ndarray:
    """Scratch rows of accumulators for :func:`resolve_strips` (one per strip)."""
    return np.zeros((max(1, -(-n_cx // STRIP_COLS)), N_ACC))
