"""The stroboscopic space-time diagram reaches the page as new rows: the page holds a canvas of all the
image's rows (NaN, drawn transparent, where no row has been computed) and each frame patches only the rows
added since the last one; a thinning (rows averaged in pairs), another image or the orbit-resolved window sends
the whole image again (ringlab.tabs.hydro.plots.HydroPlots.update_image)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from bokeh.document import Document
from bokeh.document.events import ColumnDataChangedEvent, ColumnsPatchedEvent

from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.hydro.frame import IMAGE_COLUMNS, bin_columns
from ringlab.live.buffers import RollingImage, SpaceTimeImage
from ringlab.server.engine_host import EngineHost
from ringlab.tabs.hydro.plots import HydroPlots

L_X = 1000.0


def runner_showing(img, spacetime="stroboscopic"):
    return SimpleNamespace(settings=SimpleNamespace(spacetime=spacetime), shown_image=img,
                           sim=SimpleNamespace(options=SimpleNamespace(L_x=L_X)))


def plots_with_events():
    plots = HydroPlots()
    doc = Document()
    doc.add_root(plots.spacetime_fig)
    events = []
    doc.callbacks.on_change(lambda event: events.append(event))
    return plots, events


def kinds(events) -> list:
    out = []
    for e in events:
        if isinstance(e, ColumnsPatchedEvent):
            out.append(("patch", sorted(e.patches)))
        elif isinstance(e, ColumnDataChangedEvent):
            out.append(("data", None))
    return out


def check_canvas(plots, img) -> None:
    """The page's canvas: the image's rows, oldest first, then NaN; its height puts the rows shown between the
    first row's time and just after the last's (as the whole image of those rows did)."""
    data = plots.image_source.data
    canvas = np.asarray(data["image"][0])
    assert canvas.shape == (img.max_rows, img.ncols) and canvas.dtype == np.float32
    np.testing.assert_array_equal(canvas[:img.rows], img.image())
    assert np.isnan(canvas[img.rows:]).all()
    t0, t1 = img.extent()
    assert data["y"] == [t0] and data["dw"] == [L_X] and data["x"] == [-L_X / 2]
    assert np.isclose(data["dh"][0] * img.rows / img.max_rows, t1 - t0, rtol=1e-12)


def test_frames_send_only_the_new_rows_until_the_image_thins():
    rng = np.random.default_rng(4)
    img = SpaceTimeImage(64, 1.0, max_rows=8)
    plots, events = plots_with_events()
    runner = runner_showing(img)
    frames, added = [], 0
    for frame in range(20):
        for _ in range(1 + frame % 2):  # one or two rows per frame, at slightly uneven times (as a run's samples)
            img.add(added + 0.05 * (added % 3), rng.random(64))
            added += 1
        events.clear()
        plots.update_image(runner)
        check_canvas(plots, img)
        frames.append(kinds(events))
    assert frames[0] == [("data", None)]  # the first frame: the whole canvas
    patches = [f for f in frames if f and f[0][0] == "patch"]
    fulls = [f for f in frames if f and f[0][0] == "data"]
    # new rows (and the canvas's height if the rows' spacing changed); nothing when the frame's rows were averaged
    # into one not yet complete
    assert all(len(f) == 1 and "image" in f[0][1] for f in patches), frames
    assert all(f in ([], [("data", None)]) for f in frames if f not in patches), frames
    assert len(patches) >= 8 and 2 <= len(fulls) <= 5, frames  # thinned at 8 rows: a few whole canvases


def test_a_patch_carries_the_new_rows_only():
    img = SpaceTimeImage(500, 1.0)
    plots, events = plots_with_events()
    runner = runner_showing(img)
    for k in range(300):
        img.add(float(k), np.full(500, 1.0 + k))
    plots.update_image(runner)
    for k in range(300, 303):
        img.add(float(k), np.full(500, 1.0 + k))
    events.clear()
    plots.update_image(runner)
    (patch,) = [e for e in events if isinstance(e, ColumnsPatchedEvent)]
    (((index, rows, cols), values),) = patch.patches["image"]
    assert index == 0 and (rows.start, rows.stop) == (300, 303) and (cols.start, cols.stop) == (0, 500)
    assert np.asarray(values).size == 3 * 500  # 6 kB, where the whole image was 606 kB
    check_canvas(plots, img)


def test_another_image_and_the_orbit_resolved_window_are_sent_whole():
    plots, events = plots_with_events()
    a, b = SpaceTimeImage(32, 1.0), SpaceTimeImage(32, 1.0)
    for k in range(5):
        a.add(float(k), np.full(32, 1.0))
        b.add(float(k), np.full(32, 2.0))
    plots.update_image(runner_showing(a))
    events.clear()
    plots.update_image(runner_showing(b))  # a restored or new run with as many rows: not a continuation
    assert kinds(events) == [("data", None)]
    check_canvas(plots, b)
    roll = RollingImage(32, 0.05, max_rows=4)
    for k in range(6):
        roll.add(0.05 * k, np.full(32, float(k)))
    events.clear()
    plots.update_image(runner_showing(roll, "orbit-resolved"))
    assert kinds(events) == [("data", None)]
    np.testing.assert_array_equal(plots.image_source.data["image"][0], roll.image())
    events.clear()
    plots.update_image(runner_showing(b))  # back to the stroboscopic image: whole again
    assert kinds(events) == [("data", None)]
    check_canvas(plots, b)


def test_rows_not_computed_yet_are_transparent():
    assert HydroPlots().color_mapper.nan_color == "rgba(0, 0, 0, 0)"


def test_a_worker_sends_each_sample_row_binned_and_the_image_is_the_one_of_the_full_rows():
    """A worker bins each sample's profile to the image's columns once (every page following a shared run used
    to bin every row again); binning a binned row again changes nothing, so the orbit-resolved image a page keeps
    is the one it keeps from the engine's own full rows, value for value."""
    opt = HydroOptions(L_x=2000.0, h=2.5, samples_per_orbit=20)
    local = Hydro1D(params.get("tau15", 400.0), opt, initial="noise", seed=3)
    host = EngineHost(local.snapshot(), renice=False)
    full = []
    local.on_sample(lambda sim, s: full.append((s["orbit"], sim.U[0].copy())))
    local.advance(orbits=1.0)
    res = host.advance(orbits=1.0)
    rows = [(s["orbit"], s["sigma_row"]) for s in res["samples"]]
    assert len(rows) == len(full) == 20
    assert all(r.dtype == np.float32 and r.size == 400 <= IMAGE_COLUMNS for _, r in rows)
    a, b = RollingImage(local.n, 0.05), RollingImage(local.n, 0.05)
    for (t, row), (t_full, row_full) in zip(rows, full):
        assert t == t_full
        np.testing.assert_array_equal(bin_columns(row), row)
        a.add(t, row)
        b.add(t_full, row_full)
    np.testing.assert_array_equal(a.image(), b.image())
