"""Headless tests of the live hydro tab: settings, runner, bounded buffers, export (no browser).

Every control must change the simulation the way ``ringcore.hydro`` would be set up by
hand; invalid combinations must give a message and leave the run alone; a blow-up must
pause the run at the last good state; the exported file must be a readable run file.
Small boxes keep the suite fast.
"""
from __future__ import annotations

import time

import numpy as np
import panel as pn
import pytest

from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.tabs.hydro.view import HydroView
from ringlab.live.buffers import RollingImage, SeriesBuffer, SpaceTimeImage, bin_columns
from ringcore import linear, params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import read_run

SMALL = dict(L_x=500.0, h=2.5)


@pytest.fixture
def runner():
    return HydroRunner(settings=HydroSettings(**SMALL))


def test_defaults_match_the_issue():
    s = HydroSettings()
    assert (s.param_set, s.sigma0, s.isothermal, s.L_x, s.h) == ("tau15", 400.0, False, 2000.0, 2.5)
    assert s.param.sigma0.bounds == (0.0, 1000.0)
    assert s.find_problems() == {}
    r = HydroRunner()
    assert r.sim.n == 800 and r.sim.params == params.get("tau15", 400.0)
    assert r.numbers["lambda_zero_m"] == pytest.approx(linear.lambda_zero(params.get("tau15", 400.0)), rel=1e-9)


def test_each_control_changes_the_model(runner):
    r = runner
    r.settings.sigma0 = 250.0
    assert r.sim.params.sigma0 == 250.0 and r.sim.orbits == 0.0
    r.settings.isothermal = True
    assert r.sim.isothermal and r.sim.nv == 3 and r.sim.params.p_s == 1.0
    r.settings.iso_p_s = 2.41
    assert r.sim.params.p_s == 2.41
    r.settings.isothermal = False
    r.settings.ps_scale = 1.4
    assert r.sim.params.p_s == pytest.approx(1.4 * 2.41)
    r.settings.param.update(ps_scale=1.0, param_set="tau20")
    assert r.sim.params.name == "tau20"
    r.settings.param.update(L_x=400.0, h=2.0)
    assert r.sim.n == 200 and r.sim.x_m[0] == -200.0
    r.settings.timestep = "paper"
    assert r.sim.options.timestep == "paper"
    a = r.sim.sigma_dimless
    r.settings.seed = 7
    assert not np.array_equal(a, r.sim.sigma_dimless)
    r.settings.param.update(initial="mode", wavelength=100.0, amplitude=0.01)
    ref = Hydro1D(params.get("tau20", 250.0), HydroOptions(L_x=400.0, h=2.0), initial="mode", wavelength=100.0,
                  amplitude=0.01)
    np.testing.assert_allclose(r.sim.sigma_dimless, ref.sigma_dimless, rtol=0, atol=1e-14)
    assert "mode λ = 100 m" in r.run_label


def test_run_advances_pause_step_and_reset(runner):
    r = runner
    sigma0 = r.sim.sigma_dimless
    r.start()
    assert r.running
    for _ in range(5):
        r.tick()
    t = r.sim.orbits
    assert t > 0.2 and r.series.size > 3 and r.orbit_image.rows > 3 and r.frame > 5
    r._rates.appendleft((r._rates[0][0] - 2.0, 0.0, 0))  # as if started 2 s earlier (RATE_MIN_SPAN_S)
    steps_s, orbits_s = r.rates()
    assert steps_s > 0 and orbits_s > 0
    r.pause()
    r.tick()
    assert r.sim.orbits == t and not r.running
    r.step_once()
    # exactly t + 1 when that is a sample time, else the first step boundary after it (steps land only on samples)
    assert t + 1.0 - 1e-9 <= r.sim.orbits < t + 1.0 + r.sim.dt_orbits + 1e-9
    dt = r.typical_dt_orbits()  # the criterion's step, not the one shortened to land on the orbit
    # the readout is the criterion's recent step (the last step was shortened to land on the orbit; in a
    # nonlinear state the criterion itself drifts, so allow some slack: how far the run got depends on speed)
    assert r.sim.dt_orbits <= 1.5 * dt and dt == pytest.approx(r.sim.stable_dt() / (2 * np.pi), rel=0.5)
    assert r.strobe_image.rows >= 2  # a stroboscopic row at every full orbit
    r.reset()
    assert r.sim.orbits == 0.0 and r.series.size == 1
    np.testing.assert_array_equal(r.sim.sigma_dimless, sigma0)  # same seed, same initial state


