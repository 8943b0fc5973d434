"""A frame's changes in a Jupyter kernel go to a notebook page in one push per output, over the comm the page
opened, and stay held while no page has opened it, when the live views draw no frames but the forced ones
(:mod:`ringlab.server.kernel`).

The output is rendered by Panel's own notebook display (``_repr_mimebundle_``); the kernel's comm manager is a
stand-in whose ``comms`` holds what a page opens (in a real kernel ipykernel's, as
tests/browser/test_browser_notebook_offline.py exercises with JupyterLab).
"""
import asyncio
import json
import time
import types
import weakref

import IPython
import numpy as np
import panel as pn
from bokeh.document.events import ColumnDataChangedEvent, ColumnsPatchedEvent, ColumnsStreamedEvent
from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

from ringlab import HydroView
from ringlab.server import kernel
from ringlab.ui import frame_gate
from ringlab.ui.frame_gate import NO_PAGE, PAGE, PAGE_UNHEARD, UNOPENED


class PageComm:
    """The kernel's end of a comm a notebook page opened: records what is sent."""

    def __init__(self, target_name):
        self.target_name = target_name
        self.sent = []

    def send(self, data=None, metadata=None, buffers=None):
        self.sent.append(data if data is not None else buffers)


def kernel_comms(monkeypatch):
    """The comms pages opened to this stand-in kernel (installed after Panel rendered the outputs: Panel chooses
    its comm manager when it renders, and the stand-in should not become that of later tests)."""
    opened = {}
    shell = types.SimpleNamespace(kernel=types.SimpleNamespace(comm_manager=types.SimpleNamespace(comms=opened)))
    monkeypatch.setattr(IPython, "get_ipython", lambda: shell)
    return opened


def output():
    """A figure displayed as a notebook output (Panel renders it into a held document of its own)."""
    pn.extension()
    src = ColumnDataSource(dict(x=np.arange(3.0)))
    fig = figure()
    fig.line("x", "x", source=src)
    assert pn.Column(pn.pane.Bokeh(fig))._repr_mimebundle_() is not None
    return fig, src


def data_events(doc):
    """The kinds of the data changes held on ``doc`` for a page (Bokeh keeps each one: none is combined)."""
    kinds = (ColumnDataChangedEvent, ColumnsStreamedEvent, ColumnsPatchedEvent)
    return [type(e).__name__.replace("Event", "") for e in doc.callbacks._held_events if isinstance(e, kinds)]


def contents(comm):
    """The PATCH-DOC messages' event kinds sent over ``comm`` (each message: header, metadata, content, buffers)."""
    kinds = []
    for part in comm.sent:
        if isinstance(part, str) and '"events"' in part:
            kinds.append([e["kind"] for e in json.loads(part)["events"]])
    return kinds


def test_changes_go_once_a_page_opened_the_comm_and_stay_held_before(monkeypatch):
    fig, src = output()
    comms = kernel_comms(monkeypatch)

    async def run():
        doc = fig.document
        cid = kernel.comm_id(doc)
        assert cid is not None and kernel.comm_id(figure().document or doc) == cid
        assert kernel.page_state(fig) == UNOPENED  # no page has opened the output's comm
        with kernel.frame_changes():
            src.data = dict(x=np.arange(3.0) + 1)
        assert data_events(doc) == ["ColumnDataChanged"]  # held for a page that may open later

        page = comms["c1"] = PageComm(cid)  # a page renders the output and opens the comm
        other = comms["c0"] = PageComm("another output's comm")
        assert kernel.page_state(fig) == PAGE
        with kernel.frame_changes():
            src.data = dict(x=np.arange(3.0) * 2)
            with kernel.frame_changes():  # nested: the outer one pushes
                src.data = dict(x=np.arange(3.0) * 3)
            assert page.sent == []
        sent = contents(page)  # the held changes (the output's roots added as Panel rendered it, the source's
        assert len(sent) == 1 and sent[0].count("ColumnDataChanged") == 3  # data) and the two new ones: one message
        assert other.sent == []
        assert data_events(doc) == []
        assert kernel.push_views() == 0  # nothing left to send

        kernel.target().waiting = True  # a cell blocks in runner.wait(): the page is not heard
        assert kernel.page_state(fig) == PAGE_UNHEARD
        kernel.target().waiting = False
        reloaded = comms["c2"] = PageComm(cid)  # the page reloaded: the newest comm to the output's target
        with kernel.frame_changes():
            src.data = dict(x=np.arange(3.0) * 4)
        assert contents(reloaded) == [["ColumnDataChanged"]] and len(contents(page)) == 1

    asyncio.run(run())


def test_a_view_no_page_has_opened_holds_no_frames_while_it_runs_and_draws_once_one_has(monkeypatch):
    """A hydro view displayed in a kernel without a frontend: its run goes on, but no frame is drawn into the
    output's held document (Bokeh would keep each one: memory grew with the run) until the run stops or a page
    opens the output; then the page gets the held changes and the frames."""
    pn.extension()
    view = HydroView()
    assert view._repr_mimebundle_() is not None
    runner, plots = view.runner, view.plots
    doc = plots.profile_source.document
    comms = kernel_comms(monkeypatch)
    monkeypatch.setattr(frame_gate, "_FULL", weakref.WeakSet())  # this view's full gates hold no other test's runs

    async def run():
        assert kernel.page_state(plots.spacetime_fig) == UNOPENED
        sigma0 = np.asarray(plots.profile_source.data["sigma"]).copy()
        held0 = data_events(doc)
        runner.start()
        frame0 = runner.frame
        t_end = time.perf_counter() + 300  # a cold numba cache compiles the kernels in the first chunk
        while runner.frame < frame0 + 12 and time.perf_counter() < t_end:
            await asyncio.sleep(0.02)
        assert runner.frame >= frame0 + 12 and runner.running
        assert data_events(doc) == held0  # 12 frames, none drawn for nobody (each was an event before)
        np.testing.assert_array_equal(plots.profile_source.data["sigma"], sigma0)

        page = comms["c1"] = PageComm(kernel.comm_id(doc))  # a page opens the output
        frame1 = runner.frame
        while not contents(page) and time.perf_counter() < t_end:
            await asyncio.sleep(0.02)
        assert any("ColumnsStreamed" in kinds or "ColumnDataChanged" in kinds for kinds in contents(page))
        assert runner.frame > frame1
        runner.pause()
        while runner._inflight:
            await asyncio.sleep(0.02)
        await asyncio.sleep(0.1)
        np.testing.assert_array_equal(plots.profile_source.data["sigma"], runner.sim.frame().sigma)

    asyncio.run(run())


def test_no_page_outside_a_kernel_loop_or_a_notebook_output(monkeypatch):
    fig, _ = output()
    comms = kernel_comms(monkeypatch)
    assert kernel.page_state(fig) == NO_PAGE  # no event loop runs here: not a kernel
    plain = figure()
    assert kernel.page_state(plain) == NO_PAGE  # in no document

    async def run():
        comms["c"] = PageComm(kernel.comm_id(fig.document))
        assert kernel.page_state(fig) == PAGE
        from bokeh.document import Document
        Document().add_root(plain)
        assert kernel.comm_id(plain.document) is None and kernel.page_state(plain) == NO_PAGE

    asyncio.run(run())
