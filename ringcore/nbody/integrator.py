"""Time stepping of the shearing box: symplectic epicycle integrator + per-step hard-sphere collisions.

One step of length dt (kernel units, see :mod:`ringcore.nbody.kernels`):

1. exact epicyclic/vertical drift over dt/2 (eq. (hill) without forces),
2. kick v_x += dt F_g(x) with the collective radial self-gravity eq. (sgmodes) (if g != 0),
3. exact drift over dt/2 (Strang splitting: the SEI scheme of Rein & Tremaine 2011),
4. shear-periodic wrap with the offset D(t + dt),
5. cell-list search and resolution of the overlapping, approaching pairs (as REBOUND does),
6. sampling of the peculiar-velocity moments for the local stress,
7. every ``sort_every`` steps, reordering of the particles into cell order (cache locality;
   ``ids`` follows the particles).

Without self-gravity and collisions the scheme is the exact flow of eq. (hill); the
splitting is symplectic, second order in dt for the self-gravity force.

References: eqs. (hill), (bridges), (sgmodes).
"""
from __future__ import annotations

from numba import njit

from .gravity import kick_selfgravity
from .kernels import (A_CROSS, A_TIME, build_cell_list, drift_epicycle, resolve_collisions,
                      sample_local_stress, shear_offset, sort_by_cell, wrap_shear_periodic)


@njit(nogil=True, cache=True)
def advance(pos, vel, t0, nsteps, dt, omega_z, L_x, L_y, n_cx, n_cy, collisions, mode, eps_const,
            v_c, g, m_lo, m_hi, rho, force, coef, gpos, gsrc, cell_start, cell_entries, cell_of, acc,
            ids, sort_every, spos, svel, sids, step0=0):
    """Advance the particles ``nsteps`` steps of ``dt``; return the new time ``t0 + (step0 + nsteps) dt``.

    ``t0`` is the time of step 0 and ``step0`` the number of steps already taken since then: time and
    the sorting schedule depend on the global step count only, so a run split into calls of any
    lengths is bit-for-bit the same as one call.

    Parameters (kernel units: R_p, 1/Omega)
    ----------
    pos, vel : (N, 3) float arrays, modified in place.
    omega_z : vertical frequency [Omega].
    L_x, L_y : box size [R_p]; n_cx, n_cy: cell counts (>= 3, cell sides >= 2 R_p).
    collisions : bool; mode, eps_const, v_c : restitution law (see ``coefficient_of_restitution``).
    g : -2 pi G sigma0 / (R_p Omega^2) (0: no self-gravity); m_lo..m_hi: modes used.
    rho, force (n_bins,), coef (2, m_hi - m_lo + 1): self-gravity work arrays.
    gpos (cap, 3), gsrc (cap,), cell_start, cell_entries, cell_of: neighbour-search work arrays.
    acc : (N_ACC,) accumulators (collisions, momentum fluxes, velocity moments).
    ids (N,) particle labels; sort_every (0: never; sorts when the global step number is a multiple);
    spos, svel (N, 3), sids (N,) scratch.
    """
    half = 0.5 * dt
    t = t0 + step0 * dt
    for k in range(nsteps):
        drift_epicycle(pos, vel, half, omega_z)
        if g != 0.0:
            kick_selfgravity(pos, vel, dt, g, L_x, m_lo, m_hi, rho, force, coef)
        drift_epicycle(pos, vel, half, omega_z)
        t = t0 + (step0 + k + 1) * dt
        D = shear_offset(t, L_x, L_y)
        acc[A_CROSS] += wrap_shear_periodic(pos, vel, L_x, L_y, D)
        if collisions:
            ng = build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, gpos, gsrc, cell_start, cell_entries, cell_of)
            resolve_collisions(pos, vel, gpos, gsrc, cell_start, cell_entries, n_cx, n_cy, L_x, L_y, dt,
                               mode, eps_const, v_c, acc)
            if sort_every > 0 and (step0 + k) % sort_every == 0:
                sort_by_cell(pos, vel, ids, cell_entries, pos.shape[0] + ng, spos, svel, sids)
        sample_local_stress(pos, vel, acc)
        acc[A_TIME] += dt
    return t
