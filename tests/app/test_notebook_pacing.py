"""Pacing of live plots in a notebook page, without a browser: frames that replace whole columns go as rollover
streams, acknowledgements combined in one page message all count, and a full gate holds the kernel's runs."""
import weakref

import numpy as np
from bokeh.document import Document
from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

from ringlab.ui import frame_gate
from ringlab.ui.columns import replace_columns
from ringlab.ui.frame_gate import HOLD_S, NO_PAGE, PAGE, UNOPENED, FrameGate


def test_same_shape_columns_are_streamed_in_a_notebook_page_only():
    src = ColumnDataSource(dict(x=np.arange(3.0), y=np.zeros(3)))
    kept = src.data
    new = dict(x=np.arange(3.0) + 1, y=np.ones(3))
    replace_columns(src, new, stream=True)
    assert src.data is kept  # streamed (a rollover over the old values), not replaced
    assert np.array_equal(src.data["x"], new["x"]) and np.array_equal(src.data["y"], new["y"])
    new["x"][:] = -1  # the source holds its own values
    assert src.data["x"][0] == 1.0
    replace_columns(src, dict(x=np.arange(4.0), y=np.zeros(4)), stream=True)  # another length: replaced
    assert src.data is not kept and len(src.data["x"]) == 4
    kept = src.data
    replace_columns(src, dict(x=np.arange(4.0), y=np.ones(4)), stream=False)  # no page (or a server): replaced
    assert src.data is not kept
    lists = ColumnDataSource(dict(x=[1.0, 2.0], label=["a", "b"]))
    kept = lists.data
    replace_columns(lists, dict(x=[3.0, 4.0], label=["c", "d"]), stream=True)
    assert lists.data is kept and lists.data["label"] == ["c", "d"]


def notebook_gate(monkeypatch, max_in_flight=2, page=PAGE):
    monkeypatch.setattr(frame_gate, "_page_probe", lambda model: page)  # a notebook page shows the plot (default)
    monkeypatch.setattr(frame_gate, "_FULL", weakref.WeakSet())  # no other test's gates
    fig = figure()
    Document().add_root(fig)
    return fig, FrameGate(fig, ColumnDataSource(dict(x=[])), max_in_flight=max_in_flight)


def test_acknowledgements_combined_in_one_message_all_count(monkeypatch):
    fig, gate = notebook_gate(monkeypatch)
    now = 100.0
    for _ in range(2):  # frames at most 2 per second (a period early at most by half)
        assert gate.ready(now)
        gate.mark_sent(now, changed=True)
        now += 0.45
    assert not gate.ready(now)  # two frames the page has not drawn
    fig.tags = [2]  # the page drew both; Panel hands the two acknowledgements over as one change
    for _ in range(2):  # so two frames may go again (counting one acknowledgement let only one go)
        assert gate.ready(now)
        gate.mark_sent(now, changed=True)
        now += 0.45
    assert not gate.ready(now)


def test_a_full_gate_holds_the_runs_until_the_page_draws_or_has_gone(monkeypatch):
    fig, gate = notebook_gate(monkeypatch, max_in_flight=1)
    now = 200.0
    assert gate.ready(now)
    gate.mark_sent(now, changed=True)
    assert not frame_gate.page_behind(now)  # not full until a frame is refused
    assert not gate.ready(now + 0.6)
    assert frame_gate.page_behind(now + 0.6)
    assert not frame_gate.page_behind(now + HOLD_S + 0.1)  # no acknowledgement for HOLD_S: the page has gone
    fig.tags = [1]
    assert not frame_gate.page_behind(now + 0.7)


def test_a_page_that_stalls_holds_the_runs_though_no_gate_is_full(monkeypatch):
    fig, gate = notebook_gate(monkeypatch, max_in_flight=2)
    now = 300.0
    assert gate.ready(now)
    gate.mark_sent(now, changed=True)  # one frame of two in flight: not full
    later = now + frame_gate.PAGE_GONE_S + 0.1
    assert not gate.ready(later)  # no acknowledgement for PAGE_GONE_S: no more frames to a page that stalls ...
    assert frame_gate.page_behind(later)  # ... and the runs wait for it (they went on: the page fell behind)
    assert not frame_gate.page_behind(now + HOLD_S + 0.1)  # it has gone
    fig.tags = [1]
    assert not frame_gate.page_behind(later) and gate.ready(later)


def test_an_output_no_page_has_opened_gets_no_frames_until_one_has(monkeypatch):
    """A kernel without a frontend: a frame drawn into an output no page has opened would stay in the kernel (Bokeh
    holds every data change for the page), so the gate lets none through; once a page has opened it, frames go."""
    state = {"page": UNOPENED}
    fig, gate = notebook_gate(monkeypatch, page=None)
    monkeypatch.setattr(frame_gate, "_page_probe", lambda model: state["page"])
    now = 400.0
    for _ in range(20):
        assert not gate.ready(now) and not frame_gate.page_behind(now)  # and the runs go on
        now += 0.5
    state["page"] = PAGE
    assert gate.ready(now)
    state["page"] = NO_PAGE  # a script or a headless test: frames at the gate's own period
    assert gate.ready(now)
