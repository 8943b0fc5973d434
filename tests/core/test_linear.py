"""Exact linear theory (eq. matni) checked against independent answers."""
import math
from dataclasses import replace

import numpy as np
import pytest

from ringcore import linear, params

SETS = params.NONISOTHERMAL_SETS


@pytest.mark.parametrize("name", SETS)
def test_F2_F3_reproduce_table(name):
    p = params.get(name)
    F2, F3 = linear.thermal_coefficients(p)
    assert abs(F2 - p.F2) < 0.02 and abs(F3 - p.F3) < 0.02, (F2, F3, p.F2, p.F3)


def test_isothermal_has_no_thermal_corrections():
    F2, F3 = linear.thermal_coefficients(params.get("tau15").isothermal_limit(2.41))
    assert abs(F2) < 1e-6 and abs(F3) < 1e-6


@pytest.mark.parametrize("name", SETS)
@pytest.mark.parametrize("sigma0", [0.0, 400.0])
def test_eigenvalues_solve_the_determinant(name, sigma0):
    """Independent of eig: Det[A(k) - omega I] = 0 at the tracked omega."""
    p = params.get(name, sigma0=sigma0)
    k = np.geomspace(1e-3, 30, 60)
    om, _, _ = linear.track_overstable(p, k)
    A = linear.system_matrix(p, k)
    n = A.shape[-1]
    det = np.linalg.det(A - om[:, None, None] * np.eye(n))
    scale = np.prod(np.abs(np.linalg.eigvals(A)) + np.abs(om)[:, None], axis=1)
    assert np.all(np.abs(det) < 1e-10 * scale)


@pytest.mark.parametrize("name", SETS)
def test_osmode1_agrees_to_order_k3(name):
    """eq. (osmode1) with F2, F3 extracted at sigma0 = 0 predicts the self-gravitating branch to O(k^3)."""
    F2, F3 = linear.thermal_coefficients(params.get(name))
    p = params.get(name, sigma0=400.0)
    d = p.dimensionless()
    q = p.inv_Q0
    k = np.array([0.02, 0.01, 0.005, 0.0025])
    om, _, _ = linear.track_overstable(p, k)
    approx = (1j - 1j * q * k + k**2 * (d["nu0"] * (2 + 9 * d["beta"] - 3 * d["gamma"]) / 6
              + 0.5j * (d["p_s"] - q * q) + 0.5 * (1j * F2 + F3)))
    err = np.abs(om - approx)
    ratios = err[:-1] / err[1:]
    assert np.all(ratios > 6.5) and np.all(ratios < 9.5), ratios  # halving k divides the error by ~8
    assert np.all(err / k**3 < 50)


def test_isothermal_inviscid_limit_is_epicyclic_sound_wave():
    """nu0 -> 0, no self-gravity: omega_I = sqrt(1 + p_s k^2) exactly (3x3 model)."""
    p = replace(params.get("tau15").isothermal_limit(1.7), nu0=1e-12)
    k = np.geomspace(1e-3, 20, 50)
    om, _, _ = linear.track_overstable(p, k)
    assert np.allclose(om.imag, np.sqrt(1 + 1.7 * k**2), rtol=1e-9)
    assert np.all(np.abs(om.real) < 1e-6)  # nu0 = 1e-12 m^2/s is ~3e-10 c0^2/Omega


def test_isothermal_inviscid_with_self_gravity():
    """omega_I^2 = 1 - 2 k/Q0 + p_s k^2 (Toomre's relation) in the inviscid isothermal limit."""
    p = replace(params.get("tau15", sigma0=300).isothermal_limit(1.0), nu0=1e-12)
    k = np.geomspace(1e-3, 20, 50)
    om, _, _ = linear.track_overstable(p, k)
    assert np.allclose(om.imag, np.sqrt(1 - 2 * p.inv_Q0 * k + k**2), rtol=1e-9)


@pytest.mark.parametrize("name", ["tau15", "tau20"])
def test_nonisothermal_converges_to_isothermal_as_GT_grows(name):
    p = params.get(name, sigma0=400)
    iso = p.isothermal_limit(p.p_s)
    lam = np.geomspace(30, 3000, 40)
    ref = linear.dispersion(iso, lam).omega
    errs = []
    for GT in (1e1, 1e2, 1e3, 1e4):
        q = replace(p, G_T=GT)
        errs.append(np.max(np.abs(linear.dispersion(q, lam).omega - ref)))
    errs = np.array(errs)
    assert np.all(np.diff(errs) < 0)
    assert errs[-1] < 1e-3 * errs[0] * 10 and errs[-1] < 1e-4