def test_buffer_switched_on_while_running(runner):
    r = runner
    r.start()
    r.tick()
    r.settings.param.update(buffer_x=100.0, buffer_width=100.0, buffer_beta=-0.5, buffer_on=True)
    sim = r.sim
    assert sim.buffer_active and sim.buffer == (50.0, 150.0, -0.5)
    assert r.buffer_events[-1][1] == -0.5 and r.buffer_events[-1][0] == pytest.approx(sim.orbits)
    t = sim.orbits
    r.tick()
    assert r.sim is sim and sim.orbits > t  # the run went on, not restarted
    r.settings.buffer_beta = 0.0
    assert sim.buffer[2] == 0.0
    r.settings.buffer_x = 240.0  # 190 .. 290 m: outside the 500 m box
    assert "outside the box" in r.problems["buffer"] and not sim.buffer_active
    r.settings.buffer_x = 0.0
    assert "buffer" not in r.problems and sim.buffer_active
    r.settings.buffer_on = False
    assert not sim.buffer_active and r.buffer_events[-1][1] is None


@pytest.mark.parametrize("change, group, text", [
    (dict(h=10.0), "grid", "too coarse"),  # lambda_max = 66 m gets 6.6 cells
    (dict(h=3.0), "grid", "not an integer"),
    (dict(sigma0=900.0), "model", "Toomre Q0 = 0.89"),
    (dict(initial="mode", wavelength=70.0), "initial", "does not fit the box"),
    (dict(amplitude=0.3), "initial", "white noise"),
    (dict(L_x=20000.0, h=0.5), "grid", "too many"),
])
def test_invalid_settings_give_a_message_and_keep_the_run(runner, change, group, text):
    r = runner
    r.start()
    r.tick()
    sim, t = r.sim, r.sim.orbits
    r.settings.param.update(**change)
    assert text in r.problems[group]
    assert r.sim is sim and sim.orbits == t
    r.tick()  # the last valid run goes on
    assert sim.orbits > t


def test_blow_up_pauses_and_keeps_the_last_good_state(runner):
    r = runner
    s, u, v, T = r.sim.primitives()
    s = s.copy()
    s[100:110] = 1e6  # a deliberately impossible state: the first step fails
    r.sim.set_state(s, u, v, T)
    good = r.sim.U.copy()
    r.start()
    r.tick()
    assert not r.running and "blow-up" in r.blowup and "last good state" in r.blowup
    np.testing.assert_array_equal(r.sim.U, good)
    r.start()  # refused until reset
    assert not r.running and "Reset" in r.status
    r.reset()
    assert r.blowup == "" and np.all(np.isfinite(r.sim.U))


def test_export_is_a_readable_run_file(runner, tmp_path):
    r = runner
    r.settings.buffer_on = True
    r.step_once()
    data = r.netcdf_bytes().getvalue()
    path = tmp_path / r.export_filename()
    path.write_bytes(data)
    ds = read_run(path, "hydro")
    assert ds.attrs["kind"] == "hydro" and float(ds["t"][-1]) == pytest.approx(r.sim.orbits)
    np.testing.assert_allclose(ds["sigma"].values, r.sim.sigma_dimless * 400.0)
    assert HydroSettings.parse_settings(ds.attrs["app_settings_json"])["buffer_on"] is True
    restored = Hydro1D.from_dataset(ds)
    np.testing.assert_allclose(restored.U, r.sim.U)


