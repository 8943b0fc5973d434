"""Periodic nonlinear wave trains of the hydrodynamic model and their Floquet-Bloch stability.

>>> from ringcore import params, wavetrain
>>> p = params.get("tau15", isothermal=True)
>>> br = wavetrain.compute_branch(p, lam_max_m=400.0)          # doctest: +SKIP
>>> wavetrain.stability_boundary(p).lambda_st_m               # doctest: +SKIP

References: Eqs. (1), (8)-(11), (15); Section 5.1.1 (LO2009's lambda_st).
"""
from .branch import Branch, compute_branch, neutral_wavelength, solve_at
from .model import Grid, Model, linear_operator, residual
from .newton import NewtonFailure
from .result import WaveTrain

__all__ = ["Branch", "compute_branch", "neutral_wavelength", "solve_at", "Grid", "Model", "linear_operator",
           "residual", "NewtonFailure", "WaveTrain"]
from .boundary import StabilityBoundary, stability_boundary  # noqa: E402
from .floquet import FloquetSpectrum, floquet  # noqa: E402

__all__ += ["StabilityBoundary", "stability_boundary", "FloquetSpectrum", "floquet"]