@pytest.mark.parametrize("name", SETS)
@pytest.mark.parametrize("sigma0", [0.0, 800.0])
def test_branch_is_continuous_and_group_velocity_is_derivative(name, sigma0):
    """No branch jumps down to 0.5 m; v_g equals the numerical derivative of omega_I."""
    p = params.get(name, sigma0=sigma0)
    lam = np.geomspace(0.5, 2e4, 4000)
    d = linear.dispersion(p, lam)
    dk = np.abs(np.diff(d.k))
    jumps = np.abs(np.diff(d.omega)) / dk
    slope = np.abs(d.domega_dk)
    assert np.all(jumps < 1.5 * np.maximum(slope[1:], slope[:-1]) + 1e-6)
    num = np.gradient(d.frequency, d.k)
    # below ~5-12 m viscosity overdamps the pair (omega_I -> 0, exceptional point): compare above 20 m
    ok = lam > 20.0
    assert np.all(d.frequency[ok] > 0.1)
    assert np.allclose(d.group_velocity[ok][5:-5], num[ok][5:-5], rtol=2e-3, atol=1e-4)


def test_lambda_zero_decreases_with_sigma0_and_absent_without_gravity():
    assert math.isnan(linear.lambda_zero(params.get("tau15", sigma0=0)))
    lz = [linear.lambda_zero(params.get("tau15", sigma0=s)) for s in (100, 200, 400, 600, 800, 1000)]
    assert np.all(np.isfinite(lz)) and np.all(np.diff(lz) < 0), lz
    lzi = [linear.lambda_zero(params.get("tau15", sigma0=s).isothermal_limit()) for s in (200, 400, 800)]
    assert np.all(np.array(lzi) < np.array(lz[1:5:2][:1] + [lz[2], lz[4]]))  # isothermal shifted to smaller


def test_lambda_zero_is_frequency_minimum():
    p = params.get("tau15", sigma0=400)
    lz = linear.lambda_zero(p)
    lam = np.geomspace(20, 2000, 3000)
    d = linear.dispersion(p, lam)
    assert lam[np.argmin(d.frequency)] == pytest.approx(lz, rel=3e-3)
    # isothermal, Q0 >> 1: lambda_zero ~ 2 p_s lambda_J (Section "Comparison to Previous Studies")
    q = params.get("tau15", sigma0=20).isothermal_limit(1.0)
    assert linear.lambda_zero(q) == pytest.approx(2 * 1.0 * q.lambda_J, rel=0.05)


def test_max_growth_and_band():
    p = params.get("tau15", sigma0=400)
    lam_max, gmax = linear.max_growth(p)
    lam = np.geomspace(10, 1e4, 5000)
    d = linear.dispersion(p, lam)
    assert gmax == pytest.approx(d.growth_rate.max(), rel=1e-4)
    assert lam_max == pytest.approx(lam[np.argmax(d.growth_rate)], rel=5e-3)
    (short, long_), = linear.overstable_band(p)
    assert math.isinf(long_)
    assert linear.dispersion(p, [short * 0.99]).growth_rate[0] < 0 < linear.dispersion(p, [short * 1.01]).growth_rate[0]


def test_beta_c():
    p = params.get("tau15")
    bc = linear.beta_c(p)
    # growth coefficient changes sign at beta_c
    lo = linear.small_k_coefficients(p.with_beta(bc - 0.05))[1].real
    hi = linear.small_k_coefficients(p.with_beta(bc + 0.05))[1].real
    assert lo < 0 < hi
    # isothermal ideal gas: eq. (osgrate) gives beta_c = (gamma - 2/3)/3 exactly
    iso = params.get("st99")
    assert linear.beta_c(iso) == pytest.approx((1 - 2 / 3) / 3, abs=1e-6)
    assert linear.beta_c_approx(p) == pytest.approx((1.99 - 2 / 3 + 0.26 / p.dimensionless()["nu0"]) / 3)


@pytest.mark.parametrize("direction", ["left", "right"])
def test_eigenmode_solves_linear_problem(direction):
    p = params.get("tau15", sigma0=350)
    m = linear.eigenmode(p, 200.0, direction)
    A = linear.system_matrix(p, [m.k])[0]
    v = m.vector.copy()
    if direction == "right":
        v[1:3] *= -1
    assert np.allclose(A @ v, m.omega * v, atol=1e-12)
    assert m.vector[0] == 1
    x = np.linspace(0, 2 * np.pi / m.k, 64, endpoint=False)
    f0, f1 = m.fields(x, 0.0), m.fields(x, 0.3)
    # the density crest moves in the stated direction
    shift = np.angle(np.sum(f1[0] * np.exp(-1j * m.k * x)) / np.sum(f0[0] * np.exp(-1j * m.k * x)))
    # projection on exp(+i k x): phase grows with t for a left-mover (crest at x = -(omega_I t)/k)
    assert (shift > 0) == (direction == "left") and abs(abs(shift) - 0.3 * m.omega.imag) < 1e-6


def test_units_of_dispersion_results():
    p = params.get("tau15", sigma0=400)
    d = linear.dispersion(p, [150.0])
    assert d.growth_rate_per_s[0] == pytest.approx(d.growth_rate[0] * p.Omega)
    assert d.group_velocity_m_s[0] == pytest.approx(d.group_velocity[0] * p.c0)
    assert d.k[0] == pytest.approx(2 * np.pi / 150.0 * p.c0 / p.Omega)
    with pytest.raises(ValueError, match="wavelength_m"):
        linear.dispersion(p, [100.0, -1.0])
