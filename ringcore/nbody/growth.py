"""Growth rate and frequency of a seeded linear mode (Section 4.2.2).

The complex Fourier amplitude of the radial velocity field, U_m(t) = (2/N) sum_i v_x,i
exp(-i k_m x_i), is sampled while the box runs. Growth rate and
frequency come from :func:`ringcore.analysis.rates.complex_mode_fit` (the Lomb normalised periodogram of
Re U_m and Im U_m, as in the paper, refined by a least-squares fit of a growing rotating mode).
Units: omega_R, omega_I in Omega; times in 1/Omega (kernel units).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.rates import complex_mode_fit
from ..checks import check_int, check_real


@dataclass(frozen=True)
class ModeGrowth:
    """Measured mode: ``growth_rate``, ``frequency`` [Omega] (fit), ``frequency_lomb`` [Omega],
    ``t`` [1/Omega] and ``amplitude`` (complex U_m [R_p Omega]) of the samples used."""

    m: int
    wavelength_m: float
    growth_rate: float
    frequency: float
    frequency_lomb: float
    growth_rate_err: float
    frequency_err: float
    t: np.ndarray
    amplitude: np.ndarray


def velocity_mode(pos, vel, L_x: float, m: int) -> complex:
    """U_m = (2/N) sum v_x exp(-i k_m x) (kernel units)."""
    k = 2.0 * math.pi * m / L_x
    return complex(2.0 * np.mean(vel[:, 0] * np.exp(-1j * k * pos[:, 0])))


def measure(box, m: int, orbits: float, sample_every: float = 0.05, skip: float = 2.0) -> ModeGrowth:
    """Run ``box`` for ``orbits`` sampling U_m every ``sample_every`` orbits; fit after ``skip`` orbits."""
    m = check_int("m", m, 1, 10**6)
    orbits = check_real("orbits", orbits, 1.0, 1e6, unit="orbits")
    skip = check_real("skip", skip, 0.0, orbits - 0.5, unit="orbits")
    nstep = max(1, int(round(sample_every / box.options.dt_orbit)))
    n = int(round(orbits / (nstep * box.options.dt_orbit)))
    t = np.empty(n + 1)
    U = np.empty(n + 1, complex)
    t[0], U[0] = box.t, velocity_mode(box.pos, box.vel, box.L_x, m)
    for j in range(1, n + 1):
        box._advance_steps(nstep)
        t[j], U[j] = box.t, velocity_mode(box.pos, box.vel, box.L_x, m)
    use = (t - t[0]) >= skip * 2.0 * math.pi
    g, w, wl, eg, ew = complex_mode_fit(t[use], U[use])
    return ModeGrowth(m=m, wavelength_m=box.options.L_x / m, growth_rate=g, frequency=w, frequency_lomb=wl,
                      growth_rate_err=eg, frequency_err=ew, t=t[use], amplitude=U[use])
