"""1D axisymmetric shearing-sheet hydrodynamics (Section 4.1).

>>> from ringcore import params
>>> from ringcore.hydro import Hydro1D, HydroOptions
>>> sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=5000, h=2.5), initial="noise", seed=1)
>>> sim.advance(orbits=100, progress=True)           # doctest: +SKIP
>>> sim.save("run.nc")                                # doctest: +SKIP
>>> sim = Hydro1D.load("run.nc"); sim.advance(orbits=100)   # continues bit-for-bit  # doctest: +SKIP

``Hydro1D`` is a :class:`ringcore.engine.Engine` (snapshot/restore, advance, on_sample, diagnostics()).

Modules: :mod:`.kernels` (compiled MP5 / AUSM / central differences / RK stage), :mod:`.layout` (their array
layout), :mod:`.state_kernels` (ghosts, state check, temperature floor),
:mod:`.gravity` (FFT self-gravity), :mod:`.timestep` (SSPRK(5,4), dt criteria),
:mod:`.convert` (conservative <-> primitive), :mod:`.initial`, :mod:`.options`, :mod:`.solver`, :mod:`.stepping` (the step and ``advance``),
:mod:`.state_io` (State in and out), :mod:`.diagnostics`, :mod:`.runfile` (State <-> run file), :mod:`.bench`,
:mod:`.mp5` (MP5 reconstruction), :mod:`.stepper` (a whole step in one compiled call), :mod:`.frame` (what a
live view draws, as one value), :mod:`.cachestamp`
(one numba cache stamp for all hydro kernels).
"""
from . import cachestamp  # noqa: F401  (first: the package-wide numba cache stamp, before any kernel)
from .diagnostics import e_kin_dimless
from .diagnostics import e_kin, growth_rate, lomb_frequency, prevalent_wavelength, psd  # noqa: F401 (deprecated)
from .gravity import SelfGravity
from .options import HydroOptions
from .solver import Hydro1D, HydroBlowUp

# e_kin, psd, prevalent_wavelength, growth_rate, lomb_frequency: deprecated (they warn once); spectra, lambda_p,
# growth rates and Lomb frequencies are ringcore.analysis's
__all__ = ["Hydro1D", "HydroOptions", "HydroBlowUp", "SelfGravity", "e_kin_dimless"]
