"""Runners compose their settings (ringlab.live.hydro, ringlab.live.nbody, ringlab.live.keeper): the student's
settings live in ``runner.settings`` only, are resolved once per rebuild into frozen values, one watcher
restarts a run and the runner's own keeper keeps the replaced one; a restore rebuilds nothing."""
from __future__ import annotations

import dataclasses

import pytest

from ringlab.live.compare import CompareRunner
from ringlab.live.hydro import HydroRunner
from ringlab.live.nbody import NBodyRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.model.nbody_settings import NBodySettings

SMALL = dict(L_x=500.0, h=2.5)


def _count_rebuilds(r, monkeypatch) -> list:
    calls = []
    rebuild = r._rebuild
    monkeypatch.setattr(r, "_rebuild", lambda: calls.append(1) or rebuild())
    return calls


def test_the_settings_live_in_one_place():
    r = HydroRunner()
    assert isinstance(r.settings, HydroSettings) and r.settings.sigma0 == 400.0  # the defaults, made for it
    with pytest.raises(TypeError):
        r.settings = HydroSettings()  # constant: change its values, not the object
    with pytest.raises(AttributeError, match=r"runner\.settings\.sigma0"):
        r.sigma0 = 500.0  # would only add an attribute nobody reads
    with pytest.raises(AttributeError, match=r"runner\.settings\.L_x"):
        _ = r.L_x
    assert not hasattr(r, "find_problems") and not hasattr(NBodyRunner(), "find_problem")
    s = NBodySettings(L_x=60.0)
    n = NBodyRunner(settings=s)
    assert n.settings is s and n.box.options.L_x == 60.0 and isinstance(n.keeper.kept_label, str)


def test_a_run_is_built_from_frozen_resolved_values():
    s = HydroSettings(initial="mode", wavelength=100.0, amplitude=0.01, **SMALL)
    setup = s.resolve()
    assert setup.params == s.ring_params() and setup.options == s.options()
    assert dict(setup.initial_kw) == dict(amplitude=0.01, wavelength=100.0) and setup.setup["L_x"] == 500.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        setup.initial = "noise"
    with pytest.raises(TypeError):
        setup.setup["L_x"] = 1.0
    r = HydroRunner(settings=s)
    assert r.run_label == setup.label and r.live.setup == setup.setup and r.sim.params == setup.params
    assert NBodySettings().resolve().setup == dict(NBodyRunner().live.setup)


def test_one_watcher_rebuilds_once_per_batch(monkeypatch):
    r = HydroRunner(settings=HydroSettings(**SMALL))
    calls = _count_rebuilds(r, monkeypatch)
    r.settings.param.update(sigma0=300.0, L_x=400.0, seed=3)
    assert len(calls) == 1 and r.sim.params.sigma0 == 300.0 and r.sim.options.L_x == 400.0
    r.settings.buffer_on = True  # applies to the running state
    assert len(calls) == 1 and r.sim.buffer_active


def test_st99_keeps_the_old_run_with_its_own_settings(monkeypatch):
    """Choosing st99 switches the isothermal model on (a second setting, changed by the settings' own
    watcher first): the kept run still comes back as the tau15 non-isothermal run it was."""
    r = HydroRunner(settings=HydroSettings(**SMALL))
    r.advance(30.0, until=0.5)
    old = r.sim
    r.settings.param_set = "st99"
    assert r.settings.isothermal and r.sim.params.name == "st99" and "tau15, non-isothermal" in r.keeper.kept_label
    calls = _count_rebuilds(r, monkeypatch)
    assert r.keeper.restore()
    assert calls == [] and r.sim is old  # the kept run itself, nothing rebuilt
    assert (r.settings.param_set, r.settings.isothermal, r.problems) == ("tau15", False, {})
    assert r.run_label.startswith("tau15, non-isothermal") and "Restored" in r.status


def test_nbody_restore_puts_settings_and_box_back(monkeypatch):
    r = NBodyRunner(settings=NBodySettings(L_x=40.0, L_y=20.0))
    r.advance(5.0, orbits=0.1)
    old = r.box
    r.settings.L_x = 60.0
    assert r.box is not old and "40 m × 20 m" in r.keeper.kept_label
    calls = _count_rebuilds(r, monkeypatch)
    assert r.keeper.restore()
    assert calls == [] and r.box is old and r.settings.L_x == 40.0 and r.problem == ""
    assert r.keeper.kept_label == ""  # the replaced box had not run: nothing to keep in turn


def test_compare_runs_keep_nothing_and_restart_together():
    r = CompareRunner()
    for run in r.runs():
        run.settings.param.update(**SMALL)
    r.a.advance(30.0, until=0.2)
    sims = (r.a.sim, r.b.sim)
    r.b.settings.sigma0 = 300.0
    assert r.a.sim is not sims[0] and r.b.sim is not sims[1]  # both restarted at orbit 0
    assert not r.a.keeper.kept_label and not r.b.keeper.kept_label  # no restore button there: nothing held
    r.close()
