"""Newton's method for periodic travelling waves U(x - c t) on a Fourier grid.

Unknowns z = (w (nv, N) field-major, c, ell) with ell = lambda / lambda_ref (lambda_ref: the
neutral wavelength, so ell = O(1)).  Equations: the travelling-wave residual F(w) + c w_x at every
node, except that the continuity row at node 0 (linearly dependent on the others: the flux
divergence has zero mean) is replaced by the mass condition mean(sigma) = 1; the phase condition
Im sigma_1 = 0 (first Fourier coefficient of sigma real) removes the translation; one more
equation closes the system when ell is unknown: a fixed amplitude Re sigma_1 (start of the
branch) or a pseudo-arclength condition (continuation through folds).

All quantities dimensionless (units of :mod:`ringcore.wavetrain.model`).
"""
from __future__ import annotations

import numpy as np
import scipy.linalg

from .model import Grid, Model, linear_operator, residual


class NewtonFailure(RuntimeError):
    """Newton's method did not reach the tolerance; ``reason`` says why."""

    def __init__(self, reason: str, res: float):
        super().__init__(reason)
        self.reason, self.res = reason, res


def _phase_rows(N):
    j = np.arange(N)
    return np.sin(2 * np.pi * j / N), np.cos(2 * np.pi * j / N) * (2.0 / N)


def equations(model: Model, N: int, z, lam_ref: float, ell_fixed=None, extra=None, jac=True):
    """Equations and Jacobian at z.

    Parameters
    ----------
    ell_fixed : float or None
        If given, lambda = ell_fixed * lam_ref and z = (w, c) only.
    extra : None, ("amp", A) or ("arc", weights, t, z_pred)
        The closing equation when ell is unknown.
    """
    nv = model.nv
    n = nv * N
    w = z[:n].reshape(nv, N)
    c = z[n]
    ell = ell_fixed if ell_fixed is not None else z[n + 1]
    grid = Grid(N, ell * lam_ref, model.inv_Q0)
    r = residual(model, grid, w, c)
    sin_row, cos_row = _phase_rows(N)
    F = [r.ravel()]
    F[0][0] = w[0].mean() - 1.0
    F.append([sin_row @ w[0]])
    if ell_fixed is None:
        if extra[0] == "amp":
            F.append([cos_row @ w[0] - extra[1]])
        else:
            _, wt, t, zp = extra
            F.append([np.dot(wt * t, z - zp)])
    F = np.concatenate([np.asarray(f, float) for f in F])
    if not jac:
        return F, None
    m = n + (1 if ell_fixed is not None else 2)
    J = np.zeros((m + 0, m))
    J[:n, :n] = linear_operator(model, grid, w, c)
    J[:n, n] = grid.deriv(w).ravel()
    J[0, :] = 0.0
    J[0, :N] = 1.0 / N
    J[n, :N] = sin_row
    if ell_fixed is None:
        d = 1e-7 * ell
        r2 = residual(model, Grid(N, (ell + d) * lam_ref, model.inv_Q0), w, c).ravel()
        J[:n, n + 1] = (r2 - r.ravel()) / d
        J[0, n + 1] = 0.0
        if extra[0] == "amp":
            J[n + 1, :N] = cos_row
        else:
            J[n + 1, :] = extra[1] * extra[2]
    return F, J


def newton(model, N, z0, lam_ref, ell_fixed=None, extra=None, tol=1e-11, maxit=25):
    """Solve :func:`equations` = 0 from z0; returns (z, max |F|, iterations) or raises NewtonFailure.

    The LU factors of the Jacobian are reused (chord iterations) as long as each step reduces the
    residual at least fourfold; otherwise the Jacobian is recomputed at the current point.  From a
    continuation predictor (residual ~1e-4) the chord iterations converge about as fast as full
    Newton (the contraction factor is of the size of the correction) at a fraction of the cost: the
    dense Jacobian's assembly and factorisation dominate an iteration.
    """
    z = np.array(z0, float)
    nv = model.nv
    res = np.inf
    lu, res_prev = None, np.inf
    for it in range(maxit + 1):
        F, J = equations(model, N, z, lam_ref, ell_fixed, extra, jac=lu is None)
        res = float(np.max(np.abs(F)))
        if not np.isfinite(res):
            raise NewtonFailure("the residual is not finite (fields left the physical range)", res)
        if res <= tol:
            return z, res, it
        if it == maxit:
            break
        if lu is not None and res > 0.25 * res_prev:  # chord step too slow: fresh Jacobian here
            F, J = equations(model, N, z, lam_ref, ell_fixed, extra, jac=True)
            lu = None
        if lu is None:
            lu = scipy.linalg.lu_factor(J, overwrite_a=True, check_finite=False)
            if np.any(lu[0].diagonal() == 0.0):
                raise NewtonFailure("singular Jacobian", res)
        res_prev = res
        dz = scipy.linalg.lu_solve(lu, -F, check_finite=False)
        # damp steps that would make sigma (or T) non-positive
        a = 1.0
        w, dw = z[:nv * N].reshape(nv, N), dz[:nv * N].reshape(nv, N)
        rows = [0] if model.isothermal else [0, 3]
        for r in rows:
            neg = dw[r] < 0
            if np.any(neg):
                a = min(a, 0.9 * float(np.min(-w[r][neg] / dw[r][neg])))
        z = z + a * dz
        if it > 4 and res > 1e3:
            break
    raise NewtonFailure(f"Newton did not converge in {maxit} iterations (max residual {res:.2e})", res)