def test_settings_file_round_trip_and_bad_files(runner):
    r = runner
    r.settings.param.update(sigma0=600.0, isothermal=True, buffer_on=True, spacetime="orbit-resolved")
    text = r.settings.settings_json()
    other = HydroRunner()
    assert other.settings.load_settings(text.encode()) == ""
    assert other.settings.settings_dict() == r.settings.settings_dict() and other.sim.params.sigma0 == 600.0
    assert "not valid JSON" in other.settings.load_settings("{oops")
    assert "not a ringlab hydro settings file" in other.settings.load_settings('{"sigma0": 1}')
    assert "unknown keys ['x']" in other.settings.load_settings('{"ringlab_settings": "hydro", "x": 1}')
    assert "sigma0" in other.settings.load_settings('{"ringlab_settings": "hydro", "sigma0": 5000}')
    assert other.sim.params.sigma0 == 600.0


def test_memory_stays_bounded():
    img = SpaceTimeImage(800, 1.0, max_rows=100)
    assert img.ncols == 400
    for k in range(1000):
        img.add(float(k), np.full(800, k, float))
    assert img.rows <= 100 and img.stride == 16
    t0, t1 = img.extent()
    assert t0 == 0.0 and t1 >= 1000.0 - img.stride  # the whole run (rows still being averaged aside)
    assert img.image()[0, 0] == pytest.approx(7.5)  # mean of rows 0..15
    roll = RollingImage(10, 0.05, max_rows=20)
    for k in range(45):
        roll.add(0.05 * k, np.full(10, k, float))
    assert roll.rows == 20 and roll.image()[:, 0].tolist() == list(range(25, 45))  # the latest 20, in order
    assert roll.extent() == pytest.approx((1.25, 2.25))
    s = SeriesBuffer(("y",), max_points=64)
    for k in range(10000):
        s.add(float(k), y=2.0 * k)
    assert s.size <= 64 and s.get("t")[0] == 0.0 and s.get("y")[-1] == 2.0 * s.get("t")[-1]
    np.testing.assert_allclose(bin_columns(np.arange(10.0), 4), [1.0, 4.0, 7.0, 9.0])
    opt = HydroOptions(L_x=400.0, h=2.5, samples_per_orbit=50)
    full = Hydro1D(params.get("tau15", 400.0), opt, initial="noise")
    sim = Hydro1D(params.get("tau15", 400.0), opt, initial="noise", max_samples=100, max_rows=2)  # bounded by the core
    full.advance(orbits=3.0)
    sim.advance(orbits=3.0)
    a, b = sim.series(), full.series()
    assert sim.recorder.thinned and not full.recorder.thinned and len(b["t"]) == 151
    assert 50 <= len(a["t"]) <= 100 and a["t"][0] == 0.0 and a["t"][-1] == pytest.approx(sim.t)
    assert set(a["t"]) <= set(b["t"]) and np.all(np.diff(a["t"]) > 0)  # a subset of the samples, in order
    assert all(len(a[k]) == len(a["t"]) for k in ("e_kin", "lambda_p", "sigma_min", "T_max", "steps"))
    assert len(a["t_strobe"]) <= 2 and a["t_strobe"][-1] == b["t_strobe"][-1]
    assert np.array_equal(sim.U, full.U)  # thinning the records never changes the run


def test_view_fills_the_plots_and_readouts():
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.start()
    for _ in range(3):
        r.tick()
    p = v.plots
    assert len(p.profile_source.data["x"]) == r.sim.n == 200
    assert p.profile_source.data["sigma"].dtype == np.float32
    img = p.image_source.data["image"][0]
    assert img.dtype == np.float32 and img.shape[1] == 200
    assert p.x_range.start == -250.0
    assert 'id="hydro-orbits"' in v.readouts.object and f"{r.sim.orbits:.2f}" in v.readouts.object
    assert v.buttons["start"].disabled and not v.buttons["pause"].disabled
    r.settings.h = 10.0
    assert v.messages["grid"].visible and "too coarse" in v.messages["grid"].object
    r.settings.h = 2.5
    assert not v.messages["grid"].visible
    # the title's lines fit a phone's plot (~330 px of 13 px bold: a one-line title was cut after "(one row")
    assert "stroboscopic (one row per orbit)" in p.spacetime_fig.title.text
    assert max(len(line) for line in p.spacetime_fig.title.text.split("\n")) <= 40, p.spacetime_fig.title.text
    r.settings.spacetime = "orbit-resolved"  # shown at once, not at the next image frame
    assert "orbit-resolved (last 25 orbits)" in p.spacetime_fig.title.text
    assert max(len(line) for line in p.spacetime_fig.title.text.split("\n")) <= 40, p.spacetime_fig.title.text
    assert p.image_source.data["image"][0].shape[0] == r.orbit_image.rows
    marks = p.psd_markers.data["x"]
    assert r.numbers["lambda_zero_m"] in marks and r.numbers["lambda_max_growth_m"] in marks
    r.close()
    assert r.sim is None and not r.running
    r.tick()  # a late callback after the tab closed does nothing


