"""Visco-elastic impacts of finite duration (Dilley 1993; Salo 1995), the paper's impact model.

Section 4.2 resolves each impact as a contact of finite duration: while two particles
overlap by xi = 2 R_p - r > 0 their normal relative motion obeys the damped linear spring

    xi'' + 2 beta xi' + omega_0^2 xi = 0,

whose solution xi = (v_n0 / omega_d) exp(-beta t) sin(omega_d t) ends (xi = 0) after the contact duration
T_c = pi / omega_d with the normal relative speed scaled by exp(-beta T_c).  With

    beta = -ln(eps) / T_c,   omega_0^2 = (pi / T_c)^2 + beta^2

every contact lasts exactly T_c and returns the coefficient of restitution eps.  Salo's linear model fixes
T_c; eps is the chosen law (constant, or the Bridges et al. law Eq. (48), capped at 1 below v_c) at the
normal impact speed v_n0 recorded when the contact starts, kept in the contact memory for the whole contact.

Contact memory (arrays of shape (N, K), K = :data:`SLOTS`, rows indexed by the smaller particle label of a
pair; labels are 0 .. N-1): ``cpart`` partner label (-1: empty), ``cstamp`` the last step in which the pair
overlapped (a contact continues if it overlapped in the previous step) and ``ceps`` its coefficient of
restitution.  It is part of the run's state (saved in run files: restarts continue bit for bit).

One step (kernel units, see :mod:`ringcore.nbody.kernels`): exact drift dt/2; at the mid-step positions the
self-gravity and the contact forces (cell-list search of :func:`~ringcore.nbody.kernels.build_cell_list`,
ghosts with the shear offset of the mid-step time) kick all velocities by dt (the forces of all pairs
computed from the same velocities, then applied); exact drift dt/2; shear-periodic wrap; sampling; sorting.

Units: lengths R_p, times 1/Omega, velocities R_p Omega; forces per unit particle mass.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from .gravity import kick_selfgravity
from .integrator import (I_COLLISIONS, I_MHI, I_MLO, I_MODE, I_NCX, I_NCY, I_SORT_EVERY, OK, P_DT, P_EPS,
                         P_G, P_LX, P_LY, P_OMEGA_Z, P_T0, P_VC, P_XMAX, RUNAWAY_X, W_CELL_ENTRIES, W_CELL_OF,
                         W_CELL_START, W_COEF, W_FORCE, W_GPOS, W_GSRC, W_RHO, W_SIDS, W_SPOS, W_SVEL)
from .kernels import (A_CROSS, A_MAXDEPTH, A_NCOLL, A_NOVERLAP, A_TIME, add_impulse, build_cell_list,
                      coefficient_of_restitution, drift_epicycle, normal_speed, pair_separation, sample_local_stress,
                      shear_offset, sort_by_cell, stencil_range, wrap_shear_periodic)

SLOTS = 12  # contacts remembered per particle row (an equal sphere touches at most 12 others)
NO_STEP = -2  # stamp of an empty slot (never "the previous step")
# contact statistics cstat[S_*] (run totals, kernel units)
S_STARTED = 0  # contacts started
S_DISSIPATED = 1  # energy dissipated by the dashpots, per unit particle mass [(R_p Omega)^2]
S_OVERFLOW = 2  # contacts that found no free memory slot (eps taken at the current speed)
S_PAIR_STEPS = 3  # overlapping pair-steps (time in contact / dt, summed over pairs)
N_STAT = 4
STEPS_PER_CONTACT_MIN = 10  # fewer steps per contact duration are refused (the restitution would be off)


def new_memory(n: int):
    """Empty contact memory ``(cpart, cstamp, ceps, cstat)`` for ``n`` particles."""
    return (np.full((n, SLOTS), -1, np.int64), np.full((n, SLOTS), NO_STEP, np.int64), np.zeros((n, SLOTS)),
            np.zeros(N_STAT))


def clear_memory(mem) -> None:
    """Forget every contact in progress (a new time origin or a new run from old particles)."""
    mem[0][:] = -1
    mem[1][:] = NO_STEP
    mem[2][:] = 0.0


@njit(nogil=True, cache=True)
def _contact_eps(ia, ib, step, vimp, mode, eps_const, v_c, cpart, cstamp, ceps, cstat):
    """Coefficient of restitution of the contact of labels ``ia``, ``ib``: the remembered one if the pair
    overlapped in the previous step, else a new contact at normal speed ``vimp`` (>= 0), remembered."""
    r = min(ia, ib)
    p = max(ia, ib)
    free = -1
    for s in range(cpart.shape[1]):
        if cpart[r, s] == p and cstamp[r, s] == step - 1:
            cstamp[r, s] = step
            return ceps[r, s]
        if free < 0 and cstamp[r, s] < step - 1:
            free = s
    eps = coefficient_of_restitution(vimp, mode, eps_const, v_c)
    cstat[S_STARTED] += 1.0
    if free < 0:
        cstat[S_OVERFLOW] += 1.0
    else:
        cpart[r, free] = p
        cstamp[r, free] = step
        ceps[r, free] = eps
    return eps


@njit(nogil=True, cache=True)
def _pair(a, b, pos, vel, ids, gpos, gsrc, N, L_x, L_y, dt, step, mode, eps_const, v_c, T_c,
          cpart, cstamp, ceps, dv, acc, cstat):
    """Contact force of entries a (< N, real) and b (real or ghost), added to ``dv`` as dt F."""
    ib, vshift, dx, dy, dz, r2 = pair_separation(a, b, pos, gpos, gsrc, N, L_x, L_y)
    if r2 >= 4.0:
        return
    r = math.sqrt(r2)
    if r == 0.0:
        return
    xi = 2.0 - r
    acc[A_NOVERLAP] += 1.0
    if xi > acc[A_MAXDEPTH]:
        acc[A_MAXDEPTH] = xi
    nx = dx / r
    ny = dy / r
    nz = dz / r
    vn = normal_speed(vel, a, ib, vshift, nx, ny, nz)  # > 0: separating
    eps = _contact_eps(ids[a], ids[ib], step, max(-vn, 0.0), mode, eps_const, v_c, cpart, cstamp, ceps, cstat)
    beta = -math.log(eps) / T_c
    w02 = (math.pi / T_c) ** 2 + beta * beta
    # velocity change of a along +n (equal masses); the dashpot acts on the mean normal velocity of the
    # step (trapezoidal: an isolated pair's Delta v_n = dt (w02 xi - 2 beta (v_n + Delta v_n / 2))), which
    # makes the scheme second order in dt for the restitution
    j = 0.5 * dt * (w02 * xi - 2.0 * beta * vn) / (1.0 + beta * dt)
    add_impulse(dv, a, ib, j, nx, ny, nz, dx, dy, dz, acc)
    vm = vn + j  # mean normal relative velocity of the step
    cstat[S_DISSIPATED] += beta * vm * vm * dt  # dashpot work (per unit particle mass) of the step
    cstat[S_PAIR_STEPS] += 1.0


@njit(nogil=True, cache=True)
def contact_kick(pos, vel, ids, gpos, gsrc, cell_start, cell_entries, n_cx, n_cy, L_x, L_y, dt, step,
                 mode, eps_const, v_c, T_c, cpart, cstamp, ceps, dv, acc, cstat):
    """Kick ``vel`` by dt times the visco-elastic contact forces of all overlapping pairs.

    Pairs come from the cell list (half stencil as :func:`~ringcore.nbody.kernels.resolve_collisions`,
    cross-boundary pairs through the ghost column); the forces use the velocities before the kick
    (accumulated in ``dv`` (N, 3), then applied), so the result does not depend on the pair order.
    Contacts started are counted in ``acc[A_NCOLL]``, the nonlocal momentum flux in ``acc``.
    """
    N = pos.shape[0]
    n0 = cstat[S_STARTED]
    dv[:] = 0.0
    for cx in range(n_cx + 1):
        for cy in range(n_cy):
            c = cx * n_cy + cy
            for ka in range(cell_start[c], cell_start[c + 1]):
                a = cell_entries[ka]
                for s in range(5):
                    kb0, kb1 = stencil_range(cx, cy, s, ka, n_cx, n_cy, cell_start)
                    for kb in range(kb0, kb1):
                        b = cell_entries[kb]
                        if a >= N and b >= N:
                            continue
                        if a < N:
                            _pair(a, b, pos, vel, ids, gpos, gsrc, N, L_x, L_y, dt, step, mode, eps_const, v_c,
                                  T_c, cpart, cstamp, ceps, dv, acc, cstat)
                        else:
                            _pair(b, a, pos, vel, ids, gpos, gsrc, N, L_x, L_y, dt, step, mode, eps_const, v_c,
                                  T_c, cpart, cstamp, ceps, dv, acc, cstat)
    for i in range(N):
        vel[i, 0] += dv[i, 0]
        vel[i, 1] += dv[i, 1]
        vel[i, 2] += dv[i, 2]
    acc[A_NCOLL] += cstat[S_STARTED] - n0


@njit(nogil=True, cache=True)
def advance(pos, vel, ids, acc, fpar, ipar, work, T_c, dv, cpart, cstamp, ceps, cstat, step0, nsteps):
    """Advance ``nsteps`` steps with visco-elastic contacts of duration ``T_c`` [1/Omega]; ``(status, steps)``.

    Same contract as :func:`ringcore.nbody.integrator.advance` (packed ``fpar``/``ipar``/``work``; time,
    sorting and contact stamps depend on the global step count ``step0 + k`` only, so a run split into
    calls of any lengths is bit for bit the same); ``dv`` (N, 3) scratch; contact memory as in the module
    docstring.
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
    sort_every = ipar[I_SORT_EVERY]
    gpos = work[W_GPOS]
    gsrc = work[W_GSRC]
    cell_start = work[W_CELL_START]
    cell_entries = work[W_CELL_ENTRIES]
    half = 0.5 * dt
    for k in range(nsteps):
        step = step0 + k
        drift_epicycle(pos, vel, half, omega_z)
        if g != 0.0:
            kick_selfgravity(pos, vel, dt, g, L_x, ipar[I_MLO], ipar[I_MHI], work[W_RHO], work[W_FORCE],
                             work[W_COEF])
        ng = 0
        if collisions:
            D_mid = shear_offset(t0 + (step + 0.5) * dt, L_x, L_y)
            ng = build_cell_list(pos, L_x, L_y, D_mid, n_cx, n_cy, gpos, gsrc, cell_start, cell_entries,
                                 work[W_CELL_OF])
            contact_kick(pos, vel, ids, gpos, gsrc, cell_start, cell_entries, n_cx, n_cy, L_x, L_y, dt, step,
                         mode, eps_const, v_c, T_c, cpart, cstamp, ceps, dv, acc, cstat)
        drift_epicycle(pos, vel, half, omega_z)
        nc = wrap_shear_periodic(pos, vel, L_x, L_y, shear_offset(t0 + (step + 1) * dt, L_x, L_y), x_max)
        if nc < 0:
            return RUNAWAY_X, k
        acc[A_CROSS] += nc
        if collisions and sort_every > 0 and step % sort_every == 0:
            sort_by_cell(pos, vel, ids, cell_entries, pos.shape[0] + ng, work[W_SPOS], work[W_SVEL],
                         work[W_SIDS])
        sample_local_stress(pos, vel, acc)
        acc[A_TIME] += dt
    return OK, nsteps
