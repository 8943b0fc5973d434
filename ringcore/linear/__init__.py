"""Exact linear theory of viscous overstability (Section 2 of the paper).

>>> from ringcore import params, linear
>>> p = params.get("tau15", sigma0=400)
>>> d = linear.dispersion(p, [100.0, 200.0])
>>> d.growth_rate, d.frequency            # in units of Omega
>>> linear.summary(p).lambda_zero_m       # [m]

References: Eqs. (16), (17), (19b), (21), (22), (23).
"""
from .dispersion import Dispersion, approx_frequency, approx_growth_rate, dispersion, wavelengths_to_k
from .eigenmode import Eigenmode, eigenmode
from .features import (LinearSummary, beta_c, beta_c_approx, lambda_zero, max_growth, overstable_band,
                       small_k_coefficients, summary, thermal_coefficients, with_thermal_coefficients)
from .matrix import all_modes, coefficient_matrices, system_matrix, track_overstable

__all__ = [
    "Dispersion", "dispersion", "approx_frequency", "approx_growth_rate", "wavelengths_to_k",
    "Eigenmode", "eigenmode", "LinearSummary", "summary", "beta_c", "beta_c_approx", "lambda_zero",
    "max_growth", "overstable_band", "small_k_coefficients", "thermal_coefficients",
    "with_thermal_coefficients", "all_modes", "coefficient_matrices", "system_matrix", "track_overstable",
]
