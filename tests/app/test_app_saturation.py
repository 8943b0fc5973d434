"""Headless tests of the Saturation tab and of the session's shared run log (no browser)."""
from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import ringlab.tabs.saturation.view as sv
from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.tabs.saturation import SaturationView, load_sweep, theory_curves
from ringlab.live.session import SessionRuns
from ringcore import linear, params


def test_theory_curves_are_eq_lambdasigma_and_the_fastest_growing_wavelength():
    c = theory_curves("tau15", False)
    for j in (0, 10, len(c["sigma0"]) - 1):
        p = params.get("tau15", float(c["sigma0"][j]))
        assert c["empirical"][j] == pytest.approx(1.4 * linear.lambda_zero(p), rel=1e-9)
        assert c["fastest"][j] == pytest.approx(linear.max_growth(p)[0], rel=1e-9)
    assert np.all(np.diff(c["empirical"]) < 0)  # denser rings, shorter saturated waves (Figure "lambdap")
    iso = theory_curves("tau15", True)
    p = params.get("tau15", float(iso["sigma0"][5])).isothermal_limit(1.0)
    assert iso["empirical"][5] == pytest.approx(1.4 * linear.lambda_zero(p), rel=1e-9)


def _sweep(path, rows):
    tasks = [json.dumps({"engine": "hydro", "set": s, "sigma0": x, "isothermal": iso}) for s, x, _, iso in rows]
    ds = xr.Dataset({"lambda_p_m": ("run", np.array([r[2] for r in rows]))},
                    coords={"sigma0": ("run", np.array([r[1] for r in rows])),
                            "task": ("run", np.array(tasks, dtype=object))})
    ds.to_netcdf(path, engine="h5netcdf")


def test_sweep_file_missing_present_and_damaged(tmp_path, monkeypatch):
    pts, note = load_sweep(tmp_path / "none.nc")
    assert pts == [] and "only the theory curves" in note
    f = tmp_path / "sweep.nc"
    _sweep(f, [("tau15", 200.0, 400.0, False), ("tau15", 600.0, np.nan, False), ("tau20", 400.0, 180.0, False)])
    pts, note = load_sweep(f)
    assert note == "" and [(p["set"], p["sigma0"], p["lambda_p_m"]) for p in pts] == [
        ("tau15", 200.0, 400.0), ("tau20", 400.0, 180.0)]
    monkeypatch.setattr(sv, "SWEEP_FILE", f)
    v = SaturationView()
    assert not v.note.visible
    assert list(v.sweep_source.data["lambda_p"]) == [400.0, 180.0]
    assert list(v.sweep_source.data["alpha"]) == [1.0, 0.3]  # the other set is drawn faint
    v.param_set = "tau20"
    assert list(v.sweep_source.data["alpha"]) == [0.3, 1.0]
    bad = tmp_path / "bad.nc"
    bad.write_bytes(b"not a netcdf file")
    pts, note = load_sweep(bad)
    assert pts == [] and "cannot be read" in note


def test_invalid_model_gives_a_message_and_keeps_the_curves():
    v = SaturationView()
    before = v.curve_source.data
    v.param_set = "st99"  # isothermal only: switched for the user with a note
    assert v.isothermal and not v.model_error.visible and v.curve_source.data is not before
    assert v.model_note.visible and "switched on for you" in v.model_note.object
    before = v.curve_source.data
    v.isothermal = False  # unticked by hand: a message, the curves stay
    assert v.model_error.visible and "st99" in v.model_error.object
    assert v.curve_source.data is before
    v.isothermal = True
    assert not v.model_error.visible


def test_user_runs_of_another_set_are_greyed():
    """Switching to tau20 greys the user's tau15 run like the tau15 sweep points."""
    runs = SessionRuns()
    v = SaturationView(runs=runs)
    runs.points = [dict(sigma0=400.0, lambda_p_m=180.0, orbits=50.0, isothermal=False, set="tau15", label="a"),
                   dict(sigma0=300.0, lambda_p_m=200.0, orbits=50.0, isothermal=False, set="tau20", label="b")]
    assert list(v.user_source.data["alpha"]) == [1.0, 0.3]
    v.param_set = "tau20"
    assert list(v.user_source.data["alpha"]) == [0.3, 1.0]
    v.isothermal = True
    assert list(v.user_source.data["alpha"]) == [0.3, 0.3]


