"""One numba cache stamp for all compiled hydro code: an edit of any kernel module invalidates every cached kernel.

numba stamps a cached function with the hash of its own source file only.  A compiled function
carries the code of the compiled functions it calls (and of those inlined into it), so after an
edit of :mod:`ringcore.hydro.kernels` the cached :func:`ringcore.hydro.stepper.ssprk_step` would go on running
the old kernels while freshly compiled callers run the new ones (the fast and reference paths
would then silently differ).  This module adds the SHA-256 of every module of this package that
defines compiled code to the stamp of each function defined in the package, through two cache
locators put in front of numba's own (the user cache directory ``NUMBA_CACHE_DIR`` and the
``__pycache__`` beside the source).  Imported first by :mod:`ringcore.hydro`, before any kernel is
compiled or loaded; if numba's (internal) locator API changes, numba's own per-file stamps stay
in force.
"""
from __future__ import annotations

import functools
import hashlib
import os

HERE = os.path.dirname(os.path.abspath(__file__))
# modules without compiled code whose constants numba freezes into the kernels (the array layout)
CONSTANT_MODULES = ("layout.py",)


@functools.lru_cache(maxsize=1)
def kernel_sources_digest() -> bytes:
    """SHA-256 over the modules of this package that hold compiled code (``njit``) or the constants
    compiled into it (:data:`CONSTANT_MODULES`), in name order."""
    h = hashlib.sha256()
    for name in sorted(os.listdir(HERE)):
        if name.endswith(".py"):
            with open(os.path.join(HERE, name), "rb") as f:
                src = f.read()
            if b"njit" in src or b"intrinsic" in src or name in CONSTANT_MODULES:
                h.update(name.encode() + b"\0" + src)
    return h.digest()


def _in_package(py_file) -> bool:
    return os.path.dirname(os.path.abspath(py_file)) == HERE


try:
    from numba.core import caching as _caching

    class _PackageStamp:
        def get_source_stamp(self):
            return (super().get_source_stamp(), kernel_sources_digest())

        @classmethod
        def from_function(cls, py_func, py_file):
            return super().from_function(py_func, py_file) if _in_package(py_file) else None

    class HydroUserProvidedCacheLocator(_PackageStamp, _caching.UserProvidedCacheLocator):
        """numba's ``NUMBA_CACHE_DIR`` locator with the package-wide stamp."""

    class HydroInTreeCacheLocator(_PackageStamp, _caching.InTreeCacheLocator):
        """numba's ``__pycache__`` locator with the package-wide stamp."""

    _locators = _caching.CacheImpl._locator_classes
    for _cls in (HydroInTreeCacheLocator, HydroUserProvidedCacheLocator):  # user directory first, as numba
        if _cls not in _locators:
            _locators.insert(0, _cls)
    INSTALLED = True
except (ImportError, AttributeError):  # pragma: no cover - another numba: its per-file stamps
    INSTALLED = False
