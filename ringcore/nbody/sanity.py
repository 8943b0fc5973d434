"""Physical limits of the shearing box: the largest sigma0 it is defined for, and the runaway bounds.

Why: with sigma0 = 1e20 kg/m^2 the self-gravity kick of the first step throws particles
~1e12 R_p out of the box, and the shear-periodic wrap then subtracts L_x one crossing at a
time (hours of a numba loop that never looks at signals); at 1e14 the run "succeeds" with
<c> ~ 500 km/s.  The box therefore refuses such sigma0 up front (:func:`check_sigma0`), and
the integrator stops a run whose state runs away (:data:`X_MAX_BOXES`, :func:`speed_bound`).

References: Eqs. (54), (15); Toomre (1964) for Q.
"""
from __future__ import annotations

import math

from ..units import G

Q_MIN = 0.01  # smallest Toomre parameter (with c = R_p Omega) for which the box is defined
OMEGA_DT_MAX = 1.0  # largest (self-gravity frequency) x (time step) resolved
X_MAX_BOXES = 1000.0  # a particle farther than this many L_x from the box is a runaway
SPEED_SHEAR_FACTOR = 10.0  # runaway: peculiar speed above 10 x the shear speed 1.5 Omega L_x ...
SPEED_FLOOR = 1000.0  # ... and above 1000 R_p Omega


def sigma0_max(R_p: float, Omega: float, L_x: float, m_hi: int, dt: float) -> tuple[float, str]:
    """Largest sigma0 [kg/m^2] the box is defined for, and the condition that sets it.

    Two conditions: (1) the Toomre parameter Q = Omega c / (3.36 G sigma0) with the smallest
    velocity dispersion a dense ring of hard spheres has, c = R_p Omega, must be >= ``Q_MIN``
    (below, self-gravity exceeds everything else a hundredfold: no ring, a collapse); (2) the
    fastest self-gravity oscillation, omega_g^2 = 2 pi G sigma0 k_max (Eq. (15), k_max =
    2 pi m_hi / L_x), must be resolved by the time step: omega_g dt <= ``OMEGA_DT_MAX``.

    Parameters: R_p [m], Omega [1/s], L_x [m], m_hi (highest mode), dt [1/Omega].
    """
    s_toomre = Omega * (R_p * Omega) / (3.36 * G * Q_MIN)
    k_max = 2.0 * math.pi * m_hi / L_x  # [1/m]
    s_dt = (OMEGA_DT_MAX / dt) ** 2 * Omega**2 / (2.0 * math.pi * G * k_max)
    if s_toomre <= s_dt:
        return s_toomre, (f"the Toomre parameter with the smallest hard-sphere dispersion R_p Omega, "
                          f"Q = Omega^2 R_p / (3.36 G sigma0), must be >= {Q_MIN:g}")
    return s_dt, (f"the fastest self-gravity oscillation (2 pi G sigma0 k_max)^(1/2) must be resolved "
                  f"by the time step (omega_g dt <= {OMEGA_DT_MAX:g})")


def check_sigma0(sigma0: float, R_p: float, Omega: float, L_x: float, m_hi: int, dt: float) -> None:
    """ValueError naming sigma0, its value, the allowed range and the physical reason if too large."""
    smax, why = sigma0_max(R_p, Omega, L_x, m_hi, dt)
    if not sigma0 <= smax:
        raise ValueError(f"sigma0 = {sigma0:g} kg/m^2 is out of range for the N-body box: allowed "
                         f"0 <= sigma0 <= {smax:.4g} kg/m^2 ({why})")


def speed_bound(L_x: float) -> float:
    """Runaway peculiar speed [R_p Omega] for a box of ``L_x`` [R_p]: max(10 x 1.5 L_x, 1000).

    Ten times the Keplerian shear across the whole box and at least 1000 R_p Omega (some
    0.2 m/s for metre-sized particles, a hundred times the dispersions of dense rings):
    no local ring state comes near it, a numerical runaway passes it within a few steps.
    """
    return max(SPEED_SHEAR_FACTOR * 1.5 * L_x, SPEED_FLOOR)
