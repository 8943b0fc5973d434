"""Time stepping of the shearing box: symplectic epicycle integrator + per-step hard-sphere collisions.

One step of length dt (kernel units, see :mod:`ringcore.nbody.kernels`):

1. exact epicyclic/vertical drift over dt/2 (Eq. (49) without forces),
2. kick v_x += dt F_g(x) with the collective radial self-gravity Eq. (54) (if g != 0),
3. exact drift over dt/2 (Strang splitting: the SEI scheme of Rein & Tremaine 2011),
4. shear-periodic wrap with the offset D(t + dt),
5. cell-list search and resolution of the overlapping, approaching pairs (as REBOUND does;
   :mod:`ringcore.nbody.pairs`, in column strips on threads),
6. sampling of the peculiar-velocity moments for the local stress,
7. every ``sort_every`` steps, reordering of the particles into cell order (cache locality;
   ``ids`` follows the particles).

With ``ipar[I_THREADS]`` > 1 the drifts, the wrap and the impacts run on numba's threads
(:mod:`ringcore.nbody.blocks`, :mod:`ringcore.nbody.pairs`); the results are the same bits for every
number of threads.

Without self-gravity and collisions the scheme is the exact flow of Eq. (49); the
splitting is symplectic, second order in dt for the self-gravity force.

The kernel takes packed parameters: a float64 vector ``fpar`` (indices ``P_*``), an int64
vector ``ipar`` (indices ``I_*``) and the tuple ``work`` of work arrays (indices ``W_*``);
build them with :func:`pack_params` / :func:`new_work`.

References: Eqs. (49), (48), (54).
"""
from __future__ import annotations


import numpy as np
from numba import njit

from .gravity import kick_selfgravity
from .blocks import (blocks_for, drift_blocks, drift_wrap_blocks, entry_coords_blocks, new_counts, new_sample_parts,
                     sample_blocks)
from .kernels import (A_CROSS, A_TIME, build_cell_list, drift_epicycle, sample_local_stress, shear_offset,
                      sort_by_cell, wrap_shear_periodic)
from .pairs import entry_coords, n_strips, new_strip_accumulators, resolve_strips

# float parameters fpar[P_*] (kernel units)
P_T0 = 0  # time of step 0 [1/Omega]
P_DT = 1  # time step [1/Omega]
P_OMEGA_Z = 2  # vertical frequency [Omega]
P_LX = 3  # radial box size [R_p]
P_LY = 4  # azimuthal box size [R_p]
P_EPS = 5  # constant coefficient of restitution (law 0)
P_VC = 6  # Bridges et al. velocity scale v_c [R_p Omega] (law 1)
P_G = 7  # -2 pi G sigma0 / (R_p Omega^2); 0: no self-gravity
P_XMAX = 8  # |x| beyond which a particle is a runaway (the wrap would loop for ever) [R_p]
N_FPAR = 9
# integer parameters ipar[I_*]
I_NCX = 0  # cell columns (>= 3, sides >= 2 R_p)
I_NCY = 1  # cell rows
I_COLLISIONS = 2  # 0/1
I_MODE = 3  # restitution law: 0 constant, 1 Bridges et al.
I_MLO = 4  # lowest self-gravity mode
I_MHI = 5  # highest self-gravity mode
I_SORT_EVERY = 6  # steps between reorderings into cell order (0: never)
I_THREADS = 7  # numba threads of the drifts, wrap and impacts (1: serial; the same bits for any number)
I_NBLK = 8  # particle blocks of the threaded per-particle phases
I_STRIPS = 9  # strips of the impact search (1: the reference order; :func:`ringcore.nbody.pairs.n_strips`)
N_IPAR = 10
# work arrays work[W_*]
W_RHO, W_FORCE, W_COEF, W_GPOS, W_SPOS, W_SVEL = 0, 1, 2, 3, 4, 5
W_GSRC, W_CELL_START, W_CELL_ENTRIES, W_CELL_OF, W_SIDS = 6, 7, 8, 9, 10
W_EC, W_ACCS, W_COUNTS, W_PARTS = 11, 12, 13, 14

# status codes returned by :func:`advance`
OK = 0
RUNAWAY_X = 1  # a particle left the box by more than P_XMAX (or became non-finite) in the wrap


def pack_params(t0, dt, omega_z, L_x, L_y, eps, v_c, g, x_max, n_cx, n_cy, collisions, mode, m_lo, m_hi,
                sort_every, threads=1, n=1):
    """The packed parameter vectors ``(fpar, ipar)`` (kernel units; see the ``P_*``/``I_*`` constants);
    ``threads`` and the particle count ``n`` set the threaded phases (the work arrays of :func:`new_work`
    must be made for at least that many threads)."""
    fpar = np.zeros(N_FPAR)
    fpar[[P_T0, P_DT, P_OMEGA_Z, P_LX, P_LY, P_EPS, P_VC, P_G, P_XMAX]] = (t0, dt, omega_z, L_x, L_y, eps,
                                                                           v_c, g, x_max)
    ipar = np.zeros(N_IPAR, np.int64)
    ipar[[I_NCX, I_NCY, I_COLLISIONS, I_MODE, I_MLO, I_MHI, I_SORT_EVERY]] = (n_cx, n_cy, int(bool(collisions)),
                                                                              mode, m_lo, m_hi, sort_every)
    ipar[I_THREADS] = threads
    ipar[I_NBLK] = blocks_for(threads, n)
    ipar[I_STRIPS] = n_strips(n_cx)
    return fpar, ipar


