"""A layout sent to its page in pieces, so that no single turn of the server's event loop builds it whole.

Putting a tab's layout into a page that is already shown makes Panel build the Bokeh models of everything in
it and Bokeh serialise them into one message, in one callback of the event loop: 0.2-0.35 s of CPU for the
Hydrodynamics tab, during which no other page gets a frame, a click or its document.  :func:`take_apart`
empties every list-like container of a layout (``pn.Column``, ``pn.Row``, ``pn.FlexBox``, ``pn.GridBox``,
``pn.Card`` ...) and returns the children to put back, in document order (what is at the top of the page
first); :func:`put_back` is a generator that puts them back, a budget of :data:`BUDGET_S` of CPU time per step
(one ``pn.io.hold`` each: one message to the page per step; one ``doc.models.freeze()`` each: Bokeh re-indexes
the document's models once per step, not after every piece), and yields between steps.  Whoever drives it runs
one step per turn of the event loop (:mod:`ringlab.server.build_queue`), so everything else that waits on the
loop runs in between.  Driven to the end at once (:func:`put_back_all`), the layout is the one taken apart.

A container whose children the app changes meanwhile (a callback replacing ``objects``) keeps what the app put
there: its remaining pieces are dropped, never added on top.
"""
from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import nullcontext

import panel as pn
from panel.layout.base import ListLike

# [s] of CPU time spent putting pieces back per step; each step then also re-indexes the document and sends its
# message (about a third more), and each costs that again: 0.04 s made the Hydrodynamics tab 26 steps and 1.6x the
# CPU of one whole build, 0.08 s about 8 steps
BUDGET_S = 0.08
DEPTH = 3  # container levels taken apart (a tab: its columns, their rows, the figures of a row)


def take_apart(layout, depth: int = DEPTH) -> list:
    """Empty the list-like containers in the tree of ``layout`` (``layout`` included) down to ``depth`` levels
    below it; returns the ``(container, child)`` pairs to put back, parents before their children, in document
    order.  Deeper containers go back whole with their parent piece: every piece put into a shown page makes
    Panel walk the page's whole model tree again, so many small pieces cost more in all than a few large ones."""
    plan: list = []

    def walk(obj, level):
        if not isinstance(obj, ListLike) or level >= depth:
            return
        children = list(obj.objects)
        if not children:
            return
        obj.objects = []
        for child in children:
            plan.append((obj, child))
            walk(child, level + 1)

    walk(layout, 0)
    return plan


def put_back(plan: list, budget_s: float = BUDGET_S) -> Iterator[int]:
    """Put the children of ``plan`` (from :func:`take_apart`) back, at least one and at most ``budget_s`` of
    this thread's CPU time per step (CPU, not wall time: on a busy machine the steps stay as large); yields the number of pieces put back after each step (the last step included)."""
    if not budget_s > 0:
        raise ValueError(f"budget_s = {budget_s!r} is not valid: allowed > 0 s")
    placed: dict = {}  # id(container) -> the children this generator has given it (identity), in order
    dropped: set = set()  # id(container) whose children the app changed meanwhile
    i = 0
    while i < len(plan):
        t0 = time.thread_time()
        doc = pn.state.curdoc
        # Bokeh re-indexes the whole document after each change of its model graph: once per step, not per piece
        with pn.io.hold(), (doc.models.freeze() if doc is not None else nullcontext()):
            while i < len(plan):
                container, child = plan[i]
                i += 1
                key = id(container)
                mine = placed.setdefault(key, [])
                if key in dropped:
                    continue
                if [id(o) for o in container.objects] != [id(o) for o in mine]:
                    dropped.add(key)  # the app set this container's children itself: they stay
                    continue
                container.append(child)
                mine.append(container.objects[-1])
                if time.thread_time() - t0 >= budget_s:
                    break
        yield i


def put_back_all(plan: list) -> None:
    """Put every piece of ``plan`` back now (no server loop to yield to: a script, a notebook, a test)."""
    for _ in put_back(plan, budget_s=float("inf")):
        pass


__all__ = ["BUDGET_S", "put_back", "put_back_all", "take_apart"]
