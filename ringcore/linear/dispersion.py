"""Dispersion curves of the overstable mode in physical and dimensionless units.

References: Eqs. (16), (17), (23), (21), (22); Appendix A.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import ranges
from ..params import RingParams, require
from .matrix import track_overstable


@dataclass(frozen=True)
class Dispersion:
    """The overstable branch at a set of wavelengths.

    Attributes
    ----------
    wavelength_m : ndarray
        Wavelengths [m].
    k : ndarray
        Dimensionless wavenumbers (units Omega/c0).
    omega : ndarray of complex
        omega_R + i omega_I [Omega].
    domega_dk : ndarray of complex
        d omega/dk, dimensionless [c0].
    c0, Omega : float
        Scales [m/s], [1/s].
    """

    wavelength_m: np.ndarray
    k: np.ndarray
    omega: np.ndarray
    domega_dk: np.ndarray
    c0: float
    Omega: float

    @property
    def growth_rate(self) -> np.ndarray:
        """omega_R [Omega] (> 0: overstable)."""
        return self.omega.real

    @property
    def frequency(self) -> np.ndarray:
        """omega_I [Omega]."""
        return self.omega.imag

    @property
    def growth_rate_per_s(self) -> np.ndarray:
        """omega_R [1/s]."""
        return self.omega.real * self.Omega

    @property
    def frequency_per_s(self) -> np.ndarray:
        """omega_I [1/s]."""
        return self.omega.imag * self.Omega

    @property
    def group_velocity(self) -> np.ndarray:
        """v_g = d omega_I / dk [c0], Eq. (23)."""
        return self.domega_dk.imag

    @property
    def group_velocity_m_s(self) -> np.ndarray:
        """v_g [m/s]."""
        return self.domega_dk.imag * self.c0

    @property
    def phase_velocity_strobe(self) -> np.ndarray:
        """Effective stroboscopic phase velocity (omega_I - 1)/k [c0]."""
        return (self.omega.imag - 1.0) / self.k

    @property
    def phase_velocity_strobe_m_s(self) -> np.ndarray:
        """(omega_I - Omega)/k [m/s]: apparent speed in a 1/orbit stroboscopic diagram."""
        return self.phase_velocity_strobe * self.c0

    def to_dataset(self):
        """The branch as an ``xarray.Dataset`` over ``wavelength`` [m], each variable with its ``units``.

        Variables: ``growth_rate_per_s``, ``frequency_per_s`` [1/s]; ``group_velocity_m_s``,
        ``phase_velocity_strobe_m_s`` [m/s]; the dimensionless ``growth_rate``, ``frequency`` [Omega] and
        ``k`` [Omega/c0].  Attributes ``c0_m_s``, ``Omega_per_s``.
        """
        import xarray as xr

        def var(values, units, long_name):
            return ("wavelength", np.asarray(values, float), {"units": units, "long_name": long_name})

        dv = dict(
            growth_rate_per_s=var(self.growth_rate_per_s, "s-1", "growth rate omega_R"),
            frequency_per_s=var(self.frequency_per_s, "s-1", "oscillation frequency omega_I"),
            group_velocity_m_s=var(self.group_velocity_m_s, "m s-1", "group velocity d omega_I / dk"),
            phase_velocity_strobe_m_s=var(self.phase_velocity_strobe_m_s, "m s-1",
                                          "stroboscopic phase velocity (omega_I - Omega)/k"),
            growth_rate=var(self.growth_rate, "Omega (dimensionless)", "growth rate omega_R / Omega"),
            frequency=var(self.frequency, "Omega (dimensionless)", "frequency omega_I / Omega"),
            k=var(self.k, "Omega/c0 (dimensionless)", "wavenumber k c0 / Omega"),
        )
        coords = {"wavelength": ("wavelength", np.asarray(self.wavelength_m, float),
                                 {"units": "m", "long_name": "wavelength"})}
        return xr.Dataset(dv, coords=coords, attrs={"c0_m_s": float(self.c0), "Omega_per_s": float(self.Omega),
                                                    "title": "overstable branch of the linear theory"})


def wavelengths_to_k(p: RingParams, wavelength_m) -> np.ndarray:
    """Dimensionless k of wavelengths in meters (each must be finite and > 0)."""
    require(p)
    if isinstance(wavelength_m, (str, bytes)) or np.asarray(wavelength_m).dtype.kind not in "iuf":
        raise ValueError(f"wavelength_m = {wavelength_m!r} is not valid: give a number or an array of numbers [m]")
    lam = np.asarray(wavelength_m, float)
    r = ranges.get("wavelength_m")
    if lam.size and not np.all((lam >= r.lo) & (lam <= r.hi)):
        bad = lam[~((lam >= r.lo) & (lam <= r.hi))].ravel()[0]
        r.check(float(bad))
    return 2.0 * np.pi / (lam / p.scales.length)


def dispersion(p: RingParams, wavelength_m=None) -> Dispersion:
    """Exact overstable branch of Det[M] = 0 at the given wavelengths.

    Parameters
    ----------
    p : RingParams
        Parameter set (model and sigma0 included).
    wavelength_m : array_like, optional
        Wavelengths [m]; default 400 values log-spaced from 10 m to 10 km.

    Returns
    -------
    Dispersion
    """
    require(p)
    if wavelength_m is None:
        wavelength_m = np.geomspace(10.0, 1.0e4, 400)
    k = wavelengths_to_k(p, wavelength_m)
    lam = np.asarray(wavelength_m, float)
    om, dom, _ = track_overstable(p, k)
    return Dispersion(wavelength_m=lam, k=k, omega=om, domega_dk=dom, c0=p.c0, Omega=p.Omega)


def approx_growth_rate(p: RingParams, k, F3: float | None = None) -> np.ndarray:
    """k^2 approximation of omega_R [Omega], Eq. (21); F3 default from the table (0 if isothermal)."""
    require(p)
    d = p.dimensionless()
    if F3 is None:
        F3 = 0.0 if p.isothermal else p.F3
    k = np.asarray(k, float)
    return (d["nu0"] * (2 + 9 * d["beta"] - 3 * d["gamma"]) / 6.0 + 0.5 * F3) * k**2


def approx_frequency(p: RingParams, k, F2: float | None = None) -> np.ndarray:
    """k^2 approximation of omega_I [Omega], Eq. (22); F2 default from the table (0 if isothermal)."""
    require(p)
    if F2 is None:
        F2 = 0.0 if p.isothermal else p.F2
    q = p.inv_Q0
    k = np.asarray(k, float)
    return 1.0 - q * k + 0.5 * (-q * q + p.p_s + F2) * k**2