def new_work(n, n_cx, n_cy, n_bins, n_modes, threads=1):
    """The work-array tuple for ``n`` particles and up to ``threads`` threads (order of the ``W_*`` constants)."""
    ncell = (n_cx + 1) * n_cy
    return (np.zeros(n_bins), np.zeros(n_bins), np.zeros((2, n_modes)), np.zeros((n, 3)), np.zeros((n, 3)),
            np.zeros((n, 3)), np.zeros(n, np.int64), np.zeros(ncell + 1, np.int64), np.zeros(2 * n, np.int64),
            np.zeros(2 * n, np.int64), np.zeros(n, np.int64), np.zeros((2 * n, 3)), new_strip_accumulators(n_cx),
            new_counts(threads), new_sample_parts())


@njit(nogil=True, cache=True)
def advance(pos, vel, ids, acc, fpar, ipar, work, step0, nsteps):
    """Advance the particles ``nsteps`` steps of ``fpar[P_DT]``; return ``(status, steps_done)``.

    ``fpar[P_T0]`` is the time of step 0 and ``step0`` the number of steps already taken since
    then: time and the sorting schedule depend on the global step count only, so a run split into
    calls of any lengths is bit-for-bit the same as one call.  ``status`` is :data:`OK` or
    :data:`RUNAWAY_X` (a particle beyond ``fpar[P_XMAX]``: the step ``steps_done`` + 1 failed, the
    arrays are partly updated and must be replaced by the caller's last good copy).

    Parameters
    ----------
    pos, vel : (N, 3) float arrays, modified in place; ids (N,) particle labels (follow the sort).
    acc : (N_ACC,) accumulators (collisions, momentum fluxes, velocity moments).
    fpar (N_FPAR,), ipar (N_IPAR,) : packed parameters; work : tuple of work arrays (:func:`new_work`).
        All in kernel units (R_p, 1/Omega).
    """
    dt = fpar[P_DT]
    t0 = fpar[P_T0]
    omega_z = fpar[P_OMEGA_Z]
    L_x = fpar[P_LX]
    L_y = fpar[P_LY]
    eps_const = fpar[P_EPS]
    v_c = fpar[P_VC]
    g = fpar[P_G]
    x_max = fpar[P_XMAX]
    n_cx = ipar[I_NCX]
    n_cy = ipar[I_NCY]
    collisions = ipar[I_COLLISIONS] != 0
    mode = ipar[I_MODE]
    m_lo = ipar[I_MLO]
    m_hi = ipar[I_MHI]
    sort_every = ipar[I_SORT_EVERY]
    threads = ipar[I_THREADS]
    nblk = ipar[I_NBLK]
    rho = work[W_RHO]
    force = work[W_FORCE]
    coef = work[W_COEF]
    gpos = work[W_GPOS]
    spos = work[W_SPOS]
    svel = work[W_SVEL]
    gsrc = work[W_GSRC]
    cell_start = work[W_CELL_START]
    cell_entries = work[W_CELL_ENTRIES]
    cell_of = work[W_CELL_OF]
    sids = work[W_SIDS]
    ec = work[W_EC]
    accs = work[W_ACCS]
    counts = work[W_COUNTS]
    parts = work[W_PARTS]
    N = pos.shape[0]
    ns = ipar[I_STRIPS]  # the box's choice, never the threads'
    strips = ns > 1
    half = 0.5 * dt
    for k in range(nsteps):
        t = t0 + (step0 + k + 1) * dt
        D = shear_offset(t, L_x, L_y)
        if nblk > 1:
            if g != 0.0:
                drift_blocks(pos, vel, half, omega_z, nblk)
                kick_selfgravity(pos, vel, dt, g, L_x, m_lo, m_hi, rho, force, coef)
            nc = drift_wrap_blocks(pos, vel, half, omega_z, L_x, L_y, D, x_max, g == 0.0, nblk, counts)
        else:
            drift_epicycle(pos, vel, half, omega_z)
            if g != 0.0:
                kick_selfgravity(pos, vel, dt, g, L_x, m_lo, m_hi, rho, force, coef)
            drift_epicycle(pos, vel, half, omega_z)
            nc = wrap_shear_periodic(pos, vel, L_x, L_y, D, x_max)
        if nc < 0:
            return RUNAWAY_X, k
        acc[A_CROSS] += nc
        if collisions:
            ng = build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, gpos, gsrc, cell_start, cell_entries, cell_of)
            if nblk > 1:
                entry_coords_blocks(pos, gpos, cell_entries, N + ng, ec, nblk)
            else:
                entry_coords(pos, gpos, cell_entries, N + ng, ec)
            resolve_strips(threads, ns, ec, vel, gsrc, cell_start, cell_entries, N, n_cx, n_cy, L_x, L_y, dt, mode,
                           eps_const, v_c, accs, acc)
            if sort_every > 0 and (step0 + k) % sort_every == 0:
                sort_by_cell(pos, vel, ids, cell_entries, pos.shape[0] + ng, spos, svel, sids)
        if strips:
            sample_blocks(pos, vel, acc, parts)
        else:
            sample_local_stress(pos, vel, acc)
        acc[A_TIME] += dt
    return OK, nsteps

