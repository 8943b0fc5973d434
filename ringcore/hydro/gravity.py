"""Radial self-gravity of an axisymmetric (1D) ring by FFT.

Two response functions, both applied as a periodic convolution
``g = IFFT[ FFT(s) * G_k ]`` of the dimensionless density s = sigma/sigma0
(Eqs. (44), (46), (47)), giving the force per unit mass -d(phi)/dx in
units of c0 Omega:

``"mode"``  exact Fourier-mode response phi_k = -2 pi G sigma_k/|k| (Eq. (15)), i.e.
            G_k = i (2/Q0) sign(k) (cf. ``ringcore.linear.matrix``, A0[1, 0]).
``"wire"``  the straight-wire kernel of Eq. (45), f_{j-l} = -2 G h sigma0 / (x_j - x_l),
            dimensionless K_d = -(2/(pi Q0)) / d for node offset d != 0, summed over
            ``replicas`` extra periodic images on each side of the box (d + m n,
            |m| <= replicas), and optionally the self-bin correction of Eq. (43),
            +(2/(pi Q0)) h ds/dx with ds/dx from 6th-order central differences.

With infinitely many replicas and the bin correction the wire kernel tends to the
mode response (the discrete sum of 1/d gives the factor 1 - |k| h/pi that Eq. (43)
restores).  sigma0 = 0 (1/Q0 = 0) switches self-gravity off.

FFTs use FFTW (the library pyfftw ships) from compiled code, with plans made once per solver with
FFTW_ESTIMATE (:mod:`ringcore.hydro.fftw`): the plan, and so the rounding, is the same in every process, which a
bit-for-bit restart in a new process needs (FFTW_MEASURE picks plans by timing and can differ between
processes); numpy.fft is the fallback without pyfftw.  Both step paths of :class:`ringcore.hydro.Hydro1D` use
this convolution (:func:`ringcore.hydro.fftw.convolve`), so they agree bit for bit.
"""
from __future__ import annotations

import math

import numpy as np

from .fftw import HAVE_FFTW, HAVE_PYFFTW, RealPlans, convolve, pyfftw  # noqa: F401 (re-exported)

GRAVITY_METHODS = ("mode", "wire")


def wire_kernel(n: int, inv_Q0: float, replicas: int = 0) -> np.ndarray:
    """Real-space wire kernel K_d, d = 0 .. n-1 (offset j - l mod n), dimensionless.

    K_0 = 0 (self-bin excluded, Eq. (42)); the minimal image d' in (-n/2, n/2) plus
    ``replicas`` images on each side; K_{n/2} = 0 by antisymmetry.  References: Eq. (45).
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
        Add the self-bin term of Eq. (43) (wire only).
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
        Use FFTW (:mod:`ringcore.hydro.fftw`); default: True if its library was found.  False: numpy.fft.

    Attributes
    ----------
    G : (n//2+1,) complex128
        The response divided by n.
    g : (n,) float64
        The force of the last :meth:`force` call [c0 Omega].
    kernel_args : tuple
        ``(forward, backward, G, s, sk, g)`` for :func:`ringcore.hydro.fftw.convolve` inside compiled code
        (FFTW only).

    Notes
    -----
    :meth:`force` allocates nothing with FFTW: one compiled call subtracts the first value of the density
    (so that a uniform state gives an exactly zero force), transforms, multiplies by the cached response / n
    and transforms back into :attr:`g`.  A copy or a pickle makes its own plans.
    """

    def __init__(self, n, h, inv_Q0, method="mode", replicas=0, bin_correction=False, use_pyfftw=None):
        self._args = (n, h, inv_Q0, method, replicas, bin_correction, use_pyfftw)
        self.n = int(n)
        self.enabled = inv_Q0 != 0.0
        self.G = response(self.n, h, inv_Q0, method, replicas, bin_correction) / self.n
        self.use_pyfftw = HAVE_FFTW if use_pyfftw is None else bool(use_pyfftw and HAVE_FFTW)
        if self.use_pyfftw:
            self._plans = pl = RealPlans(self.n)
            self.g = pl.g
            self.kernel_args = (pl.forward, pl.backward, self.G, pl.s, pl.sk, pl.g)
        else:
            self.g = np.zeros(self.n)
            self.kernel_args = None

    def __reduce__(self):
        return (SelfGravity, self._args)

    def force(self, sigma: np.ndarray) -> np.ndarray:
        """Force per unit mass at the n nodes for density ``sigma`` (n,); returns :attr:`g`."""
        if not self.enabled:
            return self.g
        sigma = np.ascontiguousarray(sigma, dtype=float)
        if sigma.shape != (self.n,):
            raise ValueError(f"sigma has shape {sigma.shape}: give the density at the n = {self.n} nodes")
        if self.use_pyfftw:
            convolve(sigma, *self.kernel_args)
        else:
            s = sigma - sigma[0]
            self.g[:] = np.fft.irfft(np.fft.rfft(s) * self.G, n=self.n) * self.n
        return self.g
