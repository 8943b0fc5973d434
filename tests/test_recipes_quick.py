"""Reduced ("ci") forms of the recipes "grates" and "nlvg" and the registry of all recipes.

The full --quick runs of every recipe take minutes each; they are run by
``scripts/run_quick_recipes.py`` (wall-time table), not in the test suite.
"""
import math

import numpy as np
import pytest

from ringcore import linear, params
from ringcore.experiments import saturation_recipes
from ringcore.experiments.hydro_recipes import _grates_frequency, _grates_growth
from ringcore.experiments.registry import load_all
from ringcore.io import read_run

PAPER_FIGURES = ("grates", "tau15nga", "ekinisonosg", "ekincompare", "tau15bufnosg", "tau20nonisonosga", "sgstable",
                 "etauhydro", "tau15nonisoweaksg", "nblin1", "nblin2", "enbody", "vdispnb", "boxdouble", "lambdap",
                 "nlvg", "nbvga", "radvar", "osfrat", "boxsizecomp01", "vgpert")


def test_every_computed_figure_has_a_recipe_with_costs():
    rec = load_all()
    for name in PAPER_FIGURES:
        assert name in rec, name
        r = rec[name]
        assert r.figure == f"fig:{name}"
        assert r.quick_cost and r.full_cost


@pytest.mark.parametrize("sigma0", [0.0, 600.0])
def test_grates_ci_growth_rates(sigma0):
    """Figure grates, growth part: 1 km box of white noise, modes split into left/right eigenmodes.
    Wire kernel (5 replicas + bin correction) for sigma0 > 0, as in the paper: within 1 % of
    eq. (evp) where |omega_R| > 2e-3, within 2e-5 absolute elsewhere."""
    p = params.get("tau15", sigma0=sigma0)
    lam, g = _grates_growth(p, 2.5, 10.0)
    gl = linear.dispersion(p, lam).growth_rate
    big = np.abs(gl) > 2e-3
    assert np.max(np.abs(g[big] / gl[big] - 1)) < 0.01
    assert np.max(np.abs(g[~big] - gl[~big])) < 2e-4


def test_grates_ci_frequency():
    p = params.get("tau15", sigma0=350.0)
    for lam in (80.0, 200.0):
        w = _grates_frequency(p, lam, lam / 40, 6.0)
        assert abs(w / linear.dispersion(p, [lam]).frequency[0] - 1) < 0.01


def test_nlvg_ci(tmp_path):
    """Reduced Figure nlvg: sigma0 = 400, three wavelengths. The nonlinear frequency minimum lies at a
    larger wavelength than the linear lambda_zero (129 m), and the saturated frequencies exceed the
    linear ones at short wavelengths (paper: panel a)."""
    res = saturation_recipes.nlvg("quick", tmp_path, sigmas=(400.0,), wavelengths=(120.0, 170.0, 240.0))
    assert res.png.stat().st_size > 20_000
    ds = read_run(res.data, kind="recipe")
    lz_nl = float(ds.lambda_zero_nonlinear[0])
    lz_lin = float(ds.lambda_zero_linear[0])
    assert math.isfinite(lz_nl) and 120.0 < lz_nl < 240.0
    assert lz_nl > 1.15 * lz_lin
    w, wl = ds.frequency_s400.values, ds.linear_frequency_s400.values
    assert w[0] > wl[0] + 0.01
    assert ds.caption == res.caption
