"""Linear eigenvector of the overstable mode, for seeding clean single-mode runs.

References: Eqs. (14), (17).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import ranges
from ..checks import check_choice
from ..params import RingParams, require
from .dispersion import wavelengths_to_k
from .matrix import track_overstable


@dataclass(frozen=True)
class Eigenmode:
    """One overstable eigenmode.

    The real perturbation is ``Re[amplitude * vector * exp(omega t + i s k x)]`` with
    s = +1 for a mode traveling towards -x (``direction="left"``) and s = -1 for one
    traveling towards +x (``"right"``, the mirror image x -> -x, u -> -u, v -> -v).

    Attributes
    ----------
    omega : complex
        Eigenfrequency [Omega].
    k : float
        Dimensionless wavenumber (> 0).
    vector : ndarray of complex, shape (3,) or (4,)
        (sigma/sigma0, u/c0, v/c0[, T/c0^2]) amplitudes, normalized to sigma = 1.
    direction : {"left", "right"}
    """

    omega: complex
    k: float
    vector: np.ndarray
    direction: str

    def fields(self, x, t: float = 0.0, amplitude: float = 1e-4):
        """Real perturbations at dimensionless positions ``x`` and time ``t``.

        Returns an array of shape (n, len(x)): rows d sigma/sigma0, u/c0, v/c0[, dT/c0^2].
        ``amplitude`` is the relative surface-density amplitude.
        """
        s = 1.0 if self.direction == "left" else -1.0
        ph = np.exp(self.omega * t + 1j * s * self.k * np.asarray(x, float))
        return np.real(amplitude * self.vector[:, None] * ph[None, :])


def eigenmode(p: RingParams, wavelength_m: float, direction: str = "left") -> Eigenmode:
    """The overstable eigenmode of wavelength ``wavelength_m`` [m]."""
    require(p)
    wavelength_m = ranges.check("wavelength_m", wavelength_m)
    check_choice("direction", direction, ("left", "right"))
    k = float(wavelengths_to_k(p, wavelength_m))
    om, _, vec = track_overstable(p, np.array([k]))
    v = vec[0] / vec[0][0]
    if direction == "right":
        v = v.copy()
        v[1] = -v[1]
        v[2] = -v[2]
    return Eigenmode(omega=complex(om[0]), k=k, vector=v, direction=direction)
