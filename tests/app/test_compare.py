"""Headless tests of the Compare tab (two runs side by side), through its Parameterized classes.

* both runs advance together: never more than one frame step apart, equal whenever the common clock
  is reached, and each equals a standalone run of its own settings advanced to the same orbit;
* the preset's differing control is applied to the runs themselves (not only to the labels);
* both space-time diagrams share axes and one colour scale (percentiles of both images, computed
  here independently);
* two sessions are independent; a closed tab frees both runs.
"""
from __future__ import annotations

import numpy as np
import pytest

from ringlab.live.compare import PRESETS, TOL, CompareRunner
from ringlab.tabs.compare.view import CompareView
from ringlab.live.hydro import HydroRunner
from ringlab.live.nbody import NBodyRunner
from ringcore.hydro import Hydro1D


def run_ticks(r: CompareRunner, n: int, check=None):
    r.start()
    assert r.running
    for _ in range(n):
        r.tick()
        if check is not None:
            check(r)
    r.pause()


@pytest.fixture
def small():
    """A sigma0 = 0 vs 400 comparison in a small box (fast)."""
    v = CompareView()
    r = v.runner
    for run in r.runs():
        run.settings.param.update(L_x=500.0, h=2.5)
    return v


def test_presets_apply_the_differing_control():
    r = CompareRunner()
    a, b = r.a.sim.params, r.b.sim.params
    assert (a.sigma0, b.sigma0) == (0.0, 400.0)
    assert (a.name, a.isothermal, r.a.sim.options.L_x) == (b.name, b.isothermal, r.b.sim.options.L_x)
    assert [d[:2] for d in r.differences()] == [("sigma0", r.a.settings.param["sigma0"].label)]
    assert r.tags() == ("σ₀ = 0", "σ₀ = 400")

    r.preset = "isothermal"
    assert isinstance(r.b, HydroRunner)
    assert (r.a.sim.params.isothermal, r.b.sim.params.isothermal) == (True, False)
    assert r.a.sim.params.sigma0 == r.b.sim.params.sigma0
    assert [d[2:] for d in r.differences()] == [("yes", "no")]
    assert r.tags() == ("isothermal", "non-isothermal")

    r.preset = "engine"
    assert isinstance(r.a, HydroRunner) and isinstance(r.b, NBodyRunner)
    box, sim = r.b.box, r.a.sim
    assert box.params.name == sim.params.name and box.params.tau == sim.params.tau
    assert box.params.sigma0 == sim.params.sigma0
    assert box.options.L_x == sim.options.L_x == PRESETS["engine"].a["L_x"]
    assert [d[0] for d in r.differences()] == ["model"] and r.tags() == ("hydrodynamics", "N-body")
    assert r.orbits_per_frame == PRESETS["engine"].orbits_per_frame
    r.close()


def test_both_advance_together_and_match_standalone_runs(small):
    r = small.runner
    r.orbits_per_frame = 0.25
    gaps = []

    def check(r):
        oa, ob = r.a.sim.orbits, r.b.sim.orbits
        gaps.append(abs(oa - ob))
        assert max(oa, ob) <= r.clock + TOL
        if r.reached(r.clock):
            assert oa == pytest.approx(r.clock, abs=1e-9) and ob == pytest.approx(r.clock, abs=1e-9)

    run_ticks(r, 12, check)
    assert max(gaps) <= r.orbits_per_frame + TOL
    assert r.clock >= 1.0  # it really ran
    # each run is exactly the run its own settings give on their own (the pairing changes nothing)
    for run in r.runs():
        s = run.settings
        ref = Hydro1D(s.ring_params(), s.options(), initial="noise", seed=s.seed, amplitude=s.amplitude)
        ref.advance(until=run.sim.orbits)
        np.testing.assert_allclose(run.sim.U, ref.U, rtol=1e-12, atol=1e-14)
    # and the two differ (the control is applied): self-gravity changes the state
    assert not np.allclose(r.a.sim.U[0], r.b.sim.U[0], rtol=0, atol=1e-12)
    small.runner.close()


