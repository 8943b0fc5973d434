"""Characteristic numbers of the exact linear theory.

F2, F3 from the small-k expansion of the exact relation (Eq. (19b)), beta_c,
the wavelength and value of the largest growth rate, the overstable band and
lambda_zero (minimum of omega_I, where the group velocity changes sign).
"""
from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass, replace

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..params import RingParams, require
from ..units import G
from .matrix import refine_branch, track_overstable

# search range in wavelength [m] for band edges, maxima and lambda_zero
LAMBDA_MIN_M = 0.5
LAMBDA_MAX_M = 2.0e5


def small_k_coefficients(p: RingParams):
    """Taylor coefficients c1, c2, c3 of omega_2(k) = i + c1 k + c2 k^2 + c3 k^3 + ...

    Extracted by a least-squares polynomial fit of the exact eigenvalue at
    k = 2e-3 ... 1.6e-2 (dimensionless).  c1 = -i/Q0 exactly; c2 gives F2, F3.
    """
    require(p)
    k = 2e-3 * np.arange(1, 9)
    om, _, _ = track_overstable(p, k)
    X = np.stack([k**j for j in range(1, 7)], axis=1).astype(complex)
    c, *_ = np.linalg.lstsq(X, om - 1j, rcond=None)
    return c[0], c[1], c[2]


@functools.lru_cache(maxsize=256)
def thermal_coefficients(p: RingParams):
    """(F2, F3) of Eqs. (19b), (21), (22), from the exact relation.

    Both vanish in the isothermal model.  Computed without self-gravity, as in the table.
    """
    require(p)
    q = p.with_sigma0(0.0)
    _, c2, _ = small_k_coefficients(q)
    d = q.dimensionless()
    F3 = 2.0 * (c2.real - d["nu0"] * (2 + 9 * d["beta"] - 3 * d["gamma"]) / 6.0)
    F2 = 2.0 * c2.imag - d["p_s"]
    return float(F2), float(F3)


def beta_c(p: RingParams) -> float:
    """Critical viscosity exponent: the long-wave growth coefficient Re c2 vanishes.

    Exact in the sense that F3(beta) is recomputed from the exact relation for each beta
    (root found with brentq in -0.99 < beta < 20).  nan if there is no sign change.
    Independent of sigma0 (computed without self-gravity; cached).
    """
    require(p)
    return _beta_c(p.with_sigma0(0.0))


@functools.lru_cache(maxsize=256)
def _beta_c(q0: RingParams) -> float:

    def g(b):
        return small_k_coefficients(q0.with_beta(b))[1].real

    lo, hi = -0.99, 20.0
    glo, ghi = g(lo), g(hi)
    if glo * ghi > 0:
        return math.nan
    return float(brentq(g, lo, hi, xtol=1e-10))


def beta_c_approx(p: RingParams, F3: float | None = None) -> float:
    """beta_c = (gamma - 2/3 - F3/nu0)/3 from Eq. (21) (F3 = 0 when isothermal)."""
    require(p)
    if F3 is None:
        F3 = 0.0 if p.isothermal else p.F3
    nu0 = p.dimensionless()["nu0"]
    return (p.gamma - 2.0 / 3.0 - F3 / nu0) / 3.0


@functools.lru_cache(maxsize=64)
def _grid(p: RingParams, n: int = 1500):
    L = p.scales.length
    k = np.geomspace(2 * np.pi * L / LAMBDA_MAX_M, 2 * np.pi * L / LAMBDA_MIN_M, n)
    om, dom, _ = track_overstable(p, k)
    return k, om, dom


def _to_lambda(p, k):
    return 2 * np.pi / k * p.scales.length


def max_growth(p: RingParams):
    """(wavelength [m], omega_R [Omega]) of the largest growth rate; (nan, value) if none > 0."""
    require(p)
    k, om, _ = _grid(p)
    i = int(np.argmax(om.real))
    if om.real[i] <= 0:
        return math.nan, float(om.real[i])
    if i == 0 or i == k.size - 1:
        return float(_to_lambda(p, k[i])), float(om.real[i])
    guess = om[i]

    def f(logk):
        return -refine_branch(p, math.exp(logk), guess)[0].real

    r = minimize_scalar(f, bounds=(math.log(k[i - 1]), math.log(k[i + 1])), method="bounded",
                        options={"xatol": 1e-10})
    return float(_to_lambda(p, math.exp(r.x))), float(-r.fun)


