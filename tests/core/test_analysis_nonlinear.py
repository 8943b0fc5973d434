"""Nonlinear dispersion relation tools (ringcore.experiments.nonlinear), Section "Nonlinear Dispersion Relation"."""
import math

import numpy as np
import pytest

from ringcore import linear, params
from ringcore.experiments.nonlinear import (frequency_minimum, group_velocity, hydro_frequency,
                                            hydro_seed_amplitude, to_arrays)


@pytest.mark.parametrize("set_name, sigma0, lam", [("tau15", 400.0, 200.0), ("tau15", 0.0, 120.0)])
def test_small_amplitude_frequency_is_linear(set_name, sigma0, lam):
    """A tiny seed stays linear: the measured frequency equals omega_I of eq. (matni) within 1 %."""
    p = params.get(set_name, sigma0=sigma0)
    r = hydro_frequency(p, lam, amplitude=1e-4, orbits=8, discard=0.0, nodes=50)
    assert r.status == "ok" and r.dominant
    assert abs(r.frequency / r.linear_frequency - 1) < 0.01
    assert abs(r.frequency_phase / r.linear_frequency - 1) < 1e-3  # independent phase-slope estimate


def test_large_amplitude_shifts_frequency():
    """A saturated tau15 wave at 100 m (sigma0 = 400) oscillates faster than the linear mode (Figure nlvg a)."""
    p = params.get("tau15", sigma0=400.0)
    r = hydro_frequency(p, 100.0, amplitude=0.3, orbits=12, discard=4.0, nodes=40)
    assert r.status == "ok"
    assert r.frequency > r.linear_frequency + 0.005


def test_seed_amplitude_cap():
    p = params.get("tau15", sigma0=400.0)
    assert hydro_seed_amplitude(p, 100.0) == 0.3
    a = hydro_seed_amplitude(p, 2000.0, u_max=5.0)
    u = abs(linear.eigenmode(p, 2000.0).vector[1])
    assert a < 0.3 and math.isclose(a * u, 5.0)


def test_frequency_minimum_on_linear_curve():
    """On the exact linear curve the finder returns lambda_zero (features.lambda_zero) within 2 %."""
    p = params.get("tau15", sigma0=400.0)
    lam = np.geomspace(50, 1000, 40)
    w = linear.dispersion(p, lam).frequency
    lz, wmin = frequency_minimum(lam, w)
    assert abs(lz / linear.lambda_zero(p) - 1) < 0.02
    assert abs(wmin - w.min()) < 1e-3


def test_frequency_minimum_synthetic_parabola_and_edges():
    lam = np.array([300, 60, 100, 150, 200, 500.0])  # unsorted on purpose
    w = 0.95 + 0.02 * (np.log(lam) - np.log(137.0)) ** 2
    lz, wmin = frequency_minimum(lam, w)
    assert lz == pytest.approx(137.0, rel=1e-9) and wmin == pytest.approx(0.95, abs=1e-12)
    mono = np.linspace(1.0, 0.9, 6)  # minimum at the last point: no interior minimum
    assert all(math.isnan(v) for v in frequency_minimum(np.sort(lam), mono))
    w2 = w.copy()
    w2[2] = np.nan  # nan samples are skipped
    assert np.isfinite(frequency_minimum(lam, w2)[0])


def test_group_velocity_matches_exact_linear():
    """3-point Lagrange derivative of the linear omega_I(k) equals the exact v_g (eq. vg) within 1 %."""
    p = params.get("tau15", sigma0=400.0)
    lam = np.geomspace(60, 1500, 200)
    d = linear.dispersion(p, lam)
    vg = group_velocity(lam, d.frequency, p.Omega)
    ref = d.group_velocity_m_s
    big = np.abs(ref) > 0.05 * np.abs(ref).max()
    assert np.max(np.abs(vg[big] / ref[big] - 1)) < 0.01


def test_bad_input():
    p = params.get("tau15", sigma0=400.0)
    with pytest.raises(ValueError, match="wavelength_m"):
        hydro_frequency(p, -5.0)
    with pytest.raises(ValueError, match="discard"):
        hydro_frequency(p, 100.0, orbits=10, discard=20)
    with pytest.raises(ValueError, match="Omega"):
        group_velocity([1, 2, 3], [1, 2, 3], 0.0)
    assert to_arrays([]) == {}
