"""The hydrodynamic equations of :class:`ringcore.hydro.Hydro1D` in primitive form, Fourier-discretised.

The solver integrates Eq. (1) in conservative form (Eq. (26)); here the same equations are written
for the primitive fields w = (sigma, u, v[, T]) in the paper's dimensionless units (sigma in sigma0,
u, v in c0, T in c0^2, x in c0/Omega, t in 1/Omega):

    sigma_t = -(sigma u)_x
    u_t = -u u_x - p_x/sigma + 2 v + g + (Pi_xx)_x/sigma
    v_t = -u v_x - u/2 + (Pi_xy)_x/sigma
    T_t = -u T_x + 2/(3 sigma) [-p u_x + Pi_xx u_x + Pi_xy (v_x - 3/2) - Gamma + (kappa_D T_x)_x]

with p = sigma^p_s (T/T0)^p_T, eta = nu0 sigma^(beta+1) (T/T0)^n_T, Pi_xx = (4/3 + gamma) eta u_x,
Pi_xy = eta (v_x - 3/2), Gamma = Gamma0 sigma^G_s (T/T0)^G_T, kappa_D = (kappa0/nu0) eta (Eqs. (8)-
(11), (5)) and g = -d(phi)/dx the radial self-gravity of the solver's ``"mode"`` response
g_k = 2 i sign(k) sigma_k / Q0 (Eq. (15)).  Isothermal: 3 fields, p = sigma^p_s.

The continuity equation stays in flux form, so the mean of sigma is conserved exactly by the
discretisation.  Everything except the flux term is a pointwise function of (w, w_x, w_xx, g); its
derivatives come from complex steps (exact to rounding), giving the linearised operator
``A0 + A1 D + A2 D^2 + A_g G + D B`` for any Bloch wavenumber q (D -> D + i q).

References: Eqs. (1), (8)-(11), (5), (15).
"""
from __future__ import annotations

import numpy as np

from ..params import RingParams

_CSTEP = 1e-30  # complex step: derivative = Im f(x + i h)/h, exact to rounding


class Model:
    """Dimensionless coefficients of one parameter set and the pointwise right-hand side.

    Parameters
    ----------
    p : RingParams
        Parameter set (model, p_s and sigma0 included; sigma0 = 0: no self-gravity).
    """

    def __init__(self, p: RingParams):
        d = p.dimensionless()
        self.params = p
        self.isothermal = bool(d["isothermal"])
        self.nv = 3 if self.isothermal else 4
        self.nu0, self.ps, self.beta = d["nu0"], d["p_s"], d["beta"]
        self.bulk = d["gamma"] + 4.0 / 3.0
        self.inv_Q0 = d["inv_Q0"]
        if not self.isothermal:
            self.T0, self.pT, self.nT = d["T0"], d["p_T"], d["n_T"]
            self.Gs, self.GT, self.Gamma0 = d["G_s"], d["G_T"], d["Gamma0"]
            self.kr = d["kappa0"] / d["nu0"]

    def ground(self) -> np.ndarray:
        """Ground state (nv,): sigma = 1, u = v = 0[, T = T0]."""
        return np.array([1.0, 0.0, 0.0] + ([] if self.isothermal else [self.T0]))

    def pointwise(self, w, wx, wxx, g):
        """Non-flux part of the time derivatives, shape (nv, N) (row 0, continuity, is zero).

        Works on real or complex arrays (complex steps).
        """
        s, u, v = w[0], w[1], w[2]
        sx, ux, vx = wx[0], wx[1], wx[2]
        uxx, vxx = wxx[1], wxx[2]
        ls = np.log(s)
        lsx = sx / s
        if self.isothermal:
            p = np.exp(self.ps * ls)
            px = self.ps * p * lsx
            eta = self.nu0 * np.exp((self.beta + 1.0) * ls)
            etax = (self.beta + 1.0) * eta * lsx
        else:
            T, Tx, Txx = w[3], wx[3], wxx[3]
            lt = np.log(T / self.T0)
            ltx = Tx / T
            p = np.exp(self.ps * ls + self.pT * lt)
            px = p * (self.ps * lsx + self.pT * ltx)
            eta = self.nu0 * np.exp((self.beta + 1.0) * ls + self.nT * lt)
            etax = eta * ((self.beta + 1.0) * lsx + self.nT * ltx)
        sh = vx - 1.5  # total shear rate including the background -3/2 Omega
        dpxx = self.bulk * (eta * uxx + etax * ux)
        dpxy = eta * vxx + etax * sh
        out = [0.0 * s, -u * ux - px / s + 2.0 * v + g + dpxx / s, -u * vx - 0.5 * u + dpxy / s]
        if not self.isothermal:
            gam = self.Gamma0 * np.exp(self.Gs * ls + self.GT * lt)
            dq = self.kr * (eta * Txx + etax * Tx)
            heat = -p * ux + self.bulk * eta * ux * ux + eta * sh * sh - gam + dq
            out.append(-u * Tx + heat * (2.0 / 3.0) / s)
        return np.array(out)

    def pointwise_jacobians(self, w, wx, wxx, g):
        """d(pointwise)/d(w, w_x, w_xx) each (nv, nv, N) and d/dg (nv, N), by complex steps."""
        nv = self.nv
        w, wx, wxx, g = (np.asarray(a, complex) for a in (w, wx, wxx, g))
        A = [np.zeros((nv, nv, w.shape[1])) for _ in range(3)]
        args = [w, wx, wxx]
        for m in range(3):
            for b in range(nv):
                a = [x.copy() for x in args]
                a[m][b] += 1j * _CSTEP
                A[m][:, b] = self.pointwise(a[0], a[1], a[2], g).imag / _CSTEP
        Ag = self.pointwise(w, wx, wxx, g + 1j * _CSTEP).imag / _CSTEP
        return A[0], A[1], A[2], Ag


