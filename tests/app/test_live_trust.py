"""A lost student's live runs: Reset always restarts (invalid settings named and put back), the time
axes restart with the run, and the orbits/s readout is the orbit counter's own rate."""
from __future__ import annotations

import math
import random

import pytest

from ringlab.live.hydro import HydroRunner
from ringlab.live.loop import RATE_WINDOW_S, measured_rates
from ringlab.live.nbody import NBodyRunner
from ringlab.model.nbody_settings import NBodySettings
from ringlab.model.hydro_settings import HydroSettings
from ringlab.tabs.hydro.view import HydroView
from ringlab.tabs.nbody import NBodyView

SMALL = dict(L_x=500.0, h=2.5)


def test_reset_with_an_invalid_setting_names_it_puts_it_back_and_restarts():
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.start()
    for _ in range(3):
        r.tick()
    assert r.sim.orbits > 0
    r.settings.sigma0 = 1000.0  # Q0 = 0.80: the hydro run refuses it (the run shown keeps its settings)
    r.settings.h = 10.0  # too coarse as well
    assert r.problems and r.sim.params.sigma0 == 400.0
    grid = v.checked["grid"]
    grid.widgets["L_x"].value = 50.0  # a typed value the field never passed on
    assert grid.pane.visible
    v.reset()
    assert r.sim.orbits == 0.0 and r.problems == {}
    assert (r.settings.sigma0, r.settings.h, r.settings.L_x, grid.widgets["L_x"].value) == (400.0, 2.5, 500.0, 500.0)
    assert not grid.pane.visible
    assert "Settings invalid" not in r.status and "nothing reset" not in r.status
    for named in ("Surface density σ₀ = 1000 → 400 kg/m²", "= 10 → 2.5 m", "typed 50 → 500 m"):
        assert named in r.status, r.status
    r.close()


def test_reset_with_valid_settings_just_restarts():
    r = HydroRunner(settings=HydroSettings(**SMALL))
    r.start()
    r.tick()
    r.reset()
    assert r.sim.orbits == 0.0 and "put back" not in r.status
    r.close()


def test_nbody_reset_puts_an_impossible_box_back():
    v = NBodyView(runner=NBodyRunner(settings=NBodySettings(L_x=40.0, L_y=20.0)))
    r = v.runner
    r.settings.param.update(L_x=200.0, L_y=200.0)  # L_x L_y tau / (pi R_p^2) > MAX_PARTICLES
    assert r.problem and r.box.options.L_y == 20.0
    v.reset()
    assert r.problem == "" and (r.settings.L_x, r.settings.L_y) == (40.0, 20.0) and r.box.orbits == 0.0
    assert "put back" in r.status and "= 200 → 20 m" in r.status, r.status


def test_time_axes_restart_with_the_run():
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r, p = v.runner, v.plots
    r.start()
    while r.sim.orbits < 3.0:
        r.tick()
    assert p.t_range.end >= 3.0 and p.lp_fig.x_range is p.t_range and p.ekin_fig.x_range is p.t_range
    r.reset()
    assert (p.t_range.start, p.t_range.end) == (0.0, 1.0)
    assert (p.t_range.reset_start, p.t_range.reset_end) == (0.0, 1.0)
    r.close()


def test_nbody_time_axes_restart_with_the_box():
    v = NBodyView(runner=NBodyRunner(settings=NBodySettings(L_x=40.0, L_y=20.0)))
    r = v.runner
    while r.box.orbits < 1.2:
        r.advance(2.0, orbits=0.5)
    r.frame += 1
    assert v.t_range.end == pytest.approx(r.series.get("t")[-1])
    r.reset()
    assert (v.t_range.start, v.t_range.end) == (0.0, 1.0)


def _bursty(rate_compute=6.0, n=600, burst=5, wait=(0.5, 1.5), seed=1):
    """Chunk records as a busy server delivers them: ``burst`` chunks of 0.06 s back to back, then a wait."""
    rnd = random.Random(seed)
    recs, t, orb = [], 0.0, 0.0
    for i in range(n):
        t += 0.06
        orb += 0.06 * rate_compute
        recs.append((t, orb, 10 * (i + 1)))
        if i % burst == burst - 1:
            t += rnd.uniform(*wait)
    return recs


def counter_rate(recs, window):
    """What a student watching the orbit counter for ``window`` seconds sees: its change / window."""
    now = recs[-1][0]
    before = [r for r in recs if r[0] <= now - window][-1]
    return (recs[-1][1] - before[1]) / (now - before[0])


def test_orbits_per_second_is_the_counters_rate_over_seconds():
    recs = _bursty()
    shown, watched = [], []
    for k in range(150, 600, 7):
        part = recs[max(0, k - 400):k]
        shown.append(measured_rates(part)[1])
        watched.append(counter_rate(part, RATE_WINDOW_S))
    # the readout is the counter's own rate over the window (not one burst's compute speed or one wait)
    for s, w in zip(shown, watched):
        assert s == pytest.approx(w, rel=1e-12)
    long_run = recs[-1][1] / recs[-1][0]
    assert all(abs(s / long_run - 1) < 0.35 for s in shown)
    # the old readout (last <= 2 s of at most 40 chunks) swung far wider on the same records
    def old(r):
        r = r[-40:]
        j = 0
        while j < len(r) - 2 and r[-1][0] - r[j][0] > 2.0:
            j += 1
        return (r[-1][1] - r[j][1]) / (r[-1][0] - r[j][0])
    olds = [old(recs[:k]) for k in range(150, 600, 7)]
    assert max(olds) / min(olds) > max(shown) / min(shown)


def test_no_rate_before_two_seconds_of_running():
    assert all(math.isnan(x) for x in measured_rates([(0.0, 0.0, 0), (0.5, 1.0, 10)]))
    assert measured_rates([(0.0, 0.0, 0), (2.5, 4.0, 100)]) == (40.0, 1.6)
