"""Floquet-Bloch stability of a wave train.

Perturbations exp(i q x) phi(x) exp(mu t), phi periodic with the wave train's wavelength, in the
frame moving with the wave: mu are the eigenvalues of the dense linearised operator of
:func:`ringcore.wavetrain.model.linear_operator` (computed with LAPACK's dense eigen-solver).
q runs over the half Brillouin zone 0 <= q <= k/2 (mu(-q) = conj mu(q)).

Neutral modes.  At q = 0 the symmetries of the shearing sheet give exactly neutral modes: the
translation of the wave (mu = 0), the change of the mean density along the family (mu = 0) and the
epicyclic oscillation of the whole sheet (mu = +-i Omega, the Galilean boost of the shearing sheet).
They are excluded at q = 0 only (the NEUTRAL ones nearest 0, 0, i, -i, within ``NEUTRAL_TOL``); for
q > 0 every mode counts, so a long-wave (Eckhaus-type) instability, whose growth rate grows like q^2
from these neutral modes, is seen at the small q of the sampling.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .model import Grid, Model, linear_operator
from .result import WaveTrain

NEUTRAL_TOL = 1e-6  # [Omega] distance of a q = 0 eigenvalue from 0 or +-i to count as a symmetry mode
DEFAULT_Q = (0.0, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5)  # q / k
COARSE_Q = (0.0, 0.01, 0.1, 0.3, 0.5)  # q / k tried first on a stability scan (boundary.py)


@dataclass(frozen=True)
class FloquetSpectrum:
    """Floquet exponents of one wave train.

    Attributes
    ----------
    q_over_k : ndarray (nq,)
        Bloch wavenumbers as fractions of the wave's k (dimensionless).
    mu : ndarray (nq, nv N) complex
        Exponents [Omega]: Re = growth rate, Im = frequency in the wave frame.
    growth_per_q : ndarray (nq,)
        Largest growth rate at each q [Omega], the neutral modes excluded at q = 0.
    """

    q_over_k: np.ndarray
    mu: np.ndarray
    growth_per_q: np.ndarray

    @property
    def growth_rate(self) -> float:
        """Largest growth rate over all sampled q [Omega] (> 0: unstable)."""
        return float(self.growth_per_q.max())

    @property
    def q_max_over_k(self) -> float:
        """q/k of the fastest-growing perturbation."""
        return float(self.q_over_k[int(np.argmax(self.growth_per_q))])


def _drop_neutral(mu):
    keep = np.ones(mu.size, bool)
    for target in (0.0, 0.0, 1j, -1j):
        d = np.abs(mu - target)
        d[~keep] = np.inf
        i = int(np.argmin(d))
        if d[i] < NEUTRAL_TOL:
            keep[i] = False
    return mu[keep]


def floquet(train: WaveTrain, q_over_k=DEFAULT_Q) -> FloquetSpectrum:
    """Floquet-Bloch spectrum of ``train`` at Bloch wavenumbers q = q_over_k * k.

    Parameters
    ----------
    train : WaveTrain
    q_over_k : sequence of float
        Values in [0, 1/2].
    """
    q_over_k = np.asarray(q_over_k, float)
    if np.any((q_over_k < 0) | (q_over_k > 0.5)) or q_over_k.size == 0:
        raise ValueError(f"q_over_k = {q_over_k.tolist()} is not valid: allowed values 0 <= q/k <= 1/2")
    model = Model(train.params)
    grid = Grid(train.N, train.lam, model.inv_Q0)
    mus, growth = [], []
    for f in q_over_k:
        M = linear_operator(model, grid, train.w, train.c, q=float(f * train.k))
        mu = scipy.linalg.eigvals(M, overwrite_a=True, check_finite=False).astype(complex)
        mus.append(mu)
        g = _drop_neutral(mu) if f == 0.0 else mu
        growth.append(float(g.real.max()))
    return FloquetSpectrum(q_over_k=q_over_k, mu=np.array(mus), growth_per_q=np.array(growth))


def most_unstable_mode(train: WaveTrain, q_over_k: float):
    """Fastest-growing Floquet mode at one Bloch wavenumber q = q_over_k * k.

    Returns
    -------
    mu : complex
        Exponent [Omega] (neutral symmetry modes excluded at q = 0 are not excluded here).
    phi : ndarray (nv, N) complex
        Periodic factor of the perturbation exp(i q x) phi(x) on the wave train's nodes, normalised to
        max |phi_sigma| = 1.
    """
    model = Model(train.params)
    grid = Grid(train.N, train.lam, model.inv_Q0)
    M = linear_operator(model, grid, train.w, train.c, q=float(q_over_k * train.k))
    mu, vec = scipy.linalg.eig(M)
    i = int(np.argmax(mu.real))
    phi = vec[:, i].reshape(model.nv, train.N)
    return complex(mu[i]), phi / phi[0][np.argmax(np.abs(phi[0]))]