def test_frame_gate_paces_frames():
    from bokeh.models import ColumnDataSource
    from bokeh.plotting import figure

    from ringlab.ui import frame_gate
    from ringlab.ui.frame_gate import FrameGate

    fig, src = figure(), ColumnDataSource(dict(x=[]))
    gate = FrameGate(fig, src, min_period_s=0.25, max_in_flight=1)
    assert "change:data" in src.js_property_callbacks  # the page acknowledges each applied frame
    assert gate.ready(10.0)
    gate.mark_sent(10.0)
    assert not gate.ready(10.1) and gate.ready(10.3)  # no server session: only the period applies
    gate.mark_sent(10.1)  # a forced frame (a Pause) before the gate allowed one: the pacing starts again there
    assert not gate.ready(10.2) and gate.ready(10.1 + 0.25 * (1 - frame_gate.EARLY_FRACTION))
    gate._ack("tags", [], [1])
    assert gate.acks == 1 and gate.sent == 2


def test_frame_gate_caps_the_frame_rate_of_a_served_page(monkeypatch, ringlab_env):
    """In a server session a plot gets at most RINGLAB_MAX_FRAME_RATE updates per second (default 6), even
    when the page acknowledges every frame at once; a bad value names the variable and the allowed range."""
    from types import SimpleNamespace

    from bokeh.models import ColumnDataSource
    from bokeh.plotting import figure

    from ringlab.ui import frame_gate
    from ringlab.ui.frame_gate import FrameGate, max_frame_rate

    assert max_frame_rate() == frame_gate.DEFAULT_MAX_FRAME_RATE == 6.0
    served = SimpleNamespace(session_context=object())
    monkeypatch.setattr(type(pn.state), "curdoc", property(lambda self: served))
    ringlab_env.set(frame_gate.RATE_ENV, "4")
    gate = FrameGate(figure(), ColumnDataSource(dict(x=[])))
    sent = 0
    for i in range(1000):  # 10 s in steps of 10 ms, every frame acknowledged at once
        now = 100.0 + 0.01 * i
        if gate.ready(now):
            gate.mark_sent(now)
            gate._ack("tags", [], [1])
            sent += 1
    assert sent == 41  # 4 per second, and the first one early by half a period
    ringlab_env.set(frame_gate.RATE_ENV, "0.2")
    assert FrameGate(figure(), ColumnDataSource(dict(x=[])), min_period_s=0.25).served_period_s == 5.0
    for bad in ("0", "61", "fast", "nan"):
        with pytest.raises(ValueError, match=r"RINGLAB_MAX_FRAME_RATE = .* allowed 0.2 <= RINGLAB_MAX_FRAME_RATE <= 60"):
            ringlab_env.set(frame_gate.RATE_ENV, bad)
        assert max_frame_rate() == 0.2  # a bad value changes nothing


