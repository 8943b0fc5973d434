"""ringcore.analysis.summary: the saturation summary of a run, against hand-computed values."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore.analysis.summary import saturation_flag, series_summary, strobe_wavelength, summary
from ringcore.hydro import Hydro1D, HydroOptions


def test_series_summary_uses_the_last_fraction():
    t = np.arange(11.0)  # last 25 %: t >= 7.5 -> 8, 9, 10
    lam = np.array([1, 1, 1, 1, 1, 1, 1, 1, 200, 300, 200.0])
    e = np.arange(11.0)
    s = series_summary(t, lam, e, 0.25)
    assert s == dict(lambda_p_m=200.0, lambda_p_mean_m=pytest.approx(700 / 3), e_kin=9.0)
    s = series_summary(t, np.where(t > 8, np.nan, lam), e, 0.25)  # non-finite lambda_p ignored
    assert s["lambda_p_m"] == 200.0 and s["lambda_p_mean_m"] == 200.0
    assert all(math.isnan(v) for v in series_summary([], [], [], 0.25).values())


def test_saturation_flag_sees_coarsening_in_the_last_quarter():
    t = np.arange(0.0, 1000.0, 1.0)  # last quarter: t >= 749.25 -> 750..999, halves at 874.5
    settled = np.where(t < 500, 100.0, 142.9)
    assert saturation_flag(t, settled) == dict(saturated=1.0, lambda_p_growth=1.0)
    coarsening = np.where(t < 900, 137.9, 142.9)  # a merge at orbit 900, inside the last quarter
    f = saturation_flag(t, coarsening)
    assert f["saturated"] == 0.0 and f["lambda_p_growth"] == pytest.approx(142.9 / 137.9)
    shrinking = np.where(t < 900, 142.9, 137.9)  # lambda_p jumping to a shorter allowed value: not growth
    assert saturation_flag(t, shrinking)["saturated"] == 1.0
    jitter = np.where(t % 3 == 0, 137.9, 142.9)  # two allowed values alternating, same share in both halves
    assert saturation_flag(t, jitter)["saturated"] == 1.0
    assert all(math.isnan(v) for v in saturation_flag(t[:3], settled[:3]).values())
    assert all(math.isnan(v) for v in saturation_flag([], []).values())


def test_strobe_wavelength_finds_the_dominant_mode():
    L, n = 1000.0, 200
    x = np.arange(n) * L / n
    rows = np.array([1 + 0.1 * np.cos(2 * np.pi * 4 * x / L + k) + 0.01 * np.cos(2 * np.pi * 9 * x / L)
                     for k in range(8)], np.float32)
    assert strobe_wavelength(np.arange(8.0), rows, L, 0.5) == pytest.approx(L / 4)
    assert math.isnan(strobe_wavelength(np.arange(1.0), rows[:1], L))


def test_summary_of_a_hydro_run_matches_its_series():
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=400, h=2.5), initial="noise", seed=1)
    sim.advance(orbits=2.0)
    s, a = summary(sim), sim.series()
    t = a["t"]
    sel = t >= t[-1] - 0.25 * (t[-1] - t[0])
    assert s["orbits"] == pytest.approx(2.0) and s["steps"] == sim.steps
    assert s["e_kin"] == pytest.approx(a["e_kin"][sel].mean(), rel=1e-15)
    sig, _, _, T = sim.primitives()
    assert s["c_mean"] == pytest.approx(np.average(np.sqrt(T), weights=sig) * sim.params.scales.velocity, rel=1e-12)
    assert s == summary(sim.snapshot()) == sim.summary()
    with pytest.raises(ValueError, match="kind"):
        st = sim.snapshot()
        st.kind = "nbody"
        summary(st)
