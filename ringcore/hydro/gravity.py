"""Radial self-gravity of an axisymmetric (1D) ring by FFT.

Two response functions, both applied as a periodic convolution
``g = IFFT[ FFT(s) * G_k ]`` of the dimensionless density s = sigma/sigma0
(eqs. conv, convol, backconvol), giving the force per unit mass -d(phi)/dx in
units of c0 Omega:

``"mode"``  exact Fourier-mode response phi_k = -2 pi G sigma_k/|k| (eq. wkbsg), i.e.
            G_k = i (2/Q0) sign(k) (cf. ``ringcore.linear.matrix``, A0[1, 0]).
``"wire"``  the straight-wire kernel of eq. (kernel), f_{j-l} = -2 G h sigma0 / (x_j - x_l),
            dimensionless K_d = -(2/(pi Q0)) / d for node offset d != 0, summed over
            ``replicas`` extra periodic images on each side of the box (d + m n,
            |m| <= replicas), and optionally the self-bin correction of eq. (cbin),
            +(2/(pi Q0)) h ds/dx with ds/dx from 6th-order central differences.

With infinitely many replicas and the bin correction the wire kernel tends to the
mode response (the discrete sum of 1/d gives the factor 1 - |k| h/pi that eq. cbin
restores).  sigma0 = 0 (1/Q0 = 0) switches self-gravity off.

FFTs use pyfftw (FFTW plans made once per solver with FFTW_ESTIMATE: the plan, and so the
rounding, is the same in every process, which a bit-for-bit restart in a new process needs;
FFTW_MEASURE picks plans by timing and can differ between processes; measured no slower
for n = 1200 and 2000); numpy.fft is the fallback.  This class serves the reference path of
:meth:`ringcore.hydro.Hydro1D.step`; the default one-call step does the same convolution inside
numba (:func:`ringcore.hydro.stepper.gravity_force`, rocket-fft) with the response ``SelfGravity.G``.
"""
from __future__ import annotations

import math
import sys

import numpy as np


def _import_pyfftw():
    """``pyfftw``, or None when it is not installed.

    pyfftw's package imports its dask interface whenever dask is installed (as it is with ringcore): that
    imports ``dask.array``, about 1 s of start-up for every process that imports the hydro engine, for an
    interface ringcore never uses (it calls :class:`pyfftw.FFTW` directly).  ``dask.array.fft`` is hidden for
    that one import (an entry of None in ``sys.modules`` makes pyfftw's ``try: from dask.array.fft import ...``
    fail at once) and restored right after; ``pyfftw.interfaces.dask_fft`` stays importable explicitly.
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

GRAVITY_METHODS = ("mode", "wire")


def wire_kernel(n: int, inv_Q0: float, replicas: int = 0) -> np.ndarray:
    """Real-space wire kernel K_d, d = 0 .. n-1 (offset j - l mod n), dimensionless.

    K_0 = 0 (self-bin excluded, eq. sgsum); the minimal image d' in (-n/2, n/2) plus
    ``replicas`` images on each side; K_{n/2} = 0 by antisymmetry.  References: eq. (kernel).
    """
    d = np.arange(n, dtype=float)
    d = np.where(d < n / 2.0, d, d - n)
    K = np.zeros(n)
    nz = (d != 0) & (np.abs(d) != n / 2.0)
    for m in range(-replicas, replicas + 1):
        K[nz] += 1.0 / (d[nz] + m * n)
    return -(2.0 / math.pi) * inv_Q0 * K


def response(n: int, h: float, inv_Q0: float, method: str = "mode", replicas: int = 0,
             bin_correction: bool = False) -> np.ndarray:
    """Complex response G_k on the rfft frequencies 0 .. n/2 (not normalized by n).

    Parameters
    ----------
    n : int
        Number of nodes.
    h : float
        Node spacing [c0/Omega].
    inv_Q0 : float
        1/Q0 (0: no self-gravity).
    method : {"mode", "wire"}
    replicas : int
        Extra kernel images on each side (wire only).
    bin_correction : bool
        Add the self-bin term of eq. (cbin) (wire only).
    """
    m = np.arange(n // 2 + 1)
    if method == "mode":
        G = 2j * inv_Q0 * np.ones(m.size)
        G[0] = 0.0
        if n % 2 == 0:
            G[-1] = 0.0  # Nyquist mode: sign(k) undefined, its force is dropped
        return G
    G = np.fft.rfft(wire_kernel(n, inv_Q0, replicas))
    if bin_correction:
        th = 2.0 * math.pi * m / n  # k h
        dk = (45.0 * np.sin(th) - 9.0 * np.sin(2 * th) + np.sin(3 * th)) / 30.0  # h * modified k
        G = G + 1j * (2.0 / math.pi) * inv_Q0 * dk
    G[0] = 0.0
    return G


class SelfGravity:
    """Preallocated FFT convolution ``g = -d(phi)/dx`` for one grid.

    Parameters
    ----------
    n, h, inv_Q0, method, replicas, bin_correction
        As in :func:`response`.
    use_pyfftw : bool, optional
        Default: True if pyfftw is importable.

    Notes
    -----
    :meth:`force` allocates nothing when pyfftw is used: the density is copied into
    the aligned input array (minus its first value, so that a uniform state gives an
    exactly zero force), FFTW executes, the spectrum is multiplied in place by the
    cached response / n, and the backward FFTW writes into :attr:`g`.
    """

    def __init__(self, n, h, inv_Q0, method="mode", replicas=0, bin_correction=False, use_pyfftw=None):
        self.n = int(n)
        self.enabled = inv_Q0 != 0.0
        self.G = response(self.n, h, inv_Q0, method, replicas, bin_correction) / self.n
        self.use_pyfftw = HAVE_PYFFTW if use_pyfftw is None else bool(use_pyfftw and HAVE_PYFFTW)
        if self.use_pyfftw:
            self._s = pyfftw.empty_aligned(self.n, dtype="float64")
            self._sk = pyfftw.empty_aligned(self.n // 2 + 1, dtype="complex128")
            self.g = pyfftw.empty_aligned(self.n, dtype="float64")
            flags = ("FFTW_ESTIMATE",)  # deterministic plan: bit-for-bit restarts across processes
            self._fwd = pyfftw.FFTW(self._s, self._sk, direction="FFTW_FORWARD", flags=flags)
            self._bwd = pyfftw.FFTW(self._sk, self.g, direction="FFTW_BACKWARD", flags=flags)
        else:
            self._s = np.empty(self.n)
            self.g = np.empty(self.n)
        self.g[:] = 0.0

    def force(self, sigma: np.ndarray) -> np.ndarray:
        """Force per unit mass at the n nodes for density ``sigma`` (n,); returns :attr:`g`."""
        if not self.enabled:
            return self.g
        np.subtract(sigma, sigma[0], out=self._s)
        if self.use_pyfftw:
            self._fwd.execute()
            np.multiply(self._sk, self.G, out=self._sk)
            self._bwd.execute()
        else:
            self.g[:] = np.fft.irfft(np.fft.rfft(self._s) * self.G, n=self.n) * self.n
        return self.g
