"""The live hydro run kept and restored as one value (ringlab.live.run, ringlab.live.keeper), and what a
frame costs the app process: the series streamed, unchanged images and PSD markers not sent again, the
linear-theory line computed once per series (ringlab.tabs.hydro.plots)."""
from __future__ import annotations

import time

import numpy as np

from ringlab.live.buffers import SeriesBuffer
from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.tabs.hydro.view import HydroView

SMALL = dict(L_x=500.0, h=2.5)


def test_setup_change_keeps_the_previous_run_restorable():
    """A setup change starts a new run but the old one comes back with one click."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.settings.sigma0 = 300.0  # nothing has run yet: nothing to keep
    assert not v.restore_button.visible
    r.start()
    for _ in range(3):
        r.tick()
    old, t, sigma = r.sim, r.sim.orbits, r.sim.sigma_dimless.copy()
    n_series = r.series.size
    r.settings.sigma0 = 250.0
    assert r.sim is not old and r.sim.orbits == 0.0  # a new run at the new setting ...
    assert v.restore_button.visible and "σ₀ = 300" in v.kept.object and f"orbit {t:.2f}" in v.kept.object
    r.settings.h = 10.0  # invalid: nothing rebuilt, the kept run stays the same
    assert "σ₀ = 300" in v.kept.object
    r.settings.h = 2.5
    r.tick()
    v.restore_button.clicks += 1  # ... and the old one back with its settings, state and plots
    assert r.sim is old and r.sim.orbits == t and r.settings.sigma0 == 300.0 and r.series.size == n_series
    np.testing.assert_array_equal(r.sim.sigma_dimless, sigma)
    assert "Restored" in r.status and "σ₀ = 300" in v.header.object
    assert "σ₀ = 250" in v.kept.object  # the replaced run is kept in turn
    r.tick()
    assert r.sim is old and old.orbits > t  # and it goes on


def test_the_kept_run_is_one_unchanged_value_with_all_its_buffers():
    """The keeper holds the replaced ``LiveRun`` itself: restoring puts back that object, with its engine,
    series, images, buffer events, numbers and the settings Reset falls back to; the new run never wrote
    into it."""
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r = v.runner
    r.start()
    r.settings.buffer_on = True  # a buffer event in the first run
    for _ in range(3):
        r.tick()
    old = r.live
    parts = dict(engine=old.engine, series=old.series, strobe=old.strobe_image, orbit=old.orbit_image,
                 numbers=old.numbers, setup=dict(old.setup))
    sizes = (old.series.size, len(old.buffer_events), old.orbit_image.version)
    r.settings.sigma0 = 250.0
    r.settings.buffer_on = False  # a buffer event in the new run only
    r.tick()
    assert r.live is not old and r.series is not parts["series"] and r.numbers is not parts["numbers"]
    assert (old.series.size, len(old.buffer_events), old.orbit_image.version) == sizes  # untouched meanwhile
    v.restore_button.clicks += 1
    assert r.live is old and r.sim is parts["engine"] and r.series is parts["series"]
    assert r.strobe_image is parts["strobe"] and r.orbit_image is parts["orbit"] and r.numbers is parts["numbers"]
    assert r.buffer_events == old.buffer_events and len(r.buffer_events) == sizes[1] == 1
    assert r.live.setup == parts["setup"] and r.live.setup["sigma0"] == SMALL.get("sigma0", 400.0)
    r.settings.h = 10.0  # invalid; Reset puts it back to the restored run's setting
    r.reset()
    assert r.settings.h == parts["setup"]["h"]


def test_served_frames_stream_the_series_and_skip_unchanged_images(monkeypatch):
    """In a server session the series go out as streams of their new points: the page's copy must equal
    the buffer after every frame, also across the buffer's thinning (whole replacement then); an image
    that did not change is not sent again; the readout cards are re-rendered at most every
    READOUT_PERIOD_S but always on the final frame."""
    import ringlab.tabs.hydro.view as view_module

    clock = [100.0]
    monkeypatch.setattr(view_module, "served", lambda: True)
    monkeypatch.setattr(view_module.time, "perf_counter", lambda: clock[0])
    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r, p = v.runner, v.plots
    r.start()
    r.live.series = SeriesBuffer(("e_kin", "lambda_p"), max_points=16)  # thins after 16 points
    streamed, replaced = [], []
    p.series_source.on_change("data", lambda attr, old, new: replaced.append(1))
    from bokeh.models import ColumnDataSource
    orig_stream = ColumnDataSource.stream
    monkeypatch.setattr(ColumnDataSource, "stream",
                        lambda src, d, *a: (streamed.append(len(d["t"])), orig_stream(src, d, *a)))
    image_sends = []
    orig_update_image = p.update_image
    monkeypatch.setattr(p, "update_image", lambda runner: (image_sends.append(1), orig_update_image(runner)))
    readouts = []
    v.readouts.param.watch(lambda e: readouts.append(1), "object")
    strides = set()
    for i in range(60):
        r.sim.advance(until=r.sim.orbits + 0.15)
        clock[0] += 0.2
        r.frame += 1
        strides.add(r.series.stride)
        got = np.asarray(p.series_source.data["t"])
        assert np.array_equal(got, r.series.get("t").astype(np.float32)), (i, got.size, r.series.size)
        assert np.array_equal(np.asarray(p.series_source.data["lambda_p"]),
                              r.series.get("lambda_p").astype(np.float32))
    assert len(strides) >= 3 and streamed and replaced  # thinned twice; streamed between
    assert len(image_sends) < 60  # 0.15 orbits per frame: a strobe row every ~7 frames
    assert 10 <= len(readouts) <= 35  # 60 frames 0.2 s apart, at most every 0.5 s
    n = len(readouts)
    r.pause()
    assert len(readouts) == n + 1 and f"{r.sim.orbits:.2f}" in v.readouts.object
    r.close()


def test_a_frame_sends_the_psd_markers_only_when_lambda_p_moved_and_shares_the_slope_line(monkeypatch):
    """Per-frame work of the app process: the PSD's markers are made again only when lambda_p or the run
    changed; the linear-theory line of a series is computed once and is exactly the direct one."""
    from ringlab.model.connect import slope_line
    from ringlab.tabs.hydro import plots as plots_module

    v = HydroView(runner=HydroRunner(settings=HydroSettings(**SMALL)))
    r, p = v.runner, v.plots
    r.start()
    for _ in range(3):
        r.tick()
    made = []
    real = plots_module.wavelength_markers
    monkeypatch.setattr(plots_module, "wavelength_markers", lambda *a: made.append(1) or real(*a))
    p.update_lines(r)
    p.update_lines(r)  # the same frame again: lambda_p unchanged
    assert made == []
    p.allowed_lp = p.allowed_lp * 2  # as if lambda_p had moved
    p.update_lines(r)
    assert made == [1]
    t, e = r.series.get("t"), np.array(r.series.get("e_kin"), float)
    slope = p.mode["slope_per_orbit"]
    first = plots_module._slope_line(t, e, slope)
    assert plots_module._slope_line(t.copy(), e.copy(), slope) is first  # an equal series: remembered
    assert first == slope_line(t, e, slope) and first["t"]
    e2 = e.copy()
    e2[-1] *= 1.5
    assert plots_module._slope_line(t, e2, slope) == slope_line(t, e2, slope)  # another series: computed


def test_series_columns_are_of_one_moment_while_a_thread_adds_samples():
    """A run's chunk thread adds samples (and thins the buffer) while the event loop draws: every copy
    ``columns`` gives has columns of one length that belong together (y = 2 t, z = 3 t exactly)."""
    import threading

    s = SeriesBuffer(("y", "z"), max_points=64)
    stop = threading.Event()

    def writer():
        t = 0.0
        while not stop.is_set():
            t += 1.0
            s.add(t, y=2.0 * t, z=3.0 * t)

    th = threading.Thread(target=writer)
    th.start()
    try:
        checked = 0
        t_end = time.perf_counter() + 1.0
        while time.perf_counter() < t_end:
            cols, stride = s.columns()
            assert cols["t"].size == cols["y"].size == cols["z"].size
            assert np.array_equal(cols["y"], 2.0 * cols["t"]) and np.array_equal(cols["z"], 3.0 * cols["t"])
            assert np.all(np.diff(cols["t"]) > 0) and stride >= 1
            checked += 1
    finally:
        stop.set()
        th.join()
    assert checked > 100 and s.stride > 1  # the buffer was thinned meanwhile
