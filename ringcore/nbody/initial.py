"""Initial particle states: uniform non-overlapping random placement, seeded modes, box tiling.

All functions work in kernel units (lengths R_p, velocities R_p Omega, see
:mod:`ringcore.nbody.kernels`) and return (N, 3) arrays ``pos``, ``vel`` with full Hill
velocities (Keplerian shear v_y = -1.5 x included).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def insert_nonoverlapping(cand, pos, n, n_target, lo, span, ncell, periodic_x, head, nxt):
    """Accept candidate centres (rows of ``cand``) that overlap no placed sphere; return the new count.

    Spheres of radius 1 in the box ``lo + [0, span)`` (3 axes), hashed into a grid of
    ``ncell`` (3,) cells of side >= 2 (``head`` per cell, ``nxt`` per particle; linked lists).
    y is periodic, x periodic if ``periodic_x`` (the shear offset is 0 at t = 0).
    """
    for q in range(cand.shape[0]):
        if n >= n_target:
            break
        c = np.empty(3, np.int64)
        for a in range(3):
            c[a] = min(int((cand[q, a] - lo[a]) / span[a] * ncell[a]), ncell[a] - 1)
        ok = True
        for ox in range(-1, 2):
            cx = c[0] + ox
            if periodic_x:
                cx %= ncell[0]
            elif cx < 0 or cx >= ncell[0]:
                continue
            for oy in range(-1, 2):
                cy = (c[1] + oy) % ncell[1]
                for oz in range(-1, 2):
                    cz = c[2] + oz
                    if cz < 0 or cz >= ncell[2]:
                        continue
                    j = head[(cx * ncell[1] + cy) * ncell[2] + cz]
                    while j >= 0:
                        d2 = 0.0
                        for a in range(3):
                            d = cand[q, a] - pos[j, a]
                            if a == 1 or (a == 0 and periodic_x):
                                d -= span[a] * round(d / span[a])
                            d2 += d * d
                        if d2 < 4.0:
                            ok = False
                            break
                        j = nxt[j]
                    if not ok:
                        break
                if not ok:
                    break
            if not ok:
                break
        if ok:
            for a in range(3):
                pos[n, a] = cand[q, a]
            cell = (c[0] * ncell[1] + c[1]) * ncell[2] + c[2]
            nxt[n] = head[cell]
            head[cell] = n
            n += 1
    return n


def uniform_state(rng: np.random.Generator, n_particles: int, L_x: float, L_y: float, tau: float,
                  v_disp: float, fill_fraction: float = 1.0):
    """Random non-overlapping spheres, uniform in the strip |x| < fill_fraction L_x / 2.

    Vertical positions are uniform in |z| < H with H chosen for a volume filling factor of
    0.25 (H = 8 tau / 3, at least 2); peculiar velocities are Gaussian with dispersion
    ``v_disp`` per component and zero mean. Kernel units; reproducible from ``rng``.
    """
    width = fill_fraction * L_x
    H = max(2.0, 8.0 * tau / 3.0)
    lo = np.array([-0.5 * width, -0.5 * L_y, -H])
    span = np.array([width, L_y, 2.0 * H])
    if fill_fraction < 1.0:  # keep spheres inside the strip
        lo[0] += 1.0
        span[0] -= 2.0
    ncell = np.maximum((span // 2.0).astype(np.int64), 1)
    head = -np.ones(int(np.prod(ncell)), np.int64)
    nxt = -np.ones(n_particles, np.int64)
    pos = np.zeros((n_particles, 3))
    n = 0
    for _ in range(200):
        cand = lo + span * rng.random((max(2 * (n_particles - n), 64), 3))
        n = insert_nonoverlapping(cand, pos, n, n_particles, lo, span, ncell, fill_fraction >= 1.0, head, nxt)
        if n >= n_particles:
            break
    if n < n_particles:
        raise ValueError(f"tau = {tau:g} is out of range: could not place {n_particles} non-overlapping "
                         f"particles (placed {n}); allowed: a lower tau or fill_fraction closer to 1")
    w = rng.normal(0.0, v_disp, (n_particles, 3)) if v_disp > 0 else np.zeros((n_particles, 3))
    w -= w.mean(axis=0)
    vel = w.copy()
    vel[:, 1] -= 1.5 * pos[:, 0]
    return pos, vel


def add_radial_mode(pos, vel, L_x: float, m: int, amplitude: float, phase: float = 0.0) -> None:
    """Add u = amplitude sin(k_m x + phase), k_m = 2 pi m / L_x, to the radial velocities (in place)."""
    k = 2.0 * math.pi * m / L_x
    vel[:, 0] += amplitude * np.sin(k * pos[:, 0] + phase)


def tile_radially(pos, vel, L_x: float, L_y: float, t: float):
    """Two copies side by side: the state of a box of radial size 2 L_x at time ``t``.

    Copy 1 is the box shifted to x - L_x/2, copy 2 its radial image shifted to x + L_x/2,
    displaced by the current shear offset -D(t) in y (so the sheared lattice, and the
    new offset 1.5 (2 L_x) t = 2 D, stay consistent). Peculiar velocities are kept.
    """
    D = (1.5 * L_x * t) % L_y
    w = vel.copy()
    w[:, 1] += 1.5 * pos[:, 0]
    p1 = pos.copy()
    p1[:, 0] -= 0.5 * L_x
    p2 = pos.copy()
    p2[:, 0] += 0.5 * L_x
    p2[:, 1] = (p2[:, 1] - D + 0.5 * L_y) % L_y - 0.5 * L_y
    p = np.concatenate([p1, p2])
    v = np.concatenate([w, w])
    v[:, 1] -= 1.5 * p[:, 0]
    return p, v
