"""Particles of :class:`~ringcore.nbody.ShearingBox` under names that say their units.

The kernel arrays ``pos`` and ``vel`` are in the box's units (lengths R_p, velocities R_p Omega, shear
included; ``pos_dimless`` and ``vel_dimless`` name them explicitly); ``pos_m`` [m], ``vel_m_s`` [m/s] and
``t_s`` [s] are the same in SI units.
"""
from __future__ import annotations

import numpy as np


class PhysicalParticles:
    """SI and explicitly dimensionless views of the particles (a mixin of :class:`ShearingBox`)."""

    @property
    def pos_dimless(self) -> np.ndarray:
        """Particle positions (N, 3) (x, y, z) in R_p, dimensionless (the kernel array itself)."""
        return self.pos

    @property
    def vel_dimless(self) -> np.ndarray:
        """Particle Hill velocities (N, 3) in R_p Omega, shear included, dimensionless (the kernel array itself)."""
        return self.vel

    @property
    def pos_m(self) -> np.ndarray:
        """Particle positions (N, 3) (x radial, y azimuthal, z vertical) [m] (copy)."""
        return self.pos * self.options.R_p

    @property
    def vel_m_s(self) -> np.ndarray:
        """Particle Hill velocities (N, 3) [m/s], shear included (copy)."""
        return self.vel * (self.options.R_p * self.params.Omega)

    @property
    def t_s(self) -> float:
        """Elapsed time [s] (``orbits`` in orbits, ``t`` dimensionless in 1/Omega)."""
        return self.t / self.params.Omega