def test_one_setting_change_restarts_both(small):
    r = small.runner
    run_ticks(r, 3)
    assert r.a.sim.orbits > 0 and r.b.sim.orbits > 0
    r.b.settings.sigma0 = 300.0
    assert r.b.sim.params.sigma0 == 300.0
    assert r.a.sim.orbits == 0.0 and r.b.sim.orbits == 0.0 and r.clock == 0.0
    assert r.differences()[0][2:] == ("0", "300")
    old = r.a.sim
    r.a.settings.h = 3.0  # 500 / 3 is not a whole number of cells: not applied, nothing restarts
    assert r.a.problems and r.a.sim is old
    r.close()


def test_same_axes_and_colour_scale(small):
    v = small
    r, P = v.runner, v.plots
    r.orbits_per_frame = 1.0
    run_ticks(r, 8)
    v._on_frame()
    fa, fb = P.spacetime_figs["A"], P.spacetime_figs["B"]
    assert fa.x_range is fb.x_range and fa.y_range is fb.y_range
    ga, gb = (f.renderers[0].glyph for f in (fa, fb))
    assert ga.color_mapper is gb.color_mapper is P.color_mapper
    ia, ib = r.a.strobe_image.image(), r.b.strobe_image.image()
    assert ia.shape[0] >= 4 and ia.shape == ib.shape
    lo, hi = np.percentile(np.concatenate([ia.ravel(), ib.ravel()]), [1, 99])
    assert (P.color_mapper.low, P.color_mapper.high) == pytest.approx((lo, hi), rel=1e-6)
    assert (fa.x_range.start, fa.x_range.end) == (-250.0, 250.0)
    t_end = min(r.a.strobe_image.extent()[1], r.b.strobe_image.extent()[1])
    assert fa.y_range.end == pytest.approx(t_end)
    # overlays: one source per run, both filled with that run's own series
    for k, run in zip("AB", r.runs()):
        assert list(P.series_sources[k].data["t"]) == pytest.approx(list(run.series.get("t")))
    assert P.psd_sources["A"].data["power"].max() == pytest.approx(1.0)
    # readouts show each run's own orbit, lambda_p and e_kin
    for k, run in zip("AB", r.runs()):
        html = v.readouts[k].object
        assert f"{run.sim.orbits:.2f}" in html and f'id="compare-{k.lower()}-lambda-p"' in html
        assert f"{run.sim.prevalent_wavelength():.4g} m" in html
    assert "Surface density" in v.differs.object and "one control" in v.differs.object
    r.close()


def test_no_frame_is_drawn_while_a_chunk_computes(small):
    import threading

    v, r = small, small.runner
    r.orbits_per_frame = 0.5
    run_ticks(r, 2)
    shown = v.readouts["A"].object
    held, release = threading.Event(), threading.Event()

    def chunk():  # what a worker holds while it computes
        with r.compute_lock:
            held.set()
            release.wait(10)

    worker = threading.Thread(target=chunk)
    worker.start()
    assert held.wait(10)
    r.a.advance(1.0, until=r.a.sim.orbits + 0.5)  # the state changes under the worker's lock
    r.frame += 1
    assert v.readouts["A"].object == shown  # skipped: never read a state that is being computed
    release.set()
    worker.join()
    r.frame += 1
    assert v.readouts["A"].object != shown and f"{r.a.sim.orbits:.2f}" in v.readouts["A"].object
    r.close()


def test_hydro_vs_nbody_advance_together():
    r = CompareRunner(preset="engine")
    r.orbits_per_frame = 0.02
    run_ticks(r, 6, lambda r: None)
    oa, ob = r.a.sim.orbits, r.b.box.orbits
    assert oa > 0 and ob > 0 and abs(oa - ob) <= r.orbits_per_frame + TOL
    s_a, s_b = r.sides()
    assert s_a["kind"] == "hydro" and s_b["kind"] == "nbody" and s_a["L_x"] == s_b["L_x"]
    assert s_b["t"].size > 0 and np.all(s_b["e_kin"] > 0)
    r.close()


