"""The wave-train branch: from the linear neutral mode at lambda_c upward in wavelength.

The branch is started from the linear overstable eigenmode (:func:`ringcore.linear.eigenmode`) at
the neutral wavelength lambda_c (the short-wavelength edge of the overstable band, growth rate
omega_R = 0) with the surface-density amplitude as parameter (the wavelength is an unknown), then
continued by secant pseudo-arclength continuation (through folds, if any) up to ``lam_max_m``.
Continuation stops early, with the reason, if Newton fails at the smallest step, the profile is no
longer resolved by the N Fourier nodes, or the fields leave the physical range.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import linear
from ..checks import check_int, check_real
from ..params import RingParams, require
from .model import Model
from .newton import NewtonFailure, newton
from .result import WaveTrain

TAIL_MAX = 1e-6  # spectral tail above this: the wave train is not resolved by N nodes
# longest wavelength of a branch, in units of lambda_c: the continuation steps at most 0.1 lambda_c, so the
# cost grows with the length (25 lambda_c, the default scan of lambda_st, took ~1 min, 50 lambda_c ~2 min on
# a loaded 2-core machine; 1e6 m would take days); the saturated waves of the paper lie within a few lambda_c
LAMBDA_MAX_OVER_C = 50.0


def neutral_wavelength(p: RingParams) -> float:
    """lambda_c [m]: shortest neutral wavelength of the overstable mode (omega_R = 0); nan if none."""
    require(p)
    bands = linear.overstable_band(p)
    return float(bands[0][0]) if bands else math.nan


@dataclass
class Branch:
    """Wave trains along one branch, ordered by arclength (normally increasing wavelength).

    Attributes
    ----------
    params : RingParams
    N : int
        Fourier nodes per wavelength at the start (each wave train has its own ``N``).
    lambda_c_m : float
        Neutral wavelength [m] where the branch starts.
    trains : list of WaveTrain
    stop_reason : str
        Why continuation ended (``"reached lam_max"`` or the failure).
    """

    params: RingParams
    N: int
    lambda_c_m: float
    trains: list = field(default_factory=list)
    stop_reason: str = ""

    @property
    def wavelength_m(self) -> np.ndarray:
        """Wavelengths of the computed wave trains [m]."""
        return np.array([t.wavelength_m for t in self.trains])

    def nearest(self, wavelength_m: float) -> WaveTrain:
        """The computed wave train with wavelength closest to ``wavelength_m`` [m]."""
        return self.trains[int(np.argmin(np.abs(self.wavelength_m - wavelength_m)))]


def _lam_ref(p):
    return neutral_wavelength(p) / p.scales.length


def _linear_guess(model, p, N, lam_c_m, amp):
    mode = linear.eigenmode(p, lam_c_m, "left")
    lam = lam_c_m / p.scales.length
    x = lam * np.arange(N) / N
    w = model.ground()[:, None] + np.real(amp * mode.vector[:, None] * np.exp(1j * mode.k * x)[None, :])
    return w, -mode.omega.imag / mode.k


def _train(p, model, N, z, lam_ref, res, ell=None):
    n = model.nv * N
    ell = z[n + 1] if ell is None else ell
    return WaveTrain(params=p, lam=float(ell * lam_ref), c=float(z[n]), w=z[:n].reshape(model.nv, N).copy(),
                     residual=float(res))


def _regrid(z, nv, N, N2):
    """z on N nodes -> N2 nodes (odd both) by Fourier zero-padding; c, ell kept."""
    n = nv * N
    W = np.fft.rfft(z[:n].reshape(nv, N), axis=1)
    w2 = np.fft.irfft(W, n=N2, axis=1) * (N2 / N)
    return np.concatenate([w2.ravel(), z[n:]])


def _physical(model, w):
    ok = np.all(w[0] > 0)
    return ok and (model.isothermal or np.all(w[3] > 0))


def check_max_wavelength(label: str, wavelength_m, lam_c_m: float) -> float:
    """``wavelength_m`` [m] within lambda_c < wavelength <= :data:`LAMBDA_MAX_OVER_C` lambda_c (ValueError naming
    ``label``, the value and the range otherwise)."""
    try:
        return check_real(label, wavelength_m, lam_c_m, LAMBDA_MAX_OVER_C * lam_c_m, lo_open=True, unit="m",
                          allow_str=False)
    except ValueError as exc:
        if "out of range" not in str(exc):
            raise
        raise ValueError(f"{exc} (wave trains start at the neutral wavelength lambda_c = {lam_c_m:.2f} m; the "
                         f"branch is continued at most to {LAMBDA_MAX_OVER_C:g} lambda_c, beyond which it takes "
                         "hours to days)") from None


def compute_branch(p: RingParams, lam_max_m: float, N: int = 65, N_max: int = 301, amp0: float = 1e-3,
                   dell: float = 0.03, dell_max: float = 0.1, tol: float = 1e-11, stop=None,
                   tail_max: float = TAIL_MAX) -> Branch:
    """Continue the wave-train branch from lambda_c to ``lam_max_m`` [m].

    Parameters
    ----------
    p : RingParams
    lam_max_m : float
        Stop when the wavelength exceeds this [m].
    N : int
        Fourier nodes per wavelength at the start (odd, >= 9); raised by ~1.5x whenever the spectral
        tail exceeds TAIL_MAX, up to ``N_max``.
    amp0 : float
        Relative sigma amplitude (first Fourier coefficient) of the first two branch points
        (amp0 and 2 amp0), computed with the amplitude as parameter.
    dell, dell_max : float
        Initial and largest step in lambda/lambda_c per continuation step.
    tol : float
        Newton tolerance on max |F| (dimensionless).
    tail_max : float
        Largest accepted spectral tail (:attr:`WaveTrain.spectral_tail`) before N is raised.
    stop : callable, optional
        ``stop(train) -> str or None`` called with each new continuation point; a string ends the
        continuation with that reason.
    """
    require(p)
    N = check_int("N", N, 9, 1001)
    N_max = check_int("N_max", N_max, N, 1001)
    for nm, v in (("N", N), ("N_max", N_max)):
        if v % 2 == 0:
            raise ValueError(f"{nm} = {v} is not valid: the number of Fourier nodes must be odd (9 .. 1001)")
    lam_c_m = neutral_wavelength(p)
    if not math.isfinite(lam_c_m):
        raise ValueError(f"parameter set {p.name!r} ({p.model}, sigma0 = {p.sigma0:g} kg/m^2) is not valid for "
                         "wave trains: it has no overstable band (no neutral wavelength)")
    check_max_wavelength("lam_max_m", lam_max_m, lam_c_m)
    model = Model(p)
    nv = model.nv
    lam_ref = lam_c_m / p.scales.length
    br = Branch(params=p, N=N, lambda_c_m=lam_c_m)
    zs = []
    w, c = _linear_guess(model, p, N, lam_c_m, amp0)
    z = np.concatenate([w.ravel(), [c, 1.0]])
    a = amp0
    while True:  # amplitude as parameter until the branch has left lambda_c (where it is vertical)
        try:
            z, res, _ = newton(model, N, z, lam_ref, extra=("amp", a), tol=tol)
        except NewtonFailure as e:
            br.stop_reason = f"could not leave the linear mode at amplitude {a:g}: {e.reason}"
            return br
        zs.append(z.copy())
        br.trains.append(_train(p, model, N, z, lam_ref, res))
        if len(zs) >= 2 and (abs(z[-1] - 1.0) > 0.5 * dell or a > 0.2):
            break
        a *= 2.0
    ell_max = lam_max_m / lam_c_m

    def weights(N):
        return np.concatenate([np.full(nv * N, 1.0 / math.sqrt(N)), [1.0, 1.0]])  # RMS weight for the fields

    wt = weights(N)
    ds = float(np.linalg.norm((zs[-1] - zs[-2]) * wt))
    while True:
        z0, z1 = zs[-2], zs[-1]
        sec = (z1 - z0) * wt
        t = sec / np.linalg.norm(sec)
        t_unw = t / wt
        while True:
            zp = z1 + ds * t_unw
            try:
                z, res, it = newton(model, N, zp, lam_ref, extra=("arc", wt, t, zp), tol=tol)
                if not _physical(model, z[:nv * N].reshape(nv, N)):
                    raise NewtonFailure("the fields left the physical range (sigma or T <= 0)", res)
                break
            except NewtonFailure as e:
                ds *= 0.5
                if ds * abs(t[-1]) < 1e-5:
                    br.stop_reason = (f"continuation stopped at lambda = {z1[-1] * lam_c_m:.1f} m: {e.reason} "
                                      "even at the smallest step")
                    return br
        tr = _train(p, model, N, z, lam_ref, res)
        if tr.spectral_tail > tail_max:  # refine the grid and redo this step
            N2 = min(2 * int(0.75 * N) + 1, N_max)  # about 1.5 N, odd
            if N2 <= N:
                br.stop_reason = (f"continuation stopped at lambda = {tr.wavelength_m:.1f} m: the profile is not "
                                  f"resolved by N_max = {N_max} Fourier nodes (spectral tail "
                                  f"{tr.spectral_tail:.1e} > {tail_max:g}); use a larger N_max")
                return br
            zs = [_regrid(zz, nv, N, N2) for zz in zs[-2:]]
            N = N2
            wt = weights(N)
            continue
        zs.append(z)
        br.trains.append(tr)
        if z[-1] >= ell_max:
            br.stop_reason = "reached lam_max"
            return br
        why = stop(tr) if stop is not None else None
        if why:
            br.stop_reason = why
            return br
        step_ell = abs(z[-1] - z1[-1])
        grow = 1.5 if it <= 4 else (1.0 if it <= 8 else 0.6)
        ds *= grow
        if step_ell * grow > dell_max:
            ds *= dell_max / (step_ell * grow)


def solve_at(branch: Branch, wavelength_m: float, tol: float = 1e-11) -> WaveTrain:
    """The wave train at exactly ``wavelength_m`` [m] (Newton with lambda fixed, guess from the branch).

    The guess is the nearest computed wave train, re-gridded by spectral interpolation (the profile
    in x/lambda is kept).
    """
    p = branch.params
    lam_c = branch.lambda_c_m
    check_real("wavelength_m", wavelength_m, lam_c, math.inf, lo_open=True, unit="m")
    near = branch.nearest(wavelength_m)
    model = Model(p)
    z0 = np.concatenate([near.w.ravel(), [near.c * wavelength_m / near.wavelength_m]])
    lam_ref = lam_c / p.scales.length
    ell = wavelength_m / lam_c
    z, res, _ = newton(model, near.N, z0, lam_ref, ell_fixed=ell, tol=tol)
    return _train(p, model, near.N, np.concatenate([z, [ell]]), lam_ref, res)