class Grid:
    """Fourier collocation on N (odd) equidistant nodes of one period ``lam`` (dimensionless).

    Odd N avoids the Nyquist mode, so D_q and the gravity response are defined for every q.
    """

    def __init__(self, N: int, lam: float, inv_Q0: float = 0.0):
        if N % 2 == 0:
            raise ValueError(f"N = {N} is not valid: the number of Fourier nodes must be odd")
        self.N, self.lam, self.inv_Q0 = N, float(lam), float(inv_Q0)
        self.k = 2.0 * np.pi * np.fft.fftfreq(N, d=self.lam / N)  # wavenumbers of the DFT [Omega/c0]
        self.x = self.lam * np.arange(N) / N

    def deriv(self, f, order=1):
        """Spectral derivative of real periodic rows f (..., N)."""
        return np.fft.ifft((1j * self.k) ** order * np.fft.fft(f, axis=-1), axis=-1).real

    def gravity(self, sigma):
        """Force per unit mass g = -d(phi)/dx of density sigma (N,), the solver's ``"mode"`` response."""
        if self.inv_Q0 == 0.0:
            return np.zeros_like(sigma)
        Gk = 2j * self.inv_Q0 * np.sign(self.k)
        return np.fft.ifft(Gk * np.fft.fft(sigma)).real

    def matrices(self, q: float = 0.0):
        """Dense D_q, D_q^2 and G_q (N, N) acting on the periodic factor of exp(i q x) phi(x).

        Real for q = 0, complex otherwise.  Each is diagonal in Fourier space, hence circulant on
        the nodes: M[j, l] = ifft(symbol)[(j - l) mod N], built in O(N^2) without matrix products.
        """
        N = self.N
        kq = self.k + q
        idx = (np.arange(N)[:, None] - np.arange(N)[None, :]) % N
        mats = []
        for symbol in (1j * kq, -(kq**2) + 0j, 2j * self.inv_Q0 * np.sign(kq)):
            col = np.fft.ifft(symbol)
            mats.append(col.real[idx] if q == 0.0 else col[idx])
        return tuple(mats)


def residual(model: Model, grid: Grid, w, c):
    """Travelling-wave residual F(w) + c w_x, shape (nv, N): zero for a wave train U(x - c t)."""
    wx = grid.deriv(w)
    wxx = grid.deriv(w, 2)
    g = grid.gravity(w[0])
    r = model.pointwise(w, wx, wxx, g)
    r[0] = -grid.deriv(w[0] * w[1])
    return r + c * wx


def linear_operator(model: Model, grid: Grid, w, c, q: float = 0.0, mats=None):
    """Dense linearisation of F(w) + c w_x for Bloch perturbations exp(i q x) phi(x), (nv N, nv N).

    Rows/columns are field-major (field a, node j) -> a N + j.  Its eigenvalues are the Floquet
    exponents mu [Omega] of perturbations in the frame moving with the wave (growth rate Re mu).
    """
    nv, N = w.shape
    D, D2, G = mats if mats is not None else grid.matrices(q)
    wx = grid.deriv(w)
    wxx = grid.deriv(w, 2)
    g = grid.gravity(w[0])
    A0, A1, A2, Ag = model.pointwise_jacobians(w, wx, wxx, g)
    J = np.zeros((nv * N, nv * N), dtype=D.dtype)
    for a in range(1, nv):
        for b in range(nv):
            blk = np.diag(A0[a, b]) + A1[a, b][:, None] * D + A2[a, b][:, None] * D2
            if b == 0:
                blk = blk + Ag[a][:, None] * G
            if a == b:
                blk = blk + c * D
            J[a * N:(a + 1) * N, b * N:(b + 1) * N] = blk
    # continuity in flux form: -(D (u dsigma + sigma du)) + c D dsigma
    J[:N, :N] = -D * w[1][None, :] + c * D
    J[:N, N:2 * N] = -D * w[0][None, :]
    return J
