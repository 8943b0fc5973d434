"""FFTW inside compiled code: the self-gravity convolution of both hydro step paths.

pyfftw drives FFTW from Python: one call per transform, a few microseconds of Python around a
transform of 800 points that itself takes less than one.  Here the FFTW library that pyfftw loaded is
made visible to numba (``llvmlite.binding.load_library_permanently``), its new-array execute functions
are declared as external functions (``fftw_execute_dft_r2c``, ``fftw_execute_dft_c2r``), and
:func:`convolve` runs the whole convolution -- subtraction, forward transform, product with the response,
backward transform -- in one compiled call that :func:`ringcore.hydro.stepper.ssprk_step` calls at every
stage.  The symbols are resolved by name when the code is linked, so the compiled code caches like any
other kernel.

The plans are made here too (:class:`RealPlans`), with the flags pyfftw's :class:`pyfftw.FFTW` uses for
these transforms (``FFTW_ESTIMATE | FFTW_PRESERVE_INPUT``) on arrays of pyfftw's SIMD alignment: FFTW
chooses the same algorithm, so the transforms are pyfftw's, bit for bit (``tests/core/test_hydro_fftw.py``),
and ``FFTW_ESTIMATE`` chooses it without timing anything, so every process chooses it alike (restarts in a new
process continue bit for bit).  The product with the response rounds once per operation on every processor;
numpy's complex multiply, which the reference path used before, fuses multiply and add where the processor
can (AVX-512 here): with the default "mode" response (purely imaginary) both give the same bits, with the
"wire" response the last bits differ (2.6e-15 relative after five orbits of a 1-km box).  FFTW's planner is not
thread-safe: every plan is made and destroyed under :data:`PLAN_LOCK` (the app builds solvers in several
threads; ringcore makes no plan through pyfftw's own lock).

Without the library (pyfftw missing) :data:`HAVE_FFTW` is False and the solver takes its reference path
with ``numpy.fft``.

References: Eqs. (44), (46), (47).
"""
from __future__ import annotations

import ctypes
import glob
import os
import re
import sys
import threading
import weakref

from numba import njit, types

FFTW_ESTIMATE = 1 << 6
FFTW_PRESERVE_INPUT = 1 << 4
PLAN_FLAGS = FFTW_ESTIMATE | FFTW_PRESERVE_INPUT  # as pyfftw.FFTW plans r2c and one-dimensional c2r
PLAN_LOCK = threading.RLock()  # re-entrant: a finalizer may destroy plans while this thread plans


def _import_pyfftw():
    """``pyfftw``, or None when it is not installed.

    pyfftw's package imports its dask interface whenever dask is installed (as it is with ringcore): that
    imports ``dask.array``, about 1 s of start-up for every process that imports the hydro engine, for an
    interface ringcore never uses.  ``dask.array.fft`` is hidden for that one import (an entry of None in
    ``sys.modules`` makes pyfftw's ``try: from dask.array.fft import ...`` fail at once) and restored right
    after; ``pyfftw.interfaces.dask_fft`` stays importable explicitly.
    """
    hide = "dask.array.fft" not in sys.modules
    if hide:
        sys.modules["dask.array.fft"] = None
    try:
        import pyfftw
    except ImportError:  # pragma: no cover - pyfftw is a dependency
        return None
    finally:
        if hide and sys.modules.get("dask.array.fft", 0) is None:
            del sys.modules["dask.array.fft"]
    return pyfftw


pyfftw = _import_pyfftw()
HAVE_PYFFTW = pyfftw is not None
_NAME = re.compile(r"[/\\]libfftw3(-[0-9a-f]+)?(\.[0-9]+)*\.(so|dylib|dll)[.0-9]*$")  # double precision (not fftw3f/l/_omp)


def library_path() -> str | None:
    """Path of the double-precision FFTW library pyfftw uses (the one its extension loaded), or None."""
    if not HAVE_PYFFTW:
        return None
    try:  # Linux: the library the extension module actually loaded
        with open("/proc/self/maps") as f:
            for line in f:
                path = line.rstrip("\n").split(" ")[-1]
                if _NAME.search(path):
                    return path
    except OSError:
        pass
    here = os.path.dirname(pyfftw.__file__)  # wheels: auditwheel's pyfftw.libs, delocate's .dylibs, Windows' DLL
    for pattern in ("../pyfftw.libs/libfftw3-*.so*", ".dylibs/libfftw3.*dylib", "libfftw3-3.dll"):
        found = [p for p in glob.glob(os.path.join(here, pattern)) if _NAME.search(p)]
        if found:
            return os.path.realpath(found[0])
    return None


