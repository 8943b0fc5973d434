"""Analyses shared by hydro and N-body results (Sections "Tests", "Results", "Saturation Wavelength").

- :mod:`.rates`      growth rate from a log-linear fit, oscillation frequency from the Lomb periodogram
- :mod:`.spectra`    power spectral density and prevalent wavelength lambda_p
- :mod:`.prevalent`  lambda_p of a run by a named method (PSD peak of the last part: the default)
- :mod:`.saturation` empirical lambda_p = C lambda_zero (eq. lambdasigma), eq. (lambdasigmaap) with the
                     sign of eq. (osfreq) (+F2; the paper prints -F2), lambda_zero ~ 2 (p_s + F2) lambda_J,
                     3-point Lagrangian differentiation (Appendix "Group Velocities of Saturated Wave Trains")
"""
from .prevalent import lambda_p
from .rates import Fit, growth_rate, lomb_frequency
from .saturation import lagrange_derivative, lambda_p_approx, lambda_p_empirical, lambda_zero_approx
from .spectra import fourier_amplitudes, power_spectrum, prevalent_mode, prevalent_wavelength

__all__ = ["Fit", "growth_rate", "lomb_frequency", "fourier_amplitudes", "power_spectrum", "prevalent_mode",
           "prevalent_wavelength", "lambda_p_empirical", "lambda_p_approx", "lambda_zero_approx",
           "lagrange_derivative", "lambda_p"]
