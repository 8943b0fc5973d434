"""Recipe "lambdap" (Figure 20's hydro panels): shipped sweeps grouped by set and model, full mode on Dask."""
from __future__ import annotations

import numpy as np
import pytest

from ringcore import linear, params
from ringcore.experiments import lambdap_recipe as lr


def test_shipped_sweeps_are_grouped_by_set_and_model():
    got = lr.shipped_sweeps()
    assert {("tau15", False), ("tau20", False), ("tau15", True)} <= set(got)
    sig, lam, sat, src = got[("tau15", False)]
    assert list(sig) == [100.0 * k for k in range(1, 10)]
    assert list(sat) == [False, False] + [True] * 7  # 100 and 200 still coarsening (app/data/README.md)
    ratio = lam[sat] / np.array([1.4 * linear.lambda_zero(params.get("tau15", sigma0=s)) for s in sig[sat]])
    assert np.all(np.abs(ratio - 1) < 0.2)
    assert "Caveat" in got[("tau20", False)][3] and "<sub>" not in got[("tau20", False)][3]
    assert got[("tau15", True)][0].max() <= 400.0  # 500-900 blew up: no points


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_full_mode_runs_a_resumable_dask_sweep(tmp_path, monkeypatch):
    monkeypatch.setattr(lr, "FULL_SWEEP", dict(lx=200.0, h=5.0, orbits=3.0))
    tasks = lr.full_tasks("tau15", False, (300.0, 600.0))
    assert [t["sigma0"] for t in tasks] == [300.0, 600.0] and all(t["lx"] == 200.0 for t in tasks)
    sig, lam, sat, src = lr.swept_points("tau15", False, (300.0, 600.0), tmp_path / "runs", n_workers=1)
    assert sorted(sig) == [300.0, 600.0] and "1 workers" in src
    m = 200.0 / lam  # a prevalent wavelength is one of the box's L_x / m
    np.testing.assert_allclose(m, np.round(m), atol=1e-9)
    files = sorted(p.name for p in (tmp_path / "runs").glob("hydro_*.nc"))
    assert len(files) == 2
    again = lr.swept_points("tau15", False, (300.0, 600.0), tmp_path / "runs", n_workers=1)
    np.testing.assert_array_equal(np.sort(again[1]), np.sort(lam))  # finished runs are read back, not rerun


def test_bad_panel_is_refused():
    with pytest.raises(ValueError, match="parameter set"):
        lr.full_tasks("tau99", False, (100.0,))
    with pytest.raises(ValueError, match="isothermal"):
        lr.full_tasks("st99", False, (100.0,))


def test_full_tau20_panel_uses_the_finer_grid():
    """tau20 non-isothermal is under-resolved at h = 2.5 m (README, "Departures"): its full-mode runs use 1.25 m;
    the other panels keep FULL_SWEEP."""
    tau20 = lr.full_tasks("tau20", False, (500.0,))[0]
    assert tau20["h"] == 1.25 and tau20["lx"] == 4000.0
    assert lr.full_tasks("tau15", False, (500.0,))[0]["h"] == lr.FULL_SWEEP["h"] == 2.5
    assert lr.full_tasks("tau15", True, (500.0,))[0]["h"] == 2.5
    assert lr.FULL_PANEL[("tau20", False)]["sigma0"] == tuple(100.0 * k for k in range(1, 10))


def test_resolved_h_refines_only_the_models_that_need_it():
    from ringcore.experiments.resolution import H_PAPER, resolved_h

    assert resolved_h("tau20", False) == 1.25 and resolved_h("tau20", True) == H_PAPER == 2.5
    assert resolved_h("tau15", False) == 2.5 and resolved_h("tau20", False, h=1.0) == 1.0  # never coarser


@pytest.mark.parametrize("set_name", ["tau15", "tau20"])
def test_etauhydro_full_mode_uses_the_papers_grids(set_name):
    """Figure 14 (Section "nonisosg"): 20 km at h = 2.5 m, 5 km at h = 1 m for sigma0 >= 700; tau20 gets the
    1.25 m it needs below that; quick mode stays at 1 km, 2.5 m."""
    from ringcore.experiments.hydro_sg_recipes import etau_grid

    assert etau_grid("quick", set_name, 900.0) == (1000.0, 2.5)
    assert etau_grid("full", set_name, 700.0) == etau_grid("full", set_name, 1100.0) == (5000.0, 1.0)
    assert etau_grid("full", set_name, 600.0) == (20000.0, 1.25 if set_name == "tau20" else 2.5)
