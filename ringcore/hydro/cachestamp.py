"""The package-wide numba cache stamp (:mod:`ringcore.cachestamp`) for all compiled hydro code.

Imported first by :mod:`ringcore.hydro`, before any kernel is compiled or loaded: a cached
:func:`ringcore.hydro.stepper.ssprk_step` must not keep running old kernels after an edit of
``kernels.py`` or ``mp5.py``.
"""
from __future__ import annotations

from .. import cachestamp as _stamp

# modules without compiled code whose constants numba freezes into the kernels (the array layout)
CONSTANT_MODULES = ("layout.py",)
HERE = _stamp.register(__file__, constants=CONSTANT_MODULES)
INSTALLED = _stamp.INSTALLED


def kernel_sources_digest() -> bytes:
    """SHA-256 over the modules of this package that hold compiled code (``njit``) or the constants
    compiled into it (:data:`CONSTANT_MODULES`), in name order."""
    return _stamp.sources_digest(HERE)
