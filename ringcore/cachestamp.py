"""One numba cache stamp per package of compiled code: an edit of any kernel module invalidates every cached kernel.

numba stamps a cached function with the hash of its own source file only.  A compiled function
carries the code of the compiled functions it calls (and of those inlined into it), so after an
edit of, say, :mod:`ringcore.hydro.kernels` the cached :func:`ringcore.hydro.stepper.ssprk_step` would go on
running the old kernels while freshly compiled callers run the new ones (two code paths would then
silently differ); the same holds for the N-body integrator calling :mod:`ringcore.nbody.kernels`.
A package calls :func:`register` before any of its kernels is compiled or loaded; every function
defined in a registered package is then stamped, besides numba's own stamp, with the SHA-256 of
every module of that package that defines compiled code.  This is done by two cache locators put
in front of numba's own (the user cache directory ``NUMBA_CACHE_DIR`` and the ``__pycache__`` beside
the source); if numba's (internal) locator API changes, numba's per-file stamps stay in force.
"""
from __future__ import annotations

import functools
import hashlib
import os

_PACKAGES: dict[str, tuple] = {}  # directory of a registered package -> its constant modules


@functools.lru_cache(maxsize=None)
def sources_digest(package_dir: str) -> bytes:
    """SHA-256 over the modules of ``package_dir`` that hold compiled code (``njit``) or constants compiled
    into it (the ``constants`` given to :func:`register`), in name order."""
    constants = _PACKAGES.get(package_dir, ())
    h = hashlib.sha256()
    for name in sorted(os.listdir(package_dir)):
        if name.endswith(".py"):
            with open(os.path.join(package_dir, name), "rb") as f:
                src = f.read()
            if b"njit" in src or b"intrinsic" in src or name in constants:
                h.update(name.encode() + b"\0" + src)
    return h.digest()


def register(package_file: str, constants: tuple = ()) -> str:
    """Stamp every compiled function of the package whose ``__init__.py`` (or any module) is ``package_file``.

    ``constants`` names modules without compiled code whose module-level constants numba freezes into the
    kernels (an array layout, say): they are part of the stamp too.  Returns the package directory.  Call it
    before the package's first kernel is compiled or loaded.
    """
    d = os.path.dirname(os.path.abspath(package_file))
    _PACKAGES[d] = tuple(constants)
    sources_digest.cache_clear()
    return d


try:
    from numba.core import caching as _caching

    class _PackageStamp:
        _package_dir = ""

        def get_source_stamp(self):
            return (super().get_source_stamp(), sources_digest(self._package_dir))

        @classmethod
        def from_function(cls, py_func, py_file):
            d = os.path.dirname(os.path.abspath(py_file))
            if d not in _PACKAGES:
                return None
            loc = super().from_function(py_func, py_file)
            if loc is not None:
                loc._package_dir = d
            return loc

    class PackageUserProvidedCacheLocator(_PackageStamp, _caching.UserProvidedCacheLocator):
        """numba's ``NUMBA_CACHE_DIR`` locator with the package-wide stamp."""

    class PackageInTreeCacheLocator(_PackageStamp, _caching.InTreeCacheLocator):
        """numba's ``__pycache__`` locator with the package-wide stamp."""

    _locators = _caching.CacheImpl._locator_classes
    for _cls in (PackageInTreeCacheLocator, PackageUserProvidedCacheLocator):  # user directory first, as numba
        if _cls not in _locators:
            _locators.insert(0, _cls)
    INSTALLED = True
except (ImportError, AttributeError):  # pragma: no cover - another numba: its per-file stamps
    INSTALLED = False
