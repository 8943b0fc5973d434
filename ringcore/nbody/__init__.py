"""Local N-body shearing box (Section 4.2 of the paper).

>>> from ringcore import params
>>> from ringcore.nbody import ShearingBox, NBodyOptions
>>> box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=50, L_y=25), seed=1)

Modules: :mod:`.kernels` (drift, boundaries, cell list, collisions), :mod:`.gravity`
(Fourier-mode radial self-gravity), :mod:`.integrator` (the step loop, packed parameters), :mod:`.recorder`, :mod:`.sanity` (sigma0 limit, runaway bounds), :mod:`.initial`,
:mod:`.options`, :mod:`.box`, :mod:`.stepping` (the step loop of the box), :mod:`.diagnostics`, :mod:`.store` (NetCDF run files),
:mod:`.growth` (linear mode measurement), :mod:`.bench`.
Kernel units: lengths R_p, times 1/Omega, velocities R_p Omega.
"""
from .. import cachestamp as _cachestamp

# first, before any kernel is compiled or loaded: the integrator's cached step must not keep running old
# kernels after an edit of kernels.py or gravity.py (numba alone stamps a function with its own file)
_cachestamp.register(__file__)

from .box import NBodyBlowUp, ShearingBox  # noqa: E402
from .options import RESTITUTION_LAWS, NBodyOptions  # noqa: E402

__all__ = ["ShearingBox", "NBodyOptions", "NBodyBlowUp", "RESTITUTION_LAWS"]
