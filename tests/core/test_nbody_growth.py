"""Seeded linear overstable mode: growth and frequency vs the hydrodynamic prediction."""
import math

import numpy as np
import pytest

from ringcore import analysis, linear, params
from ringcore.nbody import NBodyOptions, ShearingBox, growth


@pytest.mark.parametrize("g,w", [(0.006, 1.04), (-0.01, 1.2)])
def test_fit_mode_recovers_synthetic_standing_wave(g, w):
    rng = np.random.default_rng(0)
    t = np.linspace(0, 150, 1500)
    U = np.exp(g * t) * (1.3 * np.exp(1j * w * t) + 0.9 * np.exp(-1j * w * t + 0.4))
    U = U + 0.02 * (rng.normal(size=t.size) + 1j * rng.normal(size=t.size))
    gm, wm, wl, _, _ = analysis.complex_mode_fit(t, U)
    assert gm == pytest.approx(g, abs=5e-4)
    assert wm == pytest.approx(w, abs=2e-3)
    assert wl == pytest.approx(w, abs=0.02)


@pytest.mark.slow
def test_seeded_mode_grows_at_hydro_rate():
    """tau = 1.5, sigma0 = 0, lambda = 150 m: omega_R, omega_I near eq. (evp) (paper: Figures nblin1/2)."""
    p = params.get("tau15")
    box = ShearingBox(p, NBodyOptions(L_x=150, L_y=25, restitution="bridges"), seed=1)
    box.run(6)
    box.seed_mode(1, 2.0)
    g = growth.measure(box, 1, 30)
    d = linear.dispersion(p, [150.0])
    assert g.growth_rate > 0  # overstable
    assert g.growth_rate == pytest.approx(d.growth_rate[0], rel=0.6)
    assert g.frequency == pytest.approx(d.frequency[0], rel=0.03)
    assert abs(g.amplitude[-1]) > 1.5 * abs(g.amplitude[:40]).max() / 2
    assert math.isfinite(g.frequency_lomb)