def _load():
    """ctypes handle of the library, its symbols made visible to numba's linker; None if not found."""
    path = library_path()
    if path is None:
        return None
    try:
        import llvmlite.binding as llvm

        llvm.load_library_permanently(path)
        lib = ctypes.CDLL(path)
    except (OSError, RuntimeError):  # pragma: no cover - a broken installation: the reference path
        return None
    for name in ("fftw_plan_dft_r2c_1d", "fftw_plan_dft_c2r_1d"):
        fn = getattr(lib, name)
        fn.restype = ctypes.c_void_p
        fn.argtypes = [ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_uint]
    lib.fftw_destroy_plan.restype = None
    lib.fftw_destroy_plan.argtypes = [ctypes.c_void_p]
    return lib


_lib = _load()
HAVE_FFTW = _lib is not None
LIBRARY = library_path() if HAVE_FFTW else None

_r2c = types.ExternalFunction("fftw_execute_dft_r2c", types.void(types.intp, types.voidptr, types.voidptr))
_c2r = types.ExternalFunction("fftw_execute_dft_c2r", types.void(types.intp, types.voidptr, types.voidptr))


def _destroy(*plans: int) -> None:
    with PLAN_LOCK:
        for p in plans:
            _lib.fftw_destroy_plan(p)


class RealPlans:
    """A forward real and a backward complex-to-real FFTW plan of length ``n`` with their own arrays.

    Attributes
    ----------
    s : (n,) float64
        Input of the forward transform (the density minus its first value).
    sk : (n//2+1,) complex128
        Spectrum.
    g : (n,) float64
        Output of the backward transform (unnormalised).
    forward, backward : int
        The plans' addresses, for :func:`convolve` (valid while this object lives).

    Notes
    -----
    The plans may only be executed on these arrays (FFTW's new-array execute needs the alignment the
    plans were made for): :func:`convolve` is given them together.  A copy or a pickle makes new plans.
    """

    def __init__(self, n: int):
        if not HAVE_FFTW:
            raise RuntimeError("the FFTW library of pyfftw was not found: use numpy.fft (ringcore.hydro.gravity)")
        self.n = int(n)
        self.s = pyfftw.empty_aligned(self.n, dtype="float64")
        self.sk = pyfftw.empty_aligned(self.n // 2 + 1, dtype="complex128")
        self.g = pyfftw.empty_aligned(self.n, dtype="float64")
        self.s[:] = 0.0
        self.sk[:] = 0.0
        self.g[:] = 0.0
        with PLAN_LOCK:
            fwd = _lib.fftw_plan_dft_r2c_1d(self.n, self.s.ctypes.data, self.sk.ctypes.data, PLAN_FLAGS)
            bwd = _lib.fftw_plan_dft_c2r_1d(self.n, self.sk.ctypes.data, self.g.ctypes.data, PLAN_FLAGS)
        if not fwd or not bwd:  # pragma: no cover - FFTW_ESTIMATE always finds a plan
            _destroy(*[p for p in (fwd, bwd) if p])
            raise RuntimeError(f"FFTW made no plan for n = {self.n}")
        self.forward, self.backward = int(fwd), int(bwd)
        weakref.finalize(self, _destroy, self.forward, self.backward)

    def __reduce__(self):
        return (RealPlans, (self.n,))


@njit(nogil=True, cache=True, error_model="numpy")
def convolve(sigma, forward, backward, G, s, sk, g):
    """``g = IFFT[FFT(sigma - sigma[0]) G]`` with the plans of a :class:`RealPlans` (unnormalised
    backward transform; ``G`` holds the response divided by n).

    Parameters
    ----------
    sigma : (n,) float64
        Dimensionless surface density at the interior nodes.
    forward, backward : int
        ``RealPlans.forward``, ``RealPlans.backward``.
    G : (n//2+1,) complex128
        Response divided by n (``SelfGravity.G``).
    s, sk, g : arrays of the same :class:`RealPlans`
        Scratch, scratch spectrum and the output: force per unit mass [c0 Omega].
    """
    n = sigma.shape[0]
    s0 = sigma[0]
    for i in range(n):
        s[i] = sigma[i] - s0  # a uniform state gives an exactly zero force
    _r2c(forward, s.ctypes.data, sk.ctypes.data)
    for i in range(sk.shape[0]):
        sk[i] = sk[i] * G[i]
    _c2r(backward, sk.ctypes.data, g.ctypes.data)
