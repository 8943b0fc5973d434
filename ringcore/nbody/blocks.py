"""The per-particle phases of a shearing-box step (drift, boundaries) on numba's threads, in blocks of
particles.

Every particle's update depends on that particle only and the crossing count is a sum of integers, so
the results are the bits of the serial kernels of :mod:`ringcore.nbody.kernels` for any number of
threads and any blocks.  The drift of the second half step and the boundary wrap are fused into one
pass (one parallel launch per step instead of two).  Kernel units as in :mod:`ringcore.nbody.kernels`.

References: Eq. (49).
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .kernels import A_NSAMP, A_SWX, A_SWXX, A_SWXY, A_SWY, A_SWYY, A_SWZ, A_SWZZ, drift_epicycle, wrap_shear_periodic

BLOCKS_PER_THREAD = 4  # blocks per thread (a thread slowed by another job leaves little work behind)
MIN_PARTICLES = 8192  # smaller boxes drift on one thread (a parallel launch costs more than it saves)
MAX_BLOCKS = 512  # the scratch of the crossing counts holds this many (any thread count, any machine)
SAMPLE_BLOCKS = 64  # blocks of the velocity-moment sums of the strip boxes (fixed: the sums' order is the box's)


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


@njit(nogil=True, cache=True, parallel=True)
def entry_coords_blocks(pos, gpos, cell_entries, n_entries, ec, nblk):
    """:func:`ringcore.nbody.pairs.entry_coords` in ``nblk`` blocks of entries on numba's threads."""
    N = pos.shape[0]
    for b in prange(nblk):
        for k in range(b * n_entries // nblk, (b + 1) * n_entries // nblk):
            e = cell_entries[k]
            if e < N:
                ec[k, 0] = pos[e, 0]
                ec[k, 1] = pos[e, 1]
                ec[k, 2] = pos[e, 2]
            else:
                ec[k, 0] = gpos[e - N, 0]
                ec[k, 1] = gpos[e - N, 1]
                ec[k, 2] = gpos[e - N, 2]


@njit(nogil=True, cache=True, parallel=True)
def sample_blocks(pos, vel, acc, part):
    """:func:`ringcore.nbody.kernels.sample_local_stress` as sums over ``SAMPLE_BLOCKS`` fixed blocks of
    particles (on numba's threads), added to ``acc`` in block order: the same bits for any number of
    threads (not those of the one-pass sum).  ``part`` (SAMPLE_BLOCKS, 7) is scratch."""
    n = pos.shape[0]
    nb = part.shape[0]
    for b in prange(nb):
        s0 = 0.0
        s1 = 0.0
        s2 = 0.0
        s3 = 0.0
        s4 = 0.0
        s5 = 0.0
        s6 = 0.0
        for i in range(b * n // nb, (b + 1) * n // nb):
            wx = vel[i, 0]
            wy = vel[i, 1] + 1.5 * pos[i, 0]
            wz = vel[i, 2]
            s0 += wx
            s1 += wy
            s2 += wz
            s3 += wx * wx
            s4 += wy * wy
            s5 += wz * wz
            s6 += wx * wy
        part[b, 0] = s0
        part[b, 1] = s1
        part[b, 2] = s2
        part[b, 3] = s3
        part[b, 4] = s4
        part[b, 5] = s5
        part[b, 6] = s6
    for b in range(nb):
        acc[A_SWX] += part[b, 0]
        acc[A_SWY] += part[b, 1]
        acc[A_SWZ] += part[b, 2]
        acc[A_SWXX] += part[b, 3]
        acc[A_SWYY] += part[b, 4]
        acc[A_SWZZ] += part[b, 5]
        acc[A_SWXY] += part[b, 6]
    acc[A_NSAMP] += n


def new_sample_parts() -> np.ndarray:
    """Scratch for :func:`sample_blocks`."""
    return np.zeros((SAMPLE_BLOCKS, 7))


def blocks_for(threads: int, n: int) -> int:
    """Blocks of the per-particle phases for ``threads`` threads and ``n`` particles (1: serial)."""
    if threads <= 1 or n < MIN_PARTICLES:
        return 1
    return int(min(n, threads * BLOCKS_PER_THREAD, MAX_BLOCKS))


def new_counts(threads: int = 0) -> np.ndarray:
    """Scratch for :func:`drift_wrap_blocks` (``MAX_BLOCKS`` entries whatever ``threads``: a box unpickled
    on a machine with more cores may use them all)."""
    return np.zeros(MAX_BLOCKS, np.int64)

