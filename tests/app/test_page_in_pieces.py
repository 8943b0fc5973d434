"""A page built in steps (ringlab.ui.pieces, ringlab.server.build_queue): no step holds the event loop long,
the layout put back is the layout taken apart, pages are built first come first served, and what else waits
on the loop runs between two steps."""
from __future__ import annotations

import asyncio
import time

import panel as pn
import pytest
from bokeh.document import Document
from panel.io.state import set_curdoc

from ringlab.live.session import SessionRuns
from ringlab.server import build_queue
from ringlab.tabs.hydro.view import HydroView
from ringlab.ui.pieces import put_back, put_back_all, take_apart

STEP_CPU_S = 0.08  # [s] of CPU at most per step (a piece's budget of 0.03 s of wall time plus the piece itself)


def tree(obj) -> list:
    """The layout as (depth, type, id) in document order."""
    out = []

    def walk(o, depth):
        out.append((depth, type(o).__name__, id(o)))
        for child in getattr(o, "objects", []) if isinstance(o, pn.layout.ListLike) else []:
            walk(child, depth + 1)
    walk(obj, 0)
    return out


def attached(layout, doc):
    """``doc`` holding ``layout`` (taken apart) under a root; returns (doc, holder)."""
    holder = pn.Column()
    doc.add_root(holder.get_root(doc))
    holder.append(layout)
    return doc, holder


def test_the_hydro_tab_in_pieces_holds_the_loop_briefly_and_ends_as_built():
    with set_curdoc(Document()):
        HydroView(runs=SessionRuns())  # warm-up: kernels and Bokeh's per-class caches
    doc = Document()
    with set_curdoc(doc):
        view = HydroView(runs=SessionRuns())
        layout = view.__panel__()
        before = tree(layout)
        plan = take_apart(layout, depth=99)
        assert len(plan) > 30 and layout.objects == []  # emptied down to its top container
        doc, holder = attached(layout, doc)
        cpu, steps = [], put_back(plan, budget_s=0.03)
        while True:
            t0 = time.thread_time()
            try:
                next(steps)
            except StopIteration:
                break
            cpu.append(time.thread_time() - t0)
        assert tree(layout) == before  # the same objects in the same places
        pieces_models = len(doc.models)
    # the same tab put in whole, in one step, for comparison: what the pieces avoid
    whole_doc = Document()
    with set_curdoc(whole_doc):
        whole = HydroView(runs=SessionRuns()).__panel__()
        holder = pn.Column()
        whole_doc.add_root(holder.get_root(whole_doc))
        t0 = time.thread_time()
        holder.append(whole)
        whole_cpu = time.thread_time() - t0
    assert len(cpu) >= 4, cpu
    assert max(cpu) <= STEP_CPU_S, cpu
    assert whole_cpu > max(cpu), (whole_cpu, cpu)
    assert pieces_models == len(whole_doc.models)  # the same number of Bokeh models in the page


def test_nested_layouts_come_back_piece_by_piece_and_the_apps_own_changes_stay():
    a, b, e = pn.pane.HTML("a"), pn.pane.HTML("b"), pn.pane.HTML("e")
    inner, kept, flex = pn.Row(a, b), pn.Column(pn.pane.HTML("c"), pn.pane.HTML("d")), pn.FlexBox(e)
    layout = pn.Column(inner, kept, flex)
    plan = take_apart(layout, depth=99)
    assert [len(o.objects) for o in (layout, inner, kept, flex)] == [0, 0, 0, 0]
    steps = put_back(plan, budget_s=1e-9)  # one piece per step, parents first
    next(steps)
    next(steps)
    assert layout.objects == [inner] and inner.objects == [a]
    own = pn.pane.HTML("the app's own")
    for _ in steps:
        if kept in layout.objects and own not in kept.objects:
            kept.objects = [own]  # a callback of the app sets the column's children meanwhile
    assert kept.objects == [own]  # the app's children stay; that column's remaining pieces are dropped
    assert layout.objects == [inner, kept, flex] and inner.objects == [a, b] and flex.objects == [e]
    other = pn.Column(pn.Row(pn.pane.HTML("x")), pn.pane.HTML("y"))
    before = tree(other)
    put_back_all(take_apart(other, depth=99))
    assert tree(other) == before
    one_level = take_apart(other, depth=1)  # the row goes back whole, with its child
    assert len(one_level) == 2 and other.objects == [] and len(one_level[0][1].objects) == 1
    put_back_all(one_level)
    assert tree(other) == before
    assert tree(other) == before
    with pytest.raises(ValueError, match="budget_s"):
        next(put_back(plan, budget_s=0))


class FakeDoc:
    """A served document's two hooks the build queue uses: next-tick callbacks on the running loop, and
    the session-destroyed callbacks."""

    def __init__(self):
        self.destroyed = []

    def add_next_tick_callback(self, cb):
        asyncio.get_running_loop().call_soon(cb)

    def on_session_destroyed(self, cb):
        self.destroyed.append(cb)

    def close(self):
        for cb in self.destroyed:
            cb(None)


def test_pages_are_built_first_come_first_served_with_the_loop_free_between_steps(monkeypatch):
    log = []
    monkeypatch.setattr(build_queue.gc_policy, "page_built", lambda: log.append("frozen"))

    def tab(name):
        for k in range(2):
            log.append(f"{name} piece {k}")
            yield

    def page(name):
        log.append(f"{name} frame")
        yield
        assert build_queue.follow(tab(name))  # a tab built now: its pieces run next
        log.append(f"{name} tab built")
        yield
        log.append(f"{name} done")

    async def scenario():
        a, b = FakeDoc(), FakeDoc()
        ta = build_queue.start(a, page("A"))
        tb = build_queue.start(b, page("B"))

        async def others():  # what else waits on the loop: frames, clicks, another page's document
            for _ in range(12):
                log.append("other")
                await asyncio.sleep(0)
        await asyncio.gather(ta, tb, others())

    asyncio.run(scenario())
    mine = [x for x in log if x != "other"]
    assert mine == ["A frame", "A tab built", "A piece 0", "A piece 1", "A done", "frozen",
                    "B frame", "B tab built", "B piece 0", "B piece 1", "B done", "frozen"]
    first, last = log.index("A frame"), log.index("A done")
    assert "other" in log[first:last]  # the loop ran other callbacks between the page's steps
    assert not build_queue.follow(iter(()))  # outside a step there is no build to follow


def test_a_page_closed_while_it_waits_is_dropped_and_the_next_one_built(monkeypatch):
    log = []
    monkeypatch.setattr(build_queue.gc_policy, "page_built", lambda: log.append("frozen"))

    def page(name, doc=None):
        log.append(f"{name} 1")
        yield
        if doc is not None:
            doc.close()  # the student closed the page while it was built
        yield
        log.append(f"{name} 2")

    async def scenario():
        a, b = FakeDoc(), FakeDoc()
        await asyncio.gather(build_queue.start(a, page("A", a)), build_queue.start(b, page("B")))

    asyncio.run(scenario())
    assert log == ["A 1", "B 1", "B 2", "frozen"]


def test_without_a_running_loop_every_step_runs_at_once():
    log = []

    def page():
        log.append(1)
        yield
        build_queue.follow(tab())
        log.append(3)

    def tab():
        log.append(2)
        yield
    assert build_queue.start(None, page()) is None
    assert log == [1, 3, 2]  # the followed tab runs after the step that asked for it
