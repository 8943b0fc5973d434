"""The linear eigenvalue problem Det[M] = 0 of Eq. (17) and its branch tracking.

Perturbations ``(sigma, u, v, T) = ground + amp * exp(omega t + i k x)`` (Eq. (14))
with the self-gravity potential of Eq. (15) give ``omega`` as the eigenvalues
of ``A(k) = A0 + k A1 + k^2 A2`` (Eq. (17) with omega removed from the diagonal).
Everything here is dimensionless (Table 1):
k in Omega/c0, omega in Omega.

The overstable mode is the eigenvalue that starts at ``omega = i`` as k -> 0
(Eq. (19b)).  It is followed in k by continuation: a first-order predictor from
the exact eigenvalue derivative ``d omega/dk = (V^-1 A'(k) V)_jj`` and a
nearest-eigenvalue corrector on a fine logarithmic grid, so that other modes
crossing it in the complex plane at large k cannot make it jump.
"""
from __future__ import annotations

import numpy as np

from ..params import RingParams, require


def coefficient_matrices(p: RingParams):
    """Return ``(A0, A1, A2)`` with ``A(k) = A0 + k A1 + k^2 A2`` (complex, n x n).

    n = 4 (sigma, u, v, T) for the non-isothermal model, 3 (sigma, u, v) for the
    isothermal one.  References: Eq. (17).
    """
    require(p)
    d = p.dimensionless()
    nu0, gam, beta, ps = d["nu0"], d["gamma"], d["beta"], d["p_s"]
    n = 3 if d["isothermal"] else 4
    A0 = np.zeros((n, n), complex)
    A1 = np.zeros((n, n), complex)
    A2 = np.zeros((n, n), complex)
    # continuity
    A1[0, 1] = -1j
    # radial momentum: pressure, self-gravity (2/Q0 from Eq. (15)), viscosity, Coriolis
    A0[1, 0] = 2j * d["inv_Q0"]
    A1[1, 0] = -1j * ps
    A2[1, 1] = -(4.0 / 3.0 + gam) * nu0
    A0[1, 2] = 2.0
    # azimuthal momentum
    A1[2, 0] = -1.5j * (1.0 + beta) * nu0
    A0[2, 1] = -0.5
    A2[2, 2] = -nu0
    if n == 4:
        T0, nT, pT, kap = d["T0"], d["n_T"], d["p_T"], d["kappa0"]
        Gs, GT = d["G_s"], d["G_T"]
        A1[1, 3] = -1j * pT / T0
        A1[2, 3] = -1.5j * nT * nu0 / T0
        A0[3, 0] = 1.5 * (1.0 + beta - Gs) * nu0
        A1[3, 1] = -2.0j / 3.0
        A1[3, 2] = -2.0j * nu0
        A0[3, 3] = -1.5 * nu0 * (GT - nT) / T0
        A2[3, 3] = -2.0 / 3.0 * kap
    return A0, A1, A2


def system_matrix(p: RingParams, k) -> np.ndarray:
    """``A(k)`` for an array of dimensionless wavenumbers k > 0, shape (nk, n, n)."""
    require(p)
    A0, A1, A2 = coefficient_matrices(p)
    k = np.asarray(k, float)[..., None, None]
    return A0 + k * A1 + k * k * A2


def all_modes(p: RingParams, k) -> np.ndarray:
    """All eigenfrequencies omega (units of Omega) at each k, shape (nk, n), unordered."""
    require(p)
    return np.linalg.eigvals(system_matrix(p, k))


def _eig_with_derivative(p: RingParams, k):
    """Eigenvalues, right eigenvectors and d omega/dk of every mode at each k."""
    A0, A1, A2 = coefficient_matrices(p)
    k = np.asarray(k, float)
    A = A0 + k[:, None, None] * A1 + (k * k)[:, None, None] * A2
    w, V = np.linalg.eig(A)
    dA = A1 + 2.0 * k[:, None, None] * A2
    Vinv = np.linalg.inv(V)
    dw = np.einsum("kij,kjl,kli->ki", Vinv, dA, V)
    return w, V, dw


def track_overstable(p: RingParams, k):
    """The overstable branch omega_2(k) at the given wavenumbers.

    Parameters
    ----------
    p : RingParams
    k : array_like
        Dimensionless wavenumbers (> 0), any order.

    Returns
    -------
    omega : ndarray of complex, same shape as k
        omega_R + i omega_I in units of Omega.
    domega_dk : ndarray of complex
        Exact derivative d omega / dk (its imaginary part is the group velocity, Eq. (23)).
    vectors : ndarray, shape k.shape + (n,)
        Right eigenvectors (unnormalized).
    """
    require(p)
    k = np.asarray(k, float)
    if k.size == 0:
        n = 3 if p.isothermal else 4
        return np.zeros(k.shape, complex), np.zeros(k.shape, complex), np.zeros(k.shape + (n,), complex)
    if not np.all(np.isfinite(k)) or np.any(k <= 0):
        raise ValueError("k must be finite and > 0 (dimensionless wavenumbers)")
    flat = k.ravel()
    kmin = min(1e-4, flat.min() * 0.5)
    kmax = flat.max()
    npts = max(64, int(250 * np.log10(kmax / kmin)) + 1)
    grid = np.geomspace(kmin, kmax, npts)
    allk = np.union1d(grid, flat)
    w, V, dw = _eig_with_derivative(p, allk)
    idx = np.empty(allk.size, int)
    # start: omega ~ i (1 - k/Q0) at tiny k (Eq. (19b))
    guess = 1j * (1.0 - allk[0] * p.inv_Q0)
    idx[0] = np.argmin(np.abs(w[0] - guess))
    rows = np.arange(allk.size)
    for i in range(1, allk.size):
        j = idx[i - 1]
        pred = w[i - 1, j] + dw[i - 1, j] * (allk[i] - allk[i - 1])
        idx[i] = np.argmin(np.abs(w[i] - pred))
    pos = np.searchsorted(allk, flat)
    sel = idx[pos]
    om = w[rows[pos], sel]
    dom = dw[rows[pos], sel]
    vec = V[rows[pos], :, sel]
    return om.reshape(k.shape), dom.reshape(k.shape), vec.reshape(k.shape + (V.shape[1],))


def refine_branch(p: RingParams, k, omega_guess):
    """Overstable eigenvalue and derivative at ``k`` nearest to a known nearby value."""
    w, V, dw = _eig_with_derivative(p, np.atleast_1d(float(k)))
    j = np.argmin(np.abs(w[0] - omega_guess))
    return w[0, j], dw[0, j], V[0, :, j]
