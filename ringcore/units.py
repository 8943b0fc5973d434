"""Physical constants and the paper's dimensionless scalings.

All kernels work in the units of Table 1
(Lehmann, Schmidt & Salo 2017): lengths in ``c0 / Omega``, times in
``1 / Omega``, velocities in ``c0``, surface densities in ``sigma0``,
temperatures in ``c0**2``, pressures in ``sigma0 * c0**2``, kinematic
transport coefficients (``nu0``, ``kappa0``) in ``c0**2 / Omega``.

This module is the only place where physical and dimensionless units meet.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

G = 6.67e-11  # [m^3 kg^-1 s^-2] gravitational constant (paper's value)
M_SATURN = 5.69e26  # [kg] Saturn's mass (paper's value)
OMEGA = 1.948e-4  # [1/s] orbital frequency at r = 1e5 km (paper's value)
ORBIT = 2.0 * math.pi / OMEGA  # [s] one orbital period, ~32,254 s
R_P = 1.0  # [m] particle radius adopted by the paper for e_kin units


@dataclass(frozen=True)
class Scales:
    """Scales that turn a dimensionless kernel quantity into SI units.

    Parameters
    ----------
    c0 : float
        Effective ground-state velocity dispersion [m/s].
    Omega : float
        Orbital frequency [1/s].
    sigma0 : float
        Ground-state surface density [kg/m^2]; 0 means "no self-gravity",
        in which case surface densities stay in units of sigma0 (i.e. the
        model is scale-free in sigma) and ``sigma`` returns 1.
    """

    c0: float  # [m/s]
    Omega: float = OMEGA  # [1/s]
    sigma0: float = 0.0  # [kg/m^2]

    @property
    def length(self) -> float:
        """Length unit c0/Omega [m]."""
        return self.c0 / self.Omega

    @property
    def time(self) -> float:
        """Time unit 1/Omega [s]."""
        return 1.0 / self.Omega

    @property
    def velocity(self) -> float:
        """Velocity unit c0 [m/s]."""
        return self.c0

    @property
    def wavenumber(self) -> float:
        """Wavenumber unit Omega/c0 [1/m]."""
        return self.Omega / self.c0

    @property
    def diffusivity(self) -> float:
        """Unit of kinematic viscosity / heat conductivity, c0^2/Omega [m^2/s]."""
        return self.c0**2 / self.Omega

    @property
    def temperature(self) -> float:
        """Temperature unit c0^2 [m^2/s^2]."""
        return self.c0**2

    @property
    def sigma(self) -> float:
        """Surface-density unit sigma0 [kg/m^2] (1 when sigma0 = 0)."""
        return self.sigma0 if self.sigma0 > 0 else 1.0

    def wavelength_to_k(self, wavelength_m):
        """Dimensionless wavenumber of a wavelength given in meters."""
        return 2.0 * math.pi / (wavelength_m / self.length)

    def k_to_wavelength(self, k):
        """Wavelength [m] of a dimensionless wavenumber."""
        return 2.0 * math.pi / k * self.length


def orbits_to_time(orbits):
    """Dimensionless time (units of 1/Omega) of a number of orbits."""
    return orbits * 2.0 * math.pi


def time_to_orbits(t):
    """Number of orbits of a dimensionless time (units of 1/Omega)."""
    return t / (2.0 * math.pi)


E_KIN_UNIT = "sigma0 (R_p Omega)^2"
"""The public unit of the mean kinetic energy density e_kin, Eq. (39): sigma0 (R_p Omega)^2 with the
paper's R_p = 1 m (its Figure 8 and the N-body box's own unit), the same in Python, on the command line, in run
files and in the app.  The hydro kernels compute e_kin in sigma0 c0^2 (dimensionless); :func:`e_kin_rp`
converts."""


def e_kin_rp(e_kin_dimless, c0: float, Omega: float):
    """e_kin in sigma0 c0^2 (the hydro kernels' dimensionless unit) converted to :data:`E_KIN_UNIT`,
    sigma0 (R_p Omega)^2 with R_p = 1 m.

    Parameters
    ----------
    e_kin_dimless : float or array_like
        e_kin [sigma0 c0^2].
    c0 : float
        Ground-state velocity dispersion [m/s].
    Omega : float
        Orbital frequency [1/s].
    """
    return e_kin_dimless * c0 ** 2 / (R_P * Omega) ** 2


E_KIN_DIMLESS_UNIT = "sigma0 c0^2"
"""The hydro kernels' unit of e_kin (and that of the ``e_kin`` of hydro run files written before
:data:`E_KIN_UNIT` was the one public unit; :func:`e_kin_public` converts them)."""


def e_kin_public(values, units: str, c0: float, Omega: float):
    """e_kin given in ``units`` converted to :data:`E_KIN_UNIT` (how a stored series is read).

    Parameters
    ----------
    values : float or array_like
        e_kin in ``units``.
    units : str
        :data:`E_KIN_UNIT` (also with a suffix such as ", R_p = 1 m": returned unchanged) or
        :data:`E_KIN_DIMLESS_UNIT` (converted with :func:`e_kin_rp`).
    c0 : float
        Ground-state velocity dispersion of the run [m/s].
    Omega : float
        Orbital frequency of the run [1/s].
    """
    u = str(units).strip()
    if u.startswith(E_KIN_UNIT):
        return values
    if u == E_KIN_DIMLESS_UNIT:
        return e_kin_rp(values, c0, Omega)
    raise ValueError(f"units = {units!r} is not valid for e_kin: allowed {E_KIN_UNIT!r} or {E_KIN_DIMLESS_UNIT!r}")
