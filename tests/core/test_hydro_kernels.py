"""Building blocks of the compiled kernels: fast exp/log, MP5, AUSM splitting, ground state."""
import math

import numpy as np
import pytest
from numba import njit

from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.hydro import kernels as K
from ringcore.hydro.fastmath import vexp, vlog


@njit(cache=True)
def _vexp_arr(x, o):
    for i in range(x.size):
        o[i] = vexp(x[i])


@njit(cache=True)
def _vlog_arr(x, o):
    for i in range(x.size):
        o[i] = vlog(x[i])


@njit(cache=True)
def _mp5_arr(f, o):
    for i in range(2, f.size - 3):
        o[i] = K.mp5(f[i - 2], f[i - 1], f[i], f[i + 1], f[i + 2])


def test_fast_exp_log_accuracy():
    rng = np.random.default_rng(1)
    x = rng.uniform(-60, 60, 100000)
    o = np.empty_like(x)
    _vexp_arr(x, o)
    assert np.max(np.abs(o / np.exp(x) - 1)) < 3e-16
    y = np.exp(rng.uniform(-40, 40, 100000))
    _vlog_arr(y, o)
    assert np.max(np.abs(o - np.log(y))) < 3e-16 * np.maximum(1, np.abs(np.log(y))).max()
    special = np.array([0.0, -1.0, np.nan, np.inf, 1.0])
    o = np.empty(5)
    _vlog_arr(special, o)
    assert np.isnan(o[:3]).all() and o[3] == np.inf and o[4] == 0.0
    _vexp_arr(np.array([np.nan, 800.0, -800.0, 0.0, 1.0]), o)
    assert np.isnan(o[0]) and o[1] == np.inf and o[2] == 0.0 and o[3] == 1.0 and abs(o[4] / math.e - 1) < 3e-16


def test_mp5_fifth_order_on_smooth_data():
    """Interface values of cell averages of sin: MP5 is 5th-order accurate (limiter inactive)."""
    errs = []
    for n in (32, 64, 128):
        h = 2 * np.pi / n
        xi = h * np.arange(n + 5)  # cell i spans [x_i - h/2, x_i + h/2]
        avg = (np.cos(xi - h / 2) - np.cos(xi + h / 2)) / h  # cell averages of sin
        o = np.zeros_like(avg)
        _mp5_arr(avg, o)
        i = np.arange(2, n + 2)
        errs.append(np.max(np.abs(o[i] - np.sin(xi[i] + h / 2))))
    orders = [math.log2(a / b) for a, b in zip(errs, errs[1:])]
    assert min(orders) > 4.7


def test_mp5_monotone_at_a_jump():
    f = np.r_[np.zeros(10), np.ones(10)]
    o = np.zeros_like(f)
    _mp5_arr(f, o)
    assert o[2:17].min() >= -1e-14 and o[2:17].max() <= 1 + 1e-14


@pytest.mark.parametrize("iso", [False, True])
def test_ausm_split_sums_to_physical_flux(iso):
    p = params.get("tau15", sigma0=400, isothermal=iso)
    sim = Hydro1D(p, HydroOptions(L_x=100, h=1.0), initial="mode", wavelength=50, amplitude=0.3)
    rng = np.random.default_rng(2)
    sig, u, v, T = sim.primitives()
    sim.set_state(sig, u + rng.uniform(-3, 3, sim.n), v, T)  # subsonic and supersonic Mach numbers
    U = sim._U[0]
    W = sim._W
    K._primitives(U, W, sim._beta, sim._par)
    K._split_fluxes(U, W)
    s, u, pr = U[0], W[K.R_U], W[K.R_P]
    F = [s * u, s * u * u + pr, U[2] * u] + ([] if iso else [u * (U[3] + pr)])
    for k, Fk in enumerate(F):
        assert np.allclose(W[K.R_FP + k] + W[K.R_FM + k], Fk, rtol=1e-13, atol=1e-13)
        assert np.all(W[K.R_FP] >= 0) and np.all(W[K.R_FM] <= 0)  # mass flux split by sign


def test_ground_state_equilibrium_heating_balances_cooling():
    """Viscous heating of the background shear eta (3/2)^2 equals Gamma0 = 9/4 nu0."""
    p = params.get("tau15", sigma0=400)
    sim = Hydro1D(p, HydroOptions(L_x=100, h=1.0))
    L = sim._L[0]
    K.compute_rhs(sim._U[0], sim._W, sim._beta, sim.gravity.g, sim._par, L)
    assert np.max(np.abs(L[:, K.NG:-K.NG])) < 1e-15
    d = p.dimensionless()
    assert d["nu0"] * 1.5 ** 2 == pytest.approx(d["Gamma0"], rel=1e-15)


def test_cons_to_prim_inverts_to_conservative():
    """One temperature formula: cons_to_prim(to_conservative(prim)) = prim; isothermal T = T0."""
    from ringcore.hydro.convert import cons_to_prim, temperature

    rng = np.random.default_rng(4)
    n = 50
    prim = (1.0 + 0.5 * rng.random(n), rng.normal(size=n), rng.normal(size=n), 0.5 + rng.random(n))
    for nv in (4, 3):
        U = np.zeros((nv, n + 2 * K.NG))
        K.to_conservative(*prim, U)
        back = cons_to_prim(U[:, K.NG:K.NG + n], T0=0.7)
        for k in range(3):
            np.testing.assert_allclose(back[k], prim[k], rtol=1e-14, atol=1e-14)
        np.testing.assert_allclose(back[3], prim[3] if nv == 4 else 0.7, rtol=1e-13)
    assert temperature(3.0, 2.0) == (2.0 / 3.0) * (3.0 - 2.0)  # e/sigma = u^2/2 + 3T/2


@pytest.mark.parametrize("iso", [False, True])
def test_sample_fields_in_one_pass_are_cons_to_prim_bit_for_bit(iso):
    """The recorder's one-pass sample (state_kernels.sample_fields) gives the primitive fields, the kinetic
    energy and the extrema of the numpy expressions it replaced, bit for bit (a NaN too)."""
    from ringcore.hydro.convert import cons_to_prim
    from ringcore.hydro.diagnostics import e_kin_dimless

    sim = Hydro1D(params.get("tau15", sigma0=400, isothermal=iso), HydroOptions(L_x=500, h=2.5), initial="noise",
                  seed=4, amplitude=0.05)
    T0 = sim._par[K.P_T0]
    for bad in (False, True):
        U = sim.U.copy()
        if bad:
            U[1, 17] = np.nan
        prim, w = np.empty((4, sim.n)), np.empty(sim.n)
        K.sample_fields(U[0], U[1], U[2], U[-1], T0 if iso else 0.0, prim, w)
        ref = cons_to_prim(U, T0)
        for k in range(4):
            assert np.array_equal(prim[k].view(np.uint64), np.asarray(ref[k]).view(np.uint64))
        assert float(np.mean(w)) == e_kin_dimless(*ref[:3]) or (bad and np.isnan(np.mean(w)))
        assert np.array_equal(prim.min(axis=1), [f.min() for f in ref], equal_nan=True)
        assert np.isnan(prim.min(axis=1)[1]) == bad