def test_pause_brings_both_to_the_same_orbit(small):
    r = small.runner
    r.orbits_per_frame = 2.0
    # chunks of a few steps, far too short to reach the clock: the runs are mid-frame (0.01 s reached
    # 2 orbits of this small box in two ticks on a fast CPU; a step is always taken, so the runs move)
    r.budget_s = 1e-5
    r.start()
    r.tick()
    r.tick()
    assert 0 < max(r.a.sim.orbits, r.b.sim.orbits) < r.clock / 10
    assert not r.reached(r.clock)
    r.pause()
    oa, ob = r.a.sim.orbits, r.b.sim.orbits
    assert oa == pytest.approx(r.clock, abs=1e-9) and ob == pytest.approx(r.clock, abs=1e-9)
    assert r.status == f"Paused: both runs at orbit {oa:.2f}."
    r.close()


def test_pause_when_both_are_at_the_clock_says_so(small):
    """Pause that lands when both runs have just reached the clock (no catch-up needed) shows the same
    "Paused: both runs at orbit ..." as after a catch-up (it said only "Paused." before)."""
    r = small.runner
    r.orbits_per_frame = 0.25
    r.budget_s = 5.0  # each chunk reaches the clock
    r.start()
    r.tick()
    assert r.reached(r.clock)
    r.pause()
    oa = r.a.sim.orbits
    assert oa == pytest.approx(r.clock, abs=1e-9) and r.b.sim.orbits == pytest.approx(r.clock, abs=1e-9)
    assert r.status == f"Paused: both runs at orbit {oa:.2f}."
    r.close()


def test_pause_at_stops_both_exactly():
    r = CompareRunner()
    for run in r.runs():
        run.settings.param.update(L_x=300.0)
    r.pause_at = 0.75
    r.start()
    for _ in range(40):
        r.tick()
        if not r.running:
            break
    assert not r.running and r.a.sim.orbits == pytest.approx(0.75) and r.b.sim.orbits == pytest.approx(0.75)
    r.close()


def test_blowup_of_one_run_pauses_both(small, monkeypatch):
    r = small.runner

    def blow(budget_s, until=None):
        r.b.blowup = "sigma < 0 at x = 10 m"
        return 0
    monkeypatch.setattr(r.b, "advance", blow)
    r.start()
    r.tick()
    assert not r.running and r.blowup.startswith("Run B:") and "blew up" in r.status
    r.start()
    assert not r.running  # Start refuses until Reset
    r.close()


def test_sessions_are_independent_and_close_frees_both():
    v1, v2 = CompareView(), CompareView()
    r1, r2 = v1.runner, v2.runner
    assert r1.a is not r2.a and r1.b is not r2.b and r1.compute_lock is not r2.compute_lock
    for r in (r1, r2):
        for run in r.runs():
            run.settings.param.update(L_x=300.0)
    r1.b.settings.sigma0 = 200.0
    run_ticks(r1, 3)
    assert r2.b.settings.sigma0 == 400.0 and r2.b.sim.params.sigma0 == 400.0
    assert r2.a.sim.orbits == 0.0 and r2.clock == 0.0 and r1.clock > 0
    r1.preset = "engine"
    assert r2.preset == "sigma0" and isinstance(r2.b, HydroRunner)
    a, b = r1.runs()
    r1.close()
    assert a.sim is None and b.box is None and r1.status == "Closed."
    r1.start()
    r1.tick()
    assert not r1.running or a.sim is None
    r2.start()
    r2.tick()
    assert r2.a.sim.orbits > 0  # the other session goes on
    r2.close()


def test_teacher_link_opens_and_starts_the_compare_tab():
    from ringlab import main

    index = [t for t, _ in main.TABS].index("Compare")
    assert main.TAB_KEYS["compare"] == index
    app = main.create_app()
    main.apply_query(app, {"tab": [b"compare"], "autostart": [b"1"]})
    view = app.views[index]
    assert app.tabs.active == index and isinstance(view, CompareView) and view.runner.running
    view.runner.close()
    for v in app.views:
        runner = getattr(v, "runner", None)
        if runner is not None and hasattr(runner, "close"):
            runner.close()