def test_add_my_run():
    runs = SessionRuns()
    v = SaturationView(runs=runs)
    v._add()
    assert "no hydro run" in v.message.object and runs.points == []
    r = HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5))
    runs.hydro = r
    v._add()
    assert "only 0.0 orbits" in v.message.object
    r.advance(60.0, until=24.0)
    assert r.sim.orbits == pytest.approx(24.0)
    v._add()
    assert runs.points and 'class="msg-ok"' in v.message.object
    pt = runs.points[-1]
    t, lam = r.series.get("t"), r.series.get("lambda_p")
    assert pt["lambda_p_m"] == pytest.approx(np.median(lam[t >= 0.75 * t[-1]]))
    assert pt["sigma0"] == 400.0 and pt["lambda_p_m"] in (500.0 / np.arange(1, 200))
    assert list(v.user_source.data["lambda_p"]) == [pt["lambda_p_m"]]


def test_sessions_do_not_share_runs():
    """create_app gives each session its own SessionRuns, passed to the tabs that declare ``runs``."""
    from ringlab import main

    assert [t for t, _ in main.TABS][:4] == ["Linear theory", "Hydrodynamics", "N-body", "Saturation"]
    sessions = []
    for _ in range(2):
        runs = SessionRuns()
        sessions.append((runs, [main._make(factory, runs) for _, factory in main.TABS]))
    (runs_a, (_, hydro_a, nbody_a, sat_a, *_)), (runs_b, (_, hydro_b, nbody_b, sat_b, *_)) = sessions
    assert sat_a.runs is runs_a and runs_a.hydro is hydro_a.runner
    assert sat_b.runs is runs_b and runs_b.hydro is hydro_b.runner
    assert hydro_a.runner is not hydro_b.runner and nbody_a.runner is not nbody_b.runner
    hydro_a.runner.settings.sigma0 = 800.0
    assert hydro_b.runner.sim.params.sigma0 == 400.0


def test_all_shipped_sweeps_are_loaded(tmp_path, monkeypatch):
    """SWEEP_FILE plus every saturation_sweep_*.nc next to it; a missing main file is no error then."""
    main, extra = tmp_path / "saturation_sweep.nc", tmp_path / "saturation_sweep_tau20.nc"
    _sweep(extra, [("tau20", 400.0, 180.0, False), ("tau20", 800.0, 120.0, False)])
    monkeypatch.setattr(sv, "SWEEP_FILE", main)
    assert sv.sweep_files() == [main, extra]
    pts, note = sv.load_sweeps(sv.sweep_files())
    assert note == "" and [p["lambda_p_m"] for p in pts] == [180.0, 120.0]
    _sweep(main, [("tau15", 200.0, 400.0, False)])
    pts, note = sv.load_sweeps(sv.sweep_files())
    assert note == "" and [p["set"] for p in pts] == ["tau15", "tau20", "tau20"]
    v = SaturationView()
    assert list(v.sweep_source.data["alpha"]) == [1.0, 0.3, 0.3]
    extra.write_bytes(b"damaged")
    pts, note = sv.load_sweeps(sv.sweep_files())
    assert len(pts) == 1 and "cannot be read" in note
    main.unlink()
    extra.unlink()
    pts, note = sv.load_sweeps(sv.sweep_files())
    assert pts == [] and "only the theory curves" in note


def test_a_sweep_caveat_shows_with_its_set_only(tmp_path, monkeypatch):
    main, extra = tmp_path / "saturation_sweep.nc", tmp_path / "saturation_sweep_tau20.nc"
    _sweep(main, [("tau15", 200.0, 400.0, False)])
    _sweep(extra, [("tau20", 400.0, 180.0, False)])
    with xr.open_dataset(extra, engine="h5netcdf") as f:
        ds = f.load()
    ds.attrs["caveat"] = "Not a reproduction yet: the T floor."
    ds.to_netcdf(extra, engine="h5netcdf")
    monkeypatch.setattr(sv, "SWEEP_FILE", main)
    v = SaturationView()
    assert not v.caveat.visible
    v.param_set = "tau20"
    assert v.caveat.visible and "T floor" in v.caveat.object and 'id="sat-caveat"' in v.caveat.object
    v.isothermal = True  # other model: not its runs
    assert not v.caveat.visible