def overstable_band(p: RingParams):
    """Wavelength intervals [m] where omega_R > 0, as a list of (short, long); long may be inf."""
    require(p)
    k, om, _ = _grid(p)
    gr = om.real
    pos = gr > 0
    edges = []
    for i in np.nonzero(pos[1:] != pos[:-1])[0]:
        g0 = om[i]
        kk = _bracketed_root(lambda x: refine_branch(p, x, g0)[0].real, k[i], k[i + 1], p,
                             "the overstable band", xtol=1e-12)
        edges.append((kk, bool(pos[i + 1])))  # True: band starts (going to larger k)
    bands, start = [], (k[0] if pos[0] else None)
    for kk, opens in edges:
        if opens:
            start = kk
        elif start is not None:
            bands.append((start, kk))
            start = None
    if start is not None:
        bands.append((start, k[-1]))
    out = []
    for ka, kb in bands:
        long_ = math.inf if ka == k[0] else float(_to_lambda(p, ka))
        out.append((float(_to_lambda(p, kb)), long_))
    return sorted(out)


def lambda_zero(p: RingParams) -> float:
    """Wavelength [m] of the omega_I minimum (v_g changes from - to + with k); nan if none.

    Exists only with self-gravity (sigma0 > 0): from k = 0 on, omega_I = 1 - k/Q0 + O(k^2)
    falls (v_g = -1/Q0 < 0) until its minimum at lambda_zero, roughly proportional to Q0 (i.e.
    1/sigma0).  This is the FIRST sign change of v_g coming from long waves; at weak self-gravity
    (tau15: sigma0 < ~0.25 kg/m^2) it lies beyond the wavenumber grid (``LAMBDA_MAX_M``) and is
    followed there along the branch to longer waves, up to :data:`LAMBDA_ZERO_MAX_M` (nan beyond:
    no local minimum inside a shearing sheet).  The later sign changes at wavelengths of a few
    metres (present also without self-gravity) are not lambda_zero.

    References: Eq. (23), Figure 2.
    """
    require(p)
    if p.sigma0 == 0:
        return math.nan
    k, om, dom = _grid(p)
    vg = dom.imag
    if vg[0] >= 0:  # the minimum lies at longer waves than the grid reaches
        return _lambda_zero_long(p, float(k[0]), om[0])
    idx = np.nonzero((vg[:-1] < 0) & (vg[1:] >= 0))[0]
    if idx.size == 0:
        return math.nan
    i = int(idx[0])
    g0 = om[i]
    kz = _bracketed_root(lambda x: refine_branch(p, x, g0)[1].imag, k[i], k[i + 1], p, "lambda_zero",
                         xtol=1e-12)
    return float(_to_lambda(p, kz))


LAMBDA_ZERO_MAX_M = 1.0e7  # [m] beyond, a wavelength is no longer small against the orbital radius (~1e8 m)


def _lambda_zero_long(p: RingParams, k_hi: float, guess) -> float:
    """lambda_zero [m] at wavenumbers below ``k_hi`` (where v_g >= 0), followed down the branch
    in steps of 2; nan if it lies beyond LAMBDA_ZERO_MAX_M."""
    k_min = 2 * np.pi * p.scales.length / LAMBDA_ZERO_MAX_M
    k_b = k_hi
    while k_b > k_min:
        k_a = max(k_b / 2.0, k_min)
        w, dw, _ = refine_branch(p, k_a, guess)
        if dw.imag < 0:
            kz = _bracketed_root(lambda x: refine_branch(p, x, w)[1].imag, k_a, k_b, p, "lambda_zero", xtol=1e-14)
            return float(_to_lambda(p, kz))
        k_b, guess = k_a, w
    return math.nan


