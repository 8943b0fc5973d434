"""The same shearing box in REBOUND (optional extra ``bench``: ``pip install rebound``), for comparison.

REBOUND's shearing-sheet set-up: SEI integrator with ``OMEGA`` and ``OMEGAZ`` (set before
the first step), shear boundaries with one ghost box each side in x and y, tree collision
search, hard-sphere resolution with the restitution law as a compiled ``numba.cfunc``
assigned to ``sim._coefficient_of_restitution`` (no Python callback per impact), and the
collisional y-momentum flux from ``sim.collisions_plog``. Units SI (m, s), masses 1.
The box must be a whole number of square root cells: L_x = N_root_x L_y.
"""
from __future__ import annotations

import math

import numpy as np

_COR_CACHE = {}


def available() -> bool:
    """True if REBOUND can be imported."""
    try:
        import rebound  # noqa: F401
    except ImportError:
        return False
    return True


def _restitution_cfunc(mode: int, eps_const: float, v_c: float):
    """Compiled eps(v) with REBOUND's signature double(const reb_simulation*, double v) [m/s]."""
    key = (mode, eps_const, v_c)
    if key not in _COR_CACHE:
        from numba import cfunc, types

        if mode == 0:
            def cor(r, v):
                return eps_const
        else:
            def cor(r, v):
                a = abs(v)
                if a <= v_c:
                    return 1.0
                return (a / v_c) ** -0.234
        _COR_CACHE[key] = cfunc(types.float64(types.voidptr, types.float64))(cor)
    return _COR_CACHE[key]


def make_simulation(box):
    """A REBOUND Simulation holding the state, time step and collision law of ``box`` (ShearingBox)."""
    import rebound
    from rebound.simulation import CORFF

    o, p = box.options, box.params
    n_root_x = o.L_x / o.L_y
    if abs(n_root_x - round(n_root_x)) > 1e-9:
        raise ValueError(f"L_x / L_y = {n_root_x:g} is not valid for the REBOUND comparison: "
                         "allowed a whole number (square root cells)")
    sim = rebound.Simulation()
    sim.OMEGA = p.Omega
    sim.OMEGAZ = p.omega_z * p.Omega
    sim.integrator = "sei"
    sim.boundary = "shear"
    sim.gravity = "none"
    sim.collision = "tree"
    sim.collision_resolve = "hardsphere"
    sim.root_size = o.L_y
    sim.N_root_x = int(round(n_root_x))
    sim.N_root_y = 1
    sim.N_root_z = max(1, math.ceil(60.0 * o.R_p / o.L_y))
    sim.N_ghost_x = 1
    sim.N_ghost_y = 1
    sim.N_ghost_z = 0
    sim.dt = o.dt_orbit * 2.0 * math.pi / p.Omega
    sim.t = box.t / p.Omega
    cf = _restitution_cfunc(box._mode, o.epsilon, o.v_c)
    sim._corfp = CORFF(cf.address)  # kept alive on the Simulation, as its own setter does
    sim._coefficient_of_restitution = sim._corfp
    R, vu = o.R_p, box.v_unit
    for i in range(box.N):
        x, y, z = box.pos[i] * R
        vx, vy, vz = box.vel[i] * vu
        sim.add(m=1.0, r=R, x=x, y=y, z=z, vx=vx, vy=vy, vz=vz)
    return sim


def peculiar_moments(sim, Omega: float):
    """(C_xx, C_yy, C_zz, C_xy) [m^2/s^2] of the current REBOUND state (Kepler shear removed)."""
    n = sim.N
    xyz = np.zeros((n, 3))
    v = np.zeros((n, 3))
    sim.serialize_particle_data(xyz=xyz, vxvyvz=v)
    v[:, 1] += 1.5 * Omega * xyz[:, 0]
    v -= v.mean(axis=0)
    c = v.T @ v / n
    return c[0, 0], c[1, 1], c[2, 2], c[0, 1]


def run_and_measure(sim, nsteps: int, Omega: float, samples: int = 50) -> dict:
    """Run ``nsteps`` steps, sampling the velocity moments; viscosity from ``collisions_plog``.

    Returns T, C_xx, C_yy, C_zz [m^2/s^2], nu_local, nu_nonlocal, nu [m^2/s], N.
    """
    n_per = max(1, nsteps // samples)
    plog0 = sim.collisions_plog
    t0 = sim.t
    mom = []
    done = 0
    while done < nsteps:
        k = min(n_per, nsteps - done)
        sim.steps(k)
        done += k
        mom.append(peculiar_moments(sim, Omega))
    m = np.mean(mom, axis=0)
    n = sim.N
    dt = sim.t - t0
    nu_nl = (sim.collisions_plog - plog0) / (n * 1.0 * dt * 1.5 * Omega)
    return dict(T=float(m[:3].mean()), C_xx=float(m[0]), C_yy=float(m[1]), C_zz=float(m[2]),
                nu_local=float(m[3] / (1.5 * Omega)), nu_nonlocal=float(nu_nl),
                nu=float(m[3] / (1.5 * Omega) + nu_nl), N=n)
