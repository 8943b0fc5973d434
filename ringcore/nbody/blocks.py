"""The per-particle phases of a shearing-box step (drift, boundaries) on numba's threads, in blocks of
particles.

Every particle's update depends on that particle only and the crossing count is a sum of integers, so
the results are the bits of the serial kernels of :mod:`ringcore.nbody.kernels` for any number of
threads and any blocks.  The drift of the second half step and the boundary wrap are fused into one
pass (one parallel launch per step instead of two).  Kernel units as in :mod:`ringcore.nbody.kernels`.

References: eq. (hill).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .kernels import drift_epicycle, wrap_shear_periodic

BLOCKS_PER_THREAD = 4  # blocks per thread (a thread slowed by another job leaves little work behind)
MIN_PARTICLES = 8192  # smaller boxes drift on one thread (a parallel launch costs more than it saves)


@njit(nogil=True, cache=True, parallel=True)
def drift_blocks(pos, vel, dt, omega_z, nblk):
    """:func:`~ringcore.nbody.kernels.drift_epicycle` in ``nblk`` blocks on numba's threads."""
    n = pos.shape[0]
    for b in prange(nblk):
        lo = b * n // nblk
        hi = (b + 1) * n // nblk
        drift_epicycle(pos[lo:hi], vel[lo:hi], dt, omega_z)


@njit(nogil=True, cache=True, parallel=True)
def drift_wrap_blocks(pos, vel, dt, omega_z, L_x, L_y, D, x_max, first_drift, nblk, counts):
    """Per block: (if ``first_drift``) a drift of ``dt``, a second drift of ``dt``, then the shear-periodic
    wrap; returns the radial crossings, or -1 if some particle ran away (as
    :func:`~ringcore.nbody.kernels.wrap_shear_periodic`). ``counts`` (>= nblk,) is scratch."""
    n = pos.shape[0]
    for b in prange(nblk):
        lo = b * n // nblk
        hi = (b + 1) * n // nblk
        p = pos[lo:hi]
        v = vel[lo:hi]
        if first_drift:
            drift_epicycle(p, v, dt, omega_z)
        drift_epicycle(p, v, dt, omega_z)
        counts[b] = wrap_shear_periodic(p, v, L_x, L_y, D, x_max)
    total = 0
    for b in range(nblk):
        if counts[b] < 0:
            return -1
        total += counts[b]
    return total


def blocks_for(threads: int, n: int) -> int:
    """Blocks of the per-particle phases for ``threads`` threads and ``n`` particles (1: serial)."""
    if threads <= 1 or n < MIN_PARTICLES:
        return 1
    return int(min(n, threads * BLOCKS_PER_THREAD))


def new_counts(threads: int) -> np.ndarray:
    """Scratch for :func:`drift_wrap_blocks`."""
    return np.zeros(max(1, threads * BLOCKS_PER_THREAD), np.int64)

