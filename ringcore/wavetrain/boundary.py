"""lambda_st: the shortest wavelength whose wave train is stable (LO2009's stability boundary).

The branch is computed from lambda_c up to ``lam_max_m``; the Floquet growth rate (largest over the
sampled Bloch wavenumbers) is evaluated on wave trains spaced by about ``scan_step`` in
lambda/lambda_c (up to three times that where the growth is fast, far from the boundary); in the
first bracket (unstable -> stable) of the scan the boundary is refined by bisection (Newton at fixed
wavelength) and finally by linear interpolation of the growth rate of the q that was most unstable on
the unstable side, which changes sign smoothly.

Cost.  The dense eigenvalue problems dominate (about 0.6 s for one complex q at N = 217 nodes,
isothermal), so a scan point first tries a coarse set of q (:data:`~.floquet.COARSE_Q` and the
previous point's fastest q) and computes the remaining q only if these are all stable: stable or not
is decided on the full set, while an unstable point's growth rate is a lower bound (the largest over
the q tried).

lambda_st is reported only if every scanned wave train above it, up to ``confirm`` times it, is
stable; otherwise the result says which wavelengths are unstable again.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..params import RingParams, require
from .branch import compute_branch, neutral_wavelength, solve_at
from .floquet import COARSE_Q, DEFAULT_Q, FloquetSpectrum, floquet

STABLE_TOL = 1e-7  # [Omega] growth rates below this count as stable: an e-folding time of 1.6 million orbits.
# Wave trains resolved to a spectral tail of 1e-6 can show spurious long-wave growth up to ~5e-9 Omega
# (tau20 non-isothermal at 570 m: +5e-9 with N = 97, tail 7e-7; -3e-11 with N = 145, tail 3e-8).


@dataclass
class StabilityBoundary:
    """Result of :func:`stability_boundary`.

    Attributes
    ----------
    lambda_st_m : float or None
        Stability boundary [m]; None if the scan found none (``reason`` says why).
    reason : str
        Empty if lambda_st was found, else why not.
    lambda_c_m : float
        Neutral wavelength where the branch starts [m].
    wavelength_m, growth_rate, q_max_over_k, amplitude, n_fourier : ndarray
        The scan: wavelengths [m], largest Floquet growth rate [Omega], its q/k, relative sigma
        amplitude, Fourier nodes.
    branch_stop : str
        Why the branch continuation ended.
    seconds : float
        Wall time.
    """

    lambda_st_m: float | None
    reason: str
    lambda_c_m: float
    wavelength_m: np.ndarray = field(default_factory=lambda: np.zeros(0))
    growth_rate: np.ndarray = field(default_factory=lambda: np.zeros(0))
    q_max_over_k: np.ndarray = field(default_factory=lambda: np.zeros(0))
    amplitude: np.ndarray = field(default_factory=lambda: np.zeros(0))
    n_fourier: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    branch_stop: str = ""
    seconds: float = 0.0

    def to_json_dict(self) -> dict:
        """JSON-ready dict (SI; growth rates in Omega)."""
        return dict(lambda_st_m=self.lambda_st_m, reason=self.reason or None, lambda_c_m=self.lambda_c_m,
                    branch_stop=self.branch_stop, seconds=round(self.seconds, 2),
                    scan=dict(wavelength_m=self.wavelength_m.tolist(), growth_rate_Omega=self.growth_rate.tolist(),
                              q_max_over_k=self.q_max_over_k.tolist(), amplitude_sigma=self.amplitude.tolist(),
                              n_fourier=[int(n) for n in self.n_fourier]))


def stability_boundary(p: RingParams, lam_max_m: float | None = None, N: int = 65, N_max: int = 301,
                       q_over_k=DEFAULT_Q, scan_step: float = 0.5, bisections: int = 3,
                       confirm: float = 1.5) -> StabilityBoundary:
    """Find lambda_st for parameter set ``p``.

    Parameters
    ----------
    p : RingParams
    lam_max_m : float, optional
        Largest wavelength scanned [m]; default 25 lambda_c.
    N, N_max : int
        Fourier nodes per wavelength at the start and at most (odd).
    q_over_k : sequence of float
        Bloch wavenumbers sampled, as fractions of k, in [0, 1/2].
    scan_step : float
        Spacing of the stability scan in lambda/lambda_c.
    bisections : int
        Bisection steps in the bracket before the final interpolation.
    confirm : float
        The scan ends once the wave trains have been stable from some lambda to ``confirm`` times it.
    """
    require(p)
    t0 = time.perf_counter()
    lam_c = neutral_wavelength(p)
    if not math.isfinite(lam_c):
        return StabilityBoundary(None, "no overstable band: there are no wave trains", lam_c)
    lam_max_m = 25.0 * lam_c if lam_max_m is None else lam_max_m
    lams, grs, qs, amps, ns = [], [], [], [], []
    spectra = []
    state = dict(next_ell=0.0, first_stable=None)

    def scan(tr):
        ell = tr.wavelength_m / lam_c
        if ell < state["next_ell"]:
            return None
        fs = _scan_floquet(tr, q_over_k, qs[-1] if qs else None)
        lams.append(tr.wavelength_m), grs.append(fs.growth_rate), qs.append(fs.q_max_over_k)
        amps.append(tr.amplitude), ns.append(tr.N)
        spectra.append((tr, fs))
        if fs.growth_rate > STABLE_TOL:
            state["first_stable"] = None
        elif state["first_stable"] is None:
            state["first_stable"] = tr.wavelength_m
        if state["first_stable"] is not None:  # confirming: three checks up to confirm * first stable
            step = max(scan_step, (confirm - 1.0) * state["first_stable"] / (3.0 * lam_c))
        else:  # far from the boundary (fast growth) longer steps: 1x at 1e-5 Omega, 2x at 1e-3, at most 3x
            step = scan_step * min(3.0, max(1.0, 0.5 * math.log10(fs.growth_rate / STABLE_TOL)))
        state["next_ell"] = ell + step
        if state["first_stable"] is not None and tr.wavelength_m >= confirm * state["first_stable"]:
            return (f"stopped at {tr.wavelength_m:.1f} m: stable from {state['first_stable']:.1f} m to "
                    f"{confirm:g} times that")
        return None

    br = compute_branch(p, lam_max_m, N=N, N_max=N_max, stop=scan)
    if br.trains and (not lams or lams[-1] < br.trains[-1].wavelength_m) and len(br.trains) > 2:
        state["next_ell"] = 0.0
        scan(br.trains[-1])
    res = StabilityBoundary(None, "", lam_c, np.array(lams), np.array(grs), np.array(qs), np.array(amps),
                            np.array(ns, int), br.stop_reason)
    unstable = res.growth_rate > STABLE_TOL
    if unstable.size == 0:
        res.reason = f"no wave trains computed ({br.stop_reason})"
    elif not unstable[0]:
        res.reason = f"the first scanned wave train ({lams[0]:.1f} m) is already stable: lambda_st <= that"
    elif np.all(unstable):
        res.reason = (f"all wave trains up to {lams[-1]:.1f} m are unstable (branch: {br.stop_reason}); "
                      "lambda_st is larger, if it exists")
    else:
        i = int(np.argmin(unstable))  # first stable
        if np.any(unstable[i:]):
            again = res.wavelength_m[i:][unstable[i:]]
            res.reason = (f"stable at {lams[i]:.1f} m but unstable again at {again.min():.1f} m: no single "
                          "stability boundary")
        else:
            # bisect down to the bracket a plain scan with ``bisections`` steps would end with
            width = (lams[i] - lams[i - 1]) / lam_c
            n_bis = bisections + max(0, round(math.log2(width / scan_step)))
            res.lambda_st_m = _refine(br, spectra[i - 1], spectra[i], q_over_k, n_bis)
    res.seconds = time.perf_counter() - t0
    return res


def _scan_floquet(tr, q_over_k, q_prev):
    """Floquet spectrum on a scan point: first the coarse q (and the previous point's fastest q); only if
    all of them are stable the remaining q of ``q_over_k``.  Stable/unstable is decided exactly as with
    the full set; an unstable point's growth rate is the largest over the q evaluated (a lower bound)."""
    q_all = [float(q) for q in q_over_k]
    first = [q for q in q_all if q in COARSE_Q or q == q_prev]
    fs = floquet(tr, first) if first else None
    rest = [q for q in q_all if q not in first]
    if fs is not None and (fs.growth_rate > STABLE_TOL or not rest):
        return fs
    fs2 = floquet(tr, rest)
    if fs is None:
        return fs2
    order = np.argsort(first + rest)
    return FloquetSpectrum(np.asarray(first + rest)[order], np.concatenate([fs.mu, fs2.mu])[order],
                           np.concatenate([fs.growth_per_q, fs2.growth_per_q])[order])


def _refine(br, lo, hi, q_over_k, bisections):
    """Bisection between an unstable (lo) and a stable (hi) wave train, then interpolation at q*."""
    (tr_a, fs_a), (tr_b, _) = lo, hi
    for _ in range(bisections):
        lam = 0.5 * (tr_a.wavelength_m + tr_b.wavelength_m)
        tr = solve_at(br, lam)
        fs = _scan_floquet(tr, q_over_k, fs_a.q_max_over_k)
        if fs.growth_rate > STABLE_TOL:
            tr_a, fs_a = tr, fs
        else:
            tr_b = tr
    q = [fs_a.q_max_over_k]
    ga = fs_a.growth_rate
    gb = floquet(tr_b, q).growth_rate
    la, lb = tr_a.wavelength_m, tr_b.wavelength_m
    if gb >= ga:  # not a clean sign change at q*: the midpoint is the best estimate
        return 0.5 * (la + lb)
    # gb may be slightly positive (below STABLE_TOL): keep the root inside the bracket
    return float(min(lb, la + (lb - la) * ga / (ga - gb)))
