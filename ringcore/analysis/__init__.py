"""Analyses shared by hydro and N-body results (Sections 4.1.3, 5, 6): the one
place for growth rates, Lomb frequencies and spectra, used by both engines, the command line, the recipes and the app.

- :mod:`.rates`      :func:`growth_rate` (d ln A/dt [1/unit of t]) from a log-linear fit, :func:`lomb_frequency`
                     (angular frequency [rad per unit of t]) from the Lomb periodogram; both return a :class:`Fit`
                     (value, 1-sigma error); :func:`complex_mode_fit` (growth rate and frequency [Omega] of a
                     rotating complex mode amplitude, the N-body box's growth measurement)
- :mod:`.spectra`    :func:`fourier_amplitudes` (U^m of Eq. (38), unit of the field), :func:`power_spectrum`
                     (wavelength [m], variance per mode [unit of the field squared] or normalised; the one Nyquist
                     convention), :func:`prevalent_wavelength` (lambda_p [m]), :func:`prevalent_mode` (m)
- :mod:`.prevalent`  lambda_p of a run by a named method (PSD peak of the last part: the default)
- :mod:`.saturation` empirical lambda_p = C lambda_zero (Eq. (55)), Eq. (56) with the
                     sign of Eq. (22) (+F2; the paper prints -F2), lambda_zero ~ 2 (p_s + F2) lambda_J,
                     3-point Lagrangian differentiation (Appendix C)
"""
from .prevalent import lambda_p
from .rates import Fit, complex_mode_fit, growth_rate, lomb_frequency
from .saturation import lagrange_derivative, lambda_p_approx, lambda_p_empirical, lambda_zero_approx
from .spectra import fourier_amplitudes, power_spectrum, prevalent_mode, prevalent_wavelength

__all__ = ["Fit", "growth_rate", "lomb_frequency", "complex_mode_fit", "fourier_amplitudes", "power_spectrum", "prevalent_mode",
           "prevalent_wavelength", "lambda_p_empirical", "lambda_p_approx", "lambda_zero_approx",
           "lagrange_derivative", "lambda_p"]
