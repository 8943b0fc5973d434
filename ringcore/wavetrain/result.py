"""The :class:`WaveTrain` result object (one periodic nonlinear travelling wave)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..params import RingParams
from ..units import E_KIN_UNIT, e_kin_rp

FIELDS = ("sigma", "u", "v", "T")


@dataclass(frozen=True)
class WaveTrain:
    """A periodic travelling wave U(x - c t) of the hydrodynamic equations.

    Attributes
    ----------
    params : RingParams
    lam : float
        Wavelength, dimensionless [c0/Omega].
    c : float
        Phase speed, dimensionless [c0] (< 0: travels towards -x, like the solver's ``"left"`` mode).
    w : ndarray (nv, N)
        Profiles sigma/sigma0, u/c0, v/c0[, T/c0^2] at x_j = j lam/N (one period).
    residual : float
        Max |F| of the Newton equations at the solution (dimensionless).
    """

    params: RingParams
    lam: float
    c: float
    w: np.ndarray
    residual: float

    @property
    def N(self) -> int:
        """Number of Fourier nodes per wavelength."""
        return self.w.shape[1]

    @property
    def x(self) -> np.ndarray:
        """Node positions, dimensionless [c0/Omega]."""
        return self.lam * np.arange(self.N) / self.N

    @property
    def k(self) -> float:
        """Wavenumber 2 pi/lambda, dimensionless [Omega/c0]."""
        return 2.0 * np.pi / self.lam

    @property
    def wavelength_m(self) -> float:
        """Wavelength [m]."""
        return self.lam * self.params.scales.length

    @property
    def phase_speed_m_s(self) -> float:
        """Phase speed c [m/s] (signed)."""
        return self.c * self.params.c0

    @property
    def frequency(self) -> float:
        """Oscillation frequency |c| k [Omega] (-> omega_I of linear theory at zero amplitude)."""
        return abs(self.c) * self.k

    @property
    def frequency_per_s(self) -> float:
        """Oscillation frequency [1/s]."""
        return self.frequency * self.params.Omega

    @property
    def amplitude(self) -> float:
        """Relative surface-density amplitude (max - min)/2 of sigma/sigma0 (dimensionless)."""
        return 0.5 * float(self.w[0].max() - self.w[0].min())

    @property
    def amplitude_fourier(self) -> float:
        """|2 sigma_1|: the first Fourier amplitude of sigma/sigma0 (dimensionless)."""
        return 2.0 * abs(np.fft.rfft(self.w[0])[1]) / self.N

    @property
    def u_amplitude_m_s(self) -> float:
        """Radial-velocity amplitude (max - min)/2 [m/s]."""
        return 0.5 * float(self.w[1].max() - self.w[1].min()) * self.params.c0

    @property
    def e_kin_dimless(self) -> float:
        """Mean kinetic energy density <sigma (u^2 + v^2)/2>, Eq. (39) [sigma0 c0^2] (dimensionless)."""
        s, u, v = self.w[0], self.w[1], self.w[2]
        return float(np.mean(0.5 * s * (u * u + v * v)))

    @property
    def e_kin(self) -> float:
        """Mean kinetic energy density, Eq. (39), in :data:`ringcore.units.E_KIN_UNIT` (sigma0 (R_p Omega)^2,
        R_p = 1 m), the unit of the engines' e_kin."""
        return float(e_kin_rp(self.e_kin_dimless, self.params.c0, self.params.Omega))

    @property
    def e_kin_si(self) -> float:
        """Mean kinetic energy density [J/m^2] (sigma0 c0^2 e_kin_dimless; 0 if sigma0 = 0)."""
        return self.e_kin_dimless * self.params.sigma0 * self.params.c0**2

    @property
    def spectral_tail(self) -> float:
        """Largest Fourier amplitude in the upper third of the resolved modes, relative to the
        largest non-mean one (a resolution check: small means the profile is resolved)."""
        a = np.abs(np.fft.rfft(self.w, axis=1))[:, 1:]
        top = a.max()
        m = a.shape[1]
        return float(a[:, 2 * m // 3:].max() / top) if top > 0 else 0.0

    def fields(self, x_m):
        """Profiles (nv, len(x_m)) at positions x_m [m] (spectral interpolation, dimensionless values)."""
        x = np.asarray(x_m, float) / self.params.scales.length
        W = np.fft.fft(self.w, axis=1) / self.N
        m = np.fft.fftfreq(self.N, d=1.0 / self.N)
        ph = np.exp(1j * self.k * m[:, None] * x[None, :])
        return (W @ ph).real

    def to_dataset(self):
        """``xarray.Dataset`` of the profiles (SI coordinates) with scalar results and parameters as attributes."""
        import xarray as xr

        p = self.params
        x_m = self.x * p.scales.length
        ds = xr.Dataset(coords={"x": ("x", x_m, {"units": "m", "long_name": "radial position in the wave frame"})})
        units = {"sigma": "sigma0", "u": "m/s", "v": "m/s", "T": "m^2/s^2"}
        scale = {"sigma": 1.0, "u": p.c0, "v": p.c0, "T": p.c0**2}
        for i, name in enumerate(FIELDS[:self.w.shape[0]]):
            ds[name] = ("x", self.w[i] * scale[name], {"units": units[name]})
        ds.attrs.update(dict(
            wavelength_m=self.wavelength_m, phase_speed_m_s=self.phase_speed_m_s,
            frequency_Omega=self.frequency, frequency_per_s=self.frequency_per_s, amplitude=self.amplitude,
            e_kin=self.e_kin, e_kin_units=E_KIN_UNIT, newton_residual=self.residual, n_fourier=self.N,
            spectral_tail=self.spectral_tail, model=p.model, **{f"param_{k}": (str(v) if isinstance(v, (bool, str)) else v)
                              for k, v in p.as_dict().items()}))
        return ds

    def to_json_dict(self) -> dict:
        """Scalar results in SI units (and dimensionless where stated)."""
        return dict(wavelength_m=self.wavelength_m, phase_speed_m_s=self.phase_speed_m_s,
                    frequency_Omega=self.frequency, frequency_per_s=self.frequency_per_s,
                    amplitude_sigma=self.amplitude, amplitude_u_m_s=self.u_amplitude_m_s,
                    e_kin=self.e_kin, e_kin_units=E_KIN_UNIT, newton_residual=self.residual, n_fourier=self.N,
                    spectral_tail=self.spectral_tail)