def _bracketed_root(f, a, b, p: RingParams, what: str, **kw) -> float:
    """``brentq(f, a, b)``; a failed bracket becomes a ValueError naming the physical condition.

    The bracket comes from the tracked overstable branch on a wavenumber grid: when the ground
    state is gravitationally unstable (Q0 < 1, Toomre) that branch merges with the Jeans branch
    and the sign change found on the grid is not a root of the refined branch."""
    try:
        return brentq(f, a, b, **kw)
    except ValueError:
        lam = sorted((float(_to_lambda(p, a)), float(_to_lambda(p, b))))
        where = f"between {lam[0]:.1f} m and {lam[1]:.1f} m"
        s1 = p.Omega * p.c0 / (math.pi * G)  # sigma0 at Q0 = 1 [kg/m^2]
        if p.Q0 < 1.0:
            why = (f"Q0 = {p.Q0:.3g} < 1: the ground state is gravitationally (Toomre) unstable and the "
                   f"overstable branch no longer exists as a separate branch {where}; allowed for set "
                   f"{p.name!r}: Q0 > 1, i.e. sigma0 < {s1:.0f} kg/m^2")
        else:
            why = f"the overstable branch changes character {where} (Q0 = {p.Q0:.3g}, sigma0 = {p.sigma0:g} kg/m^2)"
        raise ValueError(f"{what} is not defined for {p.name} ({p.model}) at sigma0 = {p.sigma0:g} kg/m^2: "
                         f"{why}") from None


@dataclass(frozen=True)
class LinearSummary:
    """Numbers printed by ``ringcore linear`` (units in the field names; rates in Omega)."""

    set: str
    model: str
    sigma0: float
    p_s: float
    Q0: float
    lambda_J_m: float
    lambda_zero_m: float
    lambda_max_growth_m: float
    max_growth_rate: float
    overstable_band_m: list
    beta_c: float
    beta_c_approx: float
    F2: float
    F3: float
    F2_table: float
    F3_table: float

    def to_json_dict(self) -> dict:
        """Plain JSON-ready dict; nan and inf become None."""
        def clean(v):
            if isinstance(v, float) and not math.isfinite(v):
                return None
            if isinstance(v, (list, tuple)):
                return [clean(x) for x in v]
            return v
        return {k: clean(v) for k, v in asdict(self).items()}

    def to_dataset(self):
        """The numbers as an ``xarray.Dataset`` of scalars with ``units`` attributes (the overstable band as
        ``overstable_band_m`` over ``band`` and ``edge``); ``set`` and ``model`` as attributes."""
        import numpy as np
        import xarray as xr

        units = dict(sigma0="kg m-2", p_s="1", Q0="1", lambda_J_m="m", lambda_zero_m="m", lambda_max_growth_m="m",
                     max_growth_rate="Omega (dimensionless)", beta_c="1", beta_c_approx="1", F2="1", F3="1",
                     F2_table="1", F3_table="1")
        dv = {k: ((), float(getattr(self, k)), {"units": u}) for k, u in units.items()}
        band = np.asarray(self.overstable_band_m, float).reshape(-1, 2)
        dv["overstable_band_m"] = (("band", "edge"), band, {"units": "m", "long_name": "overstable wavelength bands"})
        return xr.Dataset(dv, coords={"edge": ["min", "max"]}, attrs={"set": self.set, "model": self.model})


def summary(p: RingParams) -> LinearSummary:
    """All characteristic numbers of the linear theory for ``p``."""
    require(p)
    F2, F3 = thermal_coefficients(p)
    lam_max, gmax = max_growth(p)
    return LinearSummary(
        set=p.name, model=p.model, sigma0=p.sigma0, p_s=p.p_s, Q0=p.Q0, lambda_J_m=p.lambda_J,
        lambda_zero_m=lambda_zero(p), lambda_max_growth_m=lam_max, max_growth_rate=gmax,
        overstable_band_m=[list(b) for b in overstable_band(p)],
        beta_c=beta_c(p), beta_c_approx=beta_c_approx(p, F3), F2=F2, F3=F3,
        F2_table=math.nan if p.isothermal else p.F2, F3_table=math.nan if p.isothermal else p.F3,
    )


def with_thermal_coefficients(p: RingParams) -> RingParams:
    """Copy of ``p`` whose F2, F3 are the exactly extracted values instead of the rounded table."""
    require(p)
    F2, F3 = thermal_coefficients(p)
    return replace(p, F2=F2, F3=F3)
