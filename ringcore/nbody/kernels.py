"""Numba kernels of the local shearing box: epicycle drift, shear-periodic boundaries,
cell-list neighbour search and hard-sphere collision resolution.

Kernel units (document of record for all of :mod:`ringcore.nbody`): lengths in the
particle radius ``R_p``, times in ``1/Omega``, velocities in ``R_p Omega``. The box
spans ``-L_x/2 <= x < L_x/2``, ``-L_y/2 <= y < L_y/2``; velocities are the full Hill
velocities (Keplerian shear ``v_y = -1.5 x`` included).

Arrays: ``pos``, ``vel`` have shape (N, 3) (columns x, y, z); ghosts (images of the
particles near the inner edge, placed beyond the outer edge ``x >= L_x/2``) live in
``gpos`` (cap, 3) with their source index in ``gsrc`` (cap,). A cell list covers the
``n_cx`` real columns plus one ghost column (index ``n_cx``) times ``n_cy`` rows;
``cell_start`` has shape ((n_cx+1) n_cy + 1,), ``cell_entries`` (N + cap,) holds entry
indices (``e < N``: particle ``e``; ``e >= N``: ghost ``e - N``).

References: Eq. (49) with kappa = Omega; Eq. (48); Rein & Tremaine (2011) for
the exact epicyclic drift of the symplectic epicycle integrator (SEI).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

# indices of the accumulator array ``acc`` (float64, length N_ACC)
A_NCOLL = 0  # collisions resolved
A_NRECEDE = 1  # overlapping pairs found already separating (resolved earlier, still overlapping)
A_NUNRES = 2  # approaching overlaps deeper than the last step's approach: unresolved for > 1 step
A_PXX_NL = 3  # sum of dv_x,i (x_i - x_j) over impacts   [R_p^2 Omega]
A_PXY_NL = 4  # sum of dv_y,i (x_i - x_j)
A_PYY_NL = 5  # sum of dv_y,i (y_i - y_j)
A_PZZ_NL = 6  # sum of dv_z,i (z_i - z_j)
A_SWX = 7  # sum over particle-steps of w_x, w_y, w_z (peculiar velocity, Kepler shear removed)
A_SWY = 8
A_SWZ = 9
A_SWXX = 10
A_SWYY = 11
A_SWZZ = 12
A_SWXY = 13
A_NSAMP = 14  # particle-steps sampled
A_MAXDEPTH = 15  # largest overlap depth seen [R_p]
A_NOVERLAP = 16  # overlapping pairs seen (any state)
A_TIME = 17  # time covered by the accumulators [1/Omega]
A_CROSS = 18  # radial boundary crossings
N_ACC = 19


@njit(nogil=True, cache=True)
def drift_epicycle(pos, vel, dt, omega_z):
    """Exact free motion of Eq. (49) (kappa = Omega = 1, no forces) over ``dt``.

    Planar: guiding centre x_g = 4 x + 2 v_y; x = x_g + (x0 - x_g) cos t + v_x0 sin t,
    y = y0 - 1.5 x_g t - 2 (x0 - x_g) sin t - 2 v_x0 (1 - cos t), v_y = x_g / 2 - 2 x.
    Vertical: harmonic oscillation with frequency ``omega_z``. In place; shapes (N, 3).
    """
    s = math.sin(dt)
    c = math.cos(dt)
    omc = 2.0 * math.sin(0.5 * dt) ** 2
    sz = math.sin(omega_z * dt)
    cz = math.cos(omega_z * dt)
    for i in range(pos.shape[0]):
        x0 = pos[i, 0]
        vx0 = vel[i, 0]
        xg = 4.0 * x0 + 2.0 * vel[i, 1]
        a = x0 - xg
        x = xg + a * c + vx0 * s
        pos[i, 0] = x
        pos[i, 1] += -1.5 * xg * dt - 2.0 * a * s - 2.0 * vx0 * omc
        vel[i, 0] = -a * s + vx0 * c
        vel[i, 1] = 0.5 * xg - 2.0 * x
        z0 = pos[i, 2]
        vz0 = vel[i, 2]
        pos[i, 2] = z0 * cz + vz0 / omega_z * sz
        vel[i, 2] = -z0 * omega_z * sz + vz0 * cz


@njit(nogil=True, cache=True)
def shear_offset(t, L_x, L_y):
    """Azimuthal offset D = 1.5 L_x t mod L_y: the image of (x, y) at x + L_x sits at y - D."""
    return (1.5 * L_x * t) % L_y


@njit(nogil=True, cache=True)
def wrap_shear_periodic(pos, vel, L_x, L_y, D, x_max=math.inf):
    """Shear-periodic radial and periodic azimuthal boundaries; returns the number of radial crossings.

    A particle leaving at x >= L_x/2 re-enters at x - L_x with y + D and v_y + 1.5 L_x
    (and the reverse at -L_x/2). In place; shapes (N, 3).  Returns -1 (stopping at that
    particle) if some |x| is not below ``x_max`` or not finite: such a runaway would make the
    crossing loop run for ever (x - L_x == x beyond 2^53 L_x) or for hours.
    """
    hx = 0.5 * L_x
    hy = 0.5 * L_y
    n = 0
    for i in range(pos.shape[0]):
        x = pos[i, 0]
        if not (x < x_max and x > -x_max):
            return -1
        while x >= hx:
            x -= L_x
            pos[i, 1] += D
            vel[i, 1] += 1.5 * L_x
            n += 1
        while x < -hx:
            x += L_x
            pos[i, 1] -= D
            vel[i, 1] -= 1.5 * L_x
            n += 1
        pos[i, 0] = x
        y = pos[i, 1]
        if y >= hy or y < -hy:
            y = (y + hy) % L_y - hy
            if y >= hy:  # round-off of the modulo
                y -= L_y
            pos[i, 1] = y
    return n


@njit(nogil=True, cache=True)
def coefficient_of_restitution(vn, mode, eps_const, v_c):
    """Normal coefficient of restitution of an impact with normal speed ``vn`` >= 0.

    mode 0: constant ``eps_const``; mode 1: Bridges et al. law Eq. (48),
    (vn / v_c)^-0.234 capped at 1 below ``v_c`` (same units as ``vn``).
    """
    if mode == 0:
        return eps_const
    if vn <= v_c:
        return 1.0
    return (vn / v_c) ** -0.234


@njit(nogil=True, cache=True)
def build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, gpos, gsrc, cell_start, cell_entries, cell_of):
    """Make ghosts of the particles in the innermost column and bin all entries into cells.

    Returns the number of ghosts. ``cell_of`` (N + cap,) receives each entry's cell
    (column-major: cell = cx * n_cy + cy); counting sort, O(N).
    """
    N = pos.shape[0]
    hx = 0.5 * L_x
    hy = 0.5 * L_y
    csx = L_x / n_cx
    csy = L_y / n_cy
    ng = 0
    for i in range(N):
        if pos[i, 0] < -hx + csx:
            gpos[ng, 0] = pos[i, 0] + L_x
            y = pos[i, 1] - D
            if y < -hy:
                y += L_y
            gpos[ng, 1] = y
            gpos[ng, 2] = pos[i, 2]
            gsrc[ng] = i
            ng += 1
    ncell = (n_cx + 1) * n_cy
    for c in range(ncell + 1):
        cell_start[c] = 0
    for e in range(N + ng):
        if e < N:
            x = pos[e, 0]
            y = pos[e, 1]
            cx = int((x + hx) / csx)
            if cx > n_cx - 1:
                cx = n_cx - 1
        else:
            y = gpos[e - N, 1]
            cx = n_cx
        cy = int((y + hy) / csy)
        if cy > n_cy - 1:
            cy = n_cy - 1
        if cy < 0:
            cy = 0
        if cx < 0:
            cx = 0
        c = cx * n_cy + cy
        cell_of[e] = c
        cell_start[c + 1] += 1
    for c in range(ncell):
        cell_start[c + 1] += cell_start[c]
    # fill (use cell_of's counts via a running pointer stored temporarily in cell_start shift)
    for e in range(N + ng):
        c = cell_of[e]
        cell_entries[cell_start[c]] = e
        cell_start[c] += 1
    for c in range(ncell, 0, -1):
        cell_start[c] = cell_start[c - 1]
    cell_start[0] = 0
    return ng


@njit(nogil=True, cache=True, inline="always")
def pair_separation(a, b, pos, gpos, gsrc, N, L_x, L_y):
    """Separation of entries a (< N, real) and b (real or ghost): ``(ib, vshift, dx, dy, dz, r2)`` with ``ib``
    the particle of b, ``vshift`` the v_y offset of b's image (-1.5 L_x for a ghost) and d = x_a - x_b
    (y periodic) [R_p]; shared by the impact models."""
    if b < N:
        ib = b
        bx = pos[b, 0]
        by = pos[b, 1]
        bz = pos[b, 2]
        vshift = 0.0
    else:
        ib = gsrc[b - N]
        bx = gpos[b - N, 0]
        by = gpos[b - N, 1]
        bz = gpos[b - N, 2]
        vshift = -1.5 * L_x
    dx = pos[a, 0] - bx
    dz = pos[a, 2] - bz
    dy = pos[a, 1] - by
    if dy > 0.5 * L_y:
        dy -= L_y
    elif dy < -0.5 * L_y:
        dy += L_y
    return ib, vshift, dx, dy, dz, dx * dx + dy * dy + dz * dz


@njit(nogil=True, cache=True, inline="always")
def normal_speed(vel, ia, ib, vshift, nx, ny, nz):
    """Normal relative velocity (v_ia - v_ib) . n of a pair [R_p Omega] (> 0: separating)."""
    return ((vel[ia, 0] - vel[ib, 0]) * nx + (vel[ia, 1] - vel[ib, 1] - vshift) * ny
            + (vel[ia, 2] - vel[ib, 2]) * nz)


@njit(nogil=True, cache=True, inline="always")
def add_impulse(dv, ia, ib, j, nx, ny, nz, dx, dy, dz, acc):
    """Add the velocity change j n to ``dv[ia]`` and -j n to ``dv[ib]`` (equal masses; ``dv`` is the velocities
    themselves or a buffer) and its nonlocal momentum flux to ``acc``; shared by the impact models."""
    jx = j * nx
    jy = j * ny
    jz = j * nz
    dv[ia, 0] += jx
    dv[ia, 1] += jy
    dv[ia, 2] += jz
    dv[ib, 0] -= jx
    dv[ib, 1] -= jy
    dv[ib, 2] -= jz
    acc[A_PXX_NL] += jx * dx
    acc[A_PXY_NL] += jy * dx
    acc[A_PYY_NL] += jy * dy
    acc[A_PZZ_NL] += jz * dz


@njit(nogil=True, cache=True, inline="always")
def stencil_range(cx, cy, s, ka, n_cx, n_cy, cell_start):
    """Entries ``(kb0, kb1)`` that entry ``ka`` of cell (cx, cy) meets in part ``s`` (0..4) of the half stencil:
    the rest of its cell, the cells (+1, -1), (+1, 0), (+1, +1) (y periodic) and (0, +1); (0, 0) beyond the
    ghost column.  Every pair of the cell list is met once over all entries and parts."""
    if s == 0:
        ncx = cx
        ncy = cy
    elif s == 4:
        ncx = cx
        ncy = (cy + 1) % n_cy
    else:
        ncx = cx + 1
        ncy = (cy + s - 2) % n_cy
    if ncx > n_cx:
        return 0, 0
    nc = ncx * n_cy + ncy
    return (ka + 1 if s == 0 else cell_start[nc]), cell_start[nc + 1]


@njit(nogil=True, cache=True)
def _collide(a, b, pos, vel, gpos, gsrc, N, L_x, L_y, dt, mode, eps_const, v_c, acc):
    """Check entries a (< N, real) and b (real or ghost) and resolve if overlapping and approaching."""
    ia = a
    ib, vshift, dx, dy, dz, r2 = pair_separation(a, b, pos, gpos, gsrc, N, L_x, L_y)
    if r2 >= 4.0:
        return
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
    j = -0.5 * (1.0 + eps) * vn  # > 0, velocity change of a along +n (equal masses)
    add_impulse(vel, ia, ib, j, nx, ny, nz, dx, dy, dz, acc)
    acc[A_NCOLL] += 1.0


@njit(nogil=True, cache=True)
def resolve_collisions(pos, vel, gpos, gsrc, cell_start, cell_entries, n_cx, n_cy, L_x, L_y, dt,
                       mode, eps_const, v_c, acc):
    """Resolve all overlapping, approaching pairs once, in cell order (hard spheres).

    Half stencil over the cells (same cell, (+1,-1), (+1,0), (+1,+1), (0,+1); y periodic)
    finds every pair once, cross-boundary pairs through the ghost column. Each impact
    reverses the normal relative velocity and scales it by epsilon (Eq. (48) or
    constant), conserving momentum; the nonlocal momentum flux is accumulated in ``acc``.
    """
    N = pos.shape[0]
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
                            _collide(a, b, pos, vel, gpos, gsrc, N, L_x, L_y, dt, mode, eps_const, v_c, acc)
                        else:
                            _collide(b, a, pos, vel, gpos, gsrc, N, L_x, L_y, dt, mode, eps_const, v_c, acc)


@njit(nogil=True, cache=True)
def sample_local_stress(pos, vel, acc):
    """Add the peculiar velocities w = v - (0, -1.5 x, 0) and their products to ``acc``."""
    for i in range(pos.shape[0]):
        wx = vel[i, 0]
        wy = vel[i, 1] + 1.5 * pos[i, 0]
        wz = vel[i, 2]
        acc[A_SWX] += wx
        acc[A_SWY] += wy
        acc[A_SWZ] += wz
        acc[A_SWXX] += wx * wx
        acc[A_SWYY] += wy * wy
        acc[A_SWZZ] += wz * wz
        acc[A_SWXY] += wx * wy
    acc[A_NSAMP] += pos.shape[0]


def new_accumulators() -> np.ndarray:
    """Zeroed accumulator array of length N_ACC."""
    return np.zeros(N_ACC)


@njit(nogil=True, cache=True)
def sort_by_cell(pos, vel, ids, cell_entries, n_entries, spos, svel, sids):
    """Reorder the particles (pos, vel, ids) into cell-list order for memory locality.

    ``cell_entries[:n_entries]`` from :func:`build_cell_list` (ghost entries >= N are
    skipped); ``spos``, ``svel`` (N, 3) and ``sids`` (N,) are scratch arrays.
    """
    N = pos.shape[0]
    k = 0
    for q in range(n_entries):
        e = cell_entries[q]
        if e < N:
            for a in range(3):
                spos[k, a] = pos[e, a]
                svel[k, a] = vel[e, a]
            sids[k] = ids[e]
            k += 1
    for i in range(N):
        for a in range(3):
            pos[i, a] = spos[i, a]
            vel[i, a] = svel[i, a]
        ids[i] = sids[i]
