"""Fields of :class:`~ringcore.hydro.Hydro1D` under names that say their units.

Physical (SI) quantities end in their unit (``sigma_kg_m2``, ``u_m_s``, ``v_m_s``, ``T_m2_s2``, ``x_m``,
``t_s``); the kernels' dimensionless arrays (the paper's scalings, Table 1: sigma in sigma0, u, v in c0,
T in c0^2, x in c0/Omega) end in ``_dimless``.  The older names ``sigma``, ``u``, ``v``, ``T`` and ``x``
(dimensionless) still work and warn once (:func:`ringcore.deprecation.warn_once`).
"""
from __future__ import annotations

import numpy as np

from ..deprecation import warn_once


class PhysicalFields:
    """SI and explicitly dimensionless views of the hydro state (a mixin of :class:`Hydro1D`)."""

    # ------------------------------------------------------------ dimensionless (kernel units)
    @property
    def sigma_dimless(self) -> np.ndarray:
        """Surface density sigma/sigma0 at the nodes, dimensionless (copy)."""
        return self.U[0].copy()

    @property
    def u_dimless(self) -> np.ndarray:
        """Radial velocity u/c0 at the nodes, dimensionless."""
        return self.U[1] / self.U[0]

    @property
    def v_dimless(self) -> np.ndarray:
        """Azimuthal velocity (deviation from the shear) v/c0 at the nodes, dimensionless."""
        return self.U[2] / self.U[0]

    @property
    def T_dimless(self) -> np.ndarray:
        """Granular temperature T/c0^2 at the nodes, dimensionless (T0 everywhere when isothermal)."""
        return self.primitives()[3]

    # ------------------------------------------------------------ SI
    @property
    def sigma_kg_m2(self) -> np.ndarray:
        """Surface density at the nodes [kg/m^2].

        Raises
        ------
        ValueError
            Without self-gravity (``sigma0 = 0``) the model is scale-free in sigma: use :attr:`sigma_dimless`.
        """
        if not self.params.sigma0 > 0:
            raise ValueError(f"sigma0 = {self.params.sigma0!r} kg/m^2: without self-gravity the surface density "
                             "has no SI scale (allowed sigma0 > 0); use sigma_dimless (sigma/sigma0)")
        return self.sigma_dimless * self.params.scales.sigma

    @property
    def u_m_s(self) -> np.ndarray:
        """Radial velocity at the nodes [m/s]."""
        return self.u_dimless * self.params.scales.velocity

    @property
    def v_m_s(self) -> np.ndarray:
        """Azimuthal velocity (deviation from the shear) at the nodes [m/s]."""
        return self.v_dimless * self.params.scales.velocity

    @property
    def T_m2_s2(self) -> np.ndarray:
        """Granular temperature at the nodes [m^2/s^2]."""
        return self.T_dimless * self.params.scales.temperature

    @property
    def t_s(self) -> float:
        """Elapsed time [s] (``orbits`` in orbits, ``t`` dimensionless in 1/Omega)."""
        return self.t * self.params.scales.time

    # ------------------------------------------------------------ deprecated names
    def e_kin_rp(self) -> float:
        """Deprecated: :meth:`e_kin` (the same value: e_kin is in :data:`ringcore.units.E_KIN_UNIT` everywhere)."""
        warn_once("Hydro1D.e_kin_rp()", "Hydro1D.e_kin() (now in sigma0 (R_p Omega)^2, R_p = 1 m)")
        return self.e_kin()

    @property
    def sigma(self) -> np.ndarray:
        """Deprecated: :attr:`sigma_dimless` (sigma/sigma0) or :attr:`sigma_kg_m2`."""
        warn_once("Hydro1D.sigma", "Hydro1D.sigma_dimless (sigma/sigma0) or Hydro1D.sigma_kg_m2")
        return self.sigma_dimless

    @property
    def u(self) -> np.ndarray:
        """Deprecated: :attr:`u_dimless` (u/c0) or :attr:`u_m_s`."""
        warn_once("Hydro1D.u", "Hydro1D.u_dimless (u/c0) or Hydro1D.u_m_s")
        return self.u_dimless

    @property
    def v(self) -> np.ndarray:
        """Deprecated: :attr:`v_dimless` (v/c0) or :attr:`v_m_s`."""
        warn_once("Hydro1D.v", "Hydro1D.v_dimless (v/c0) or Hydro1D.v_m_s")
        return self.v_dimless

    @property
    def T(self) -> np.ndarray:
        """Deprecated: :attr:`T_dimless` (T/c0^2) or :attr:`T_m2_s2`."""
        warn_once("Hydro1D.T", "Hydro1D.T_dimless (T/c0^2) or Hydro1D.T_m2_s2")
        return self.T_dimless

    @property
    def x(self) -> np.ndarray:
        """Deprecated: :attr:`x_dimless` (x Omega/c0) or ``x_m`` [m]."""
        warn_once("Hydro1D.x", "Hydro1D.x_dimless (x Omega/c0) or Hydro1D.x_m [m]")
        return self.x_dimless
