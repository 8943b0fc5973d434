"""Helpers of the panels added to recipes "vdispnb" (hydro points), "boxdouble" (right panel: final PSD)
and "radvar" (spreading boundaries), each against an independent answer (a few seconds in all)."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore.experiments import nbody_saturation_recipes as R
from ringcore.experiments.registry import load_all
from ringcore.nbody import NBodyOptions, ShearingBox


@pytest.mark.parametrize("name", ["tau15", "tau15_oz2", "tau20"])
def test_hydro_dispersion_ground_state(name):
    """The uniform non-isothermal ground state keeps T = T0: the hydro point is the table's sqrt(T0)
    [m/s] (Table "tab:hydropar"; T0/c0^2 differs between the sets, so the unit conversion is checked)."""
    p = params.get(name, sigma0=300.0)
    c, status, sim = R.hydro_dispersion(p, 100.0, 2.0, initial="ground")
    assert status == "ok" and sim.orbits == pytest.approx(2.0, abs=0.05)
    assert c == pytest.approx(math.sqrt(p.T0), rel=1e-6)


@pytest.mark.parametrize("R_p, m", [(1.0, 3), (2.0, 5)])
def test_final_psd_of_a_density_wave(R_p, m):
    """Particles placed with surface density 1 + 0.8 cos(2 pi m x / L_x) (inverse-CDF quantiles): the
    final PSD (boxdouble's inset) peaks at L_x / m [m] for any particle radius."""
    L = 150.0  # [R_p]
    n = 3000
    u = (np.arange(n) + 0.5) / n
    xs = np.linspace(-L / 2, L / 2, 20001)
    cdf = (xs + L / 2 + 0.8 * L / (2 * np.pi * m) * np.sin(2 * np.pi * m * xs / L)) / L
    pos = np.zeros((n, 3))
    pos[:, 0] = np.interp(u, cdf, xs)
    pos[:, 1] = (np.arange(n) * 0.618034 % 1.0 - 0.5) * 10.0
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=L * R_p, L_y=10.0 * R_p, R_p=R_p),
                      state=(pos, np.zeros((n, 3)), 0.0))
    lam, P = R.final_psd(box)
    assert lam[np.argmax(P)] == pytest.approx(L * R_p / m, rel=1e-9)
    assert P.max() == 1.0 and np.sort(P)[-2] < 0.05


def test_filled_from_and_most_frequent():
    """8 zones, strip |x| < 0.5 L_x / 2 filled first: the outer zones are 0, 1, 6, 7."""
    t = np.arange(5.0)
    rows = [[0, 0, 2, 2, 2, 2, 0, 0],
            [0.2, 0.4, 1.7, 1.7, 1.7, 1.7, 0.2, 0.1],  # outer mean 0.225
            [0.4, 0.6, 1.5, 1.5, 1.5, 1.5, 0.6, 0.4],  # 0.5: filled at t = 2
            [0.0, 1.2, 1.0, 1.0, 1.0, 1.0, 0.9, 0.9],  # a wave trough empties zone 0: still filled
            [1.0] * 8]
    assert R.filled_from(t, rows, 0.5) == 2.0
    assert R.filled_from(t, rows, 0.5, threshold=0.9) == 4.0  # row 3: outer mean 0.75
    assert math.isnan(R.filled_from(t[:2], rows[:2], 0.5))
    assert R.most_frequent([75.0, 150.0, 75.0, np.nan, 50.0]) == 75.0
    assert math.isnan(R.most_frequent([np.nan]))


def test_moved_recipes_registered():
    rec = load_all()
    for name in ("vdispnb", "boxdouble", "radvar"):
        assert rec[name].func.__module__ == R.__name__
        # full mode: the cost in CPU hours, and whether it fits a 2-core machine
        assert "CPU h" in rec[name].full_cost
        assert ("beyond 2 cores" in rec[name].full_cost) == (name != "radvar")