def test_frame_gate_sends_jittered_frames_at_the_capped_rate(monkeypatch, ringlab_env):
    """Frames (chunks) arriving every 0.1 s give or take 10 ms at a cap of 10 per second: nearly every one is
    sent (a strict minimum spacing of 0.1 s refused about a third of them), never more than 10 per second
    on average."""
    from types import SimpleNamespace

    from bokeh.models import ColumnDataSource
    from bokeh.plotting import figure

    from ringlab.ui import frame_gate
    from ringlab.ui.frame_gate import FrameGate

    served = SimpleNamespace(session_context=object())
    monkeypatch.setattr(type(pn.state), "curdoc", property(lambda self: served))
    ringlab_env.set(frame_gate.RATE_ENV, "10")
    rng = np.random.default_rng(3)
    for centre in (0.1, 0.095, 0.05):
        gate, now, sent, offered = FrameGate(figure(), ColumnDataSource(dict(x=[]))), 50.0, 0, 0
        while now < 70.0:
            offered += 1
            if gate.ready(now):
                gate.mark_sent(now)
                gate._ack("tags", [], [1])
                sent += 1
            now += centre + rng.uniform(-0.01, 0.01)
        assert sent <= 10 * (now - 50.0) + 1  # the cap holds on average
        assert sent >= 0.95 * min(offered, 10 * (now - 50.0)), (centre, sent, offered)


def test_group_titles_say_what_restarts():
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    html = " ".join(o.object for o in v._layout.select(pn.pane.HTML) if isinstance(o.object, str))
    assert html.count("restarts the run at orbit 0") == 3 and html.count("acts on the running state") == 2


def test_out_of_range_input_says_why():
    """L_x = 50 m is not silently replaced by the old value."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r, grid = v.runner, v.checked["grid"]
    w = grid.widgets["L_x"]
    assert w.start is None and w.end is None  # the browser must not clamp the typed value
    w.value = 50.0
    assert r.settings.L_x == 500.0 and r.sim.options.L_x == 500.0
    assert grid.pane.visible and "L_x = 50 m is out of range: allowed 100 .. 20000 m" in grid.pane.object
    assert "still using 500 m" in grid.pane.object
    w.value = 400.0
    assert r.sim.options.L_x == 400.0 and not grid.pane.visible
    r.settings.L_x = 600.0  # changed elsewhere (settings file, page address): the field follows
    assert w.value == 600.0
    seed = v.checked["initial"].widgets["seed"]
    seed.value = -3
    assert r.settings.seed == 1 and "seed = -3 is out of range" in v.checked["initial"].pane.object


def test_blow_up_disables_step_and_start_and_names_the_floor():
    """After a blow-up only Reset goes on; the advice names the temperature floor."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(T_floor=0.0, **SMALL)))
    r = v.runner
    s, u, vv, T = r.sim.primitives()
    s = s.copy()
    s[100:110] = 1e6
    r.sim.set_state(s, u, vv, T)
    r.start()
    r.tick()
    assert r.blowup and v.buttons["step"].disabled and v.buttons["start"].disabled
    assert not v.buttons["reset"].disabled
    assert "temperature floor off" in v.blowup.object and "0.01 T₀" in v.blowup.object
    r.reset()
    assert not v.buttons["step"].disabled and not v.buttons["start"].disabled and not v.blowup.visible


def test_orbits_per_second_is_the_measured_figure():
    """The readout is this run's measured speed (kept when paused), not a fixed number."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.start()
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 2.5:  # the readout needs RATE_MIN_SPAN_S of records
        r.tick()
    steps_s, orb_s = r.rates()
    assert orb_s > 0
    rows = {rid: (val, note) for rid, _, val, note in v._readout_rows()}
    assert rows["hydro-orbits-per-s"] == (f"{orb_s:.1f}", "now, of wall-clock time")
    r.pause()
    rows = {rid: (val, note) for rid, _, val, note in v._readout_rows()}
    assert rows["hydro-orbits-per-s"] == (f"{orb_s:.1f}", "when last running")


def test_isothermal_only_set_switches_the_model():
    """Choosing st99 switches to the isothermal model with a note, no error."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.settings.param_set = "st99"
    assert r.settings.isothermal and r.sim.isothermal and r.sim.params.name == "st99" and "model" not in r.problems
    assert v.model_note.visible and "switched on for you" in v.model_note.object
    r.settings.isothermal = False  # unticked by hand: the message beside the controls, the run stays
    assert "isothermal" in r.problems["model"] and r.sim.params.name == "st99"
