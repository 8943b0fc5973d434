"""A settings change resolves the settings once: the run's check and the run's values share one resolution."""
from __future__ import annotations

import collections

import pytest

from ringlab.live.hydro import HydroRunner
from ringlab.live.nbody import NBodyRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.model.nbody_settings import NBodySettings


def _count(monkeypatch, cls, names):
    calls = collections.Counter()
    for name in names:
        orig = getattr(cls, name)

        def counted(self, *a, _orig=orig, _name=name, **k):
            calls[_name] += 1
            return _orig(self, *a, **k)
        monkeypatch.setattr(cls, name, counted)
    return calls


@pytest.mark.parametrize("change", [dict(sigma0=500.0), dict(seed=3), dict(L_x=1000.0)])
def test_hydro_settings_change_resolves_once(monkeypatch, change):
    r = HydroRunner()
    calls = _count(monkeypatch, HydroSettings, ("ring_params", "options", "settings"))
    r.settings.param.update(**change)
    # ring_params: the parameters; options: the grid; settings: the tuple the characteristic numbers are
    # computed from (ring_params reads it once itself)
    assert dict(calls) == {"ring_params": 1, "options": 1, "settings": 2}
    assert r.live.setup == r.settings.resolve().setup and r.numbers == dict(r.settings.resolve().numbers)


def test_hydro_invalid_change_resolves_once(monkeypatch):
    r = HydroRunner()
    calls = _count(monkeypatch, HydroSettings, ("ring_params", "options"))
    r.settings.h = 20.0  # too coarse for the fastest-growing wavelength: no run is built
    assert dict(calls) == {"ring_params": 1, "options": 1}
    assert "grid" in r.problems and r.settings.check()[0] is None


@pytest.mark.parametrize("change", [dict(seed=3), dict(sigma0=300.0)])
def test_nbody_settings_change_resolves_once(monkeypatch, change):
    r = NBodyRunner()
    calls = _count(monkeypatch, NBodySettings, ("ring_params", "options"))
    r.settings.param.update(**change)
    assert dict(calls) == {"ring_params": 1, "options": 1}
    assert r.live.setup == r.settings.resolve().setup


def test_check_agrees_with_find_problems_and_resolve():
    s = HydroSettings(sigma0=450.0, initial="mode", wavelength=200.0)
    setup, probs = s.check()
    assert probs == s.find_problems() == {}
    ref = s.resolve()
    assert (setup.params, setup.options, setup.initial, dict(setup.initial_kw), setup.initial_label,
            dict(setup.numbers), dict(setup.setup)) == (ref.params, ref.options, ref.initial, dict(ref.initial_kw),
                                                        ref.initial_label, dict(ref.numbers), dict(ref.setup))
    bad = HydroSettings(wavelength=333.0, initial="mode")
    assert bad.check() == (None, bad.find_problems()) and "initial" in bad.find_problems()
    n = NBodySettings(L_x=500.0, L_y=200.0)
    assert n.check() == (None, n.find_problem()) and n.find_problem()
