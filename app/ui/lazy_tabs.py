"""Tabs whose content is built when first needed (:class:`LazyTabs`), so opening a page costs little.

A page of the lab has six tabs; building all of them (their runners, figures and data) cost 1.6-1.9 s of
server CPU per page, which a class joining at once waits for.  ``pn.Tabs(dynamic=True)`` only defers
sending a hidden tab to the browser, not building it in Python.  Here each tab is a factory: the tab
shown first is built at once, the others hold a one-line note until they are opened (``active``) or
asked for by :meth:`LazyTabs.view` (a lesson, the teacher's "send everyone", "Run this in ...").

**In steps, on a served page** (``later=True``).  The server's event loop does one thing at a time: while it
builds a page, every other page waits (its frames, clicks, slider readouts).  Building the class start link's
page in one piece held the loop for 0.4-0.5 s of CPU (0.5-0.9 s of wall time with a class joining), a stop of
every page per student.  With ``later`` the page's document is sent with a note in its first tab; once the
page has loaded (``pn.state.onload``) the tab comes in turns of the event loop, each its own callback
(:meth:`LazyTabs.build_soon`): its Python objects (runner, figures, widgets); its Bokeh models without its
heavy parts and the message that brings them to the page; then each heavy part (the tab's ``fill_steps``: the
hydro tab's two plot groups).  A tab opened later comes the same way.  Measured for the class start link's page
(``scripts/measure_page_steps.py``, CPU of the loop's thread, loaded 2-core machine): its longest piece 0.10-0.15 s
instead of 0.37-0.46 s in one.  A caller that needs a tab at once (a lesson step, a reloaded page's run) still
gets it whole in one piece (:meth:`LazyTabs.view`); :meth:`LazyTabs.when_built` runs code once a tab is whole.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

import panel as pn
import param

NOTE_CSS = ":host {color: #555; font-size: 14px; padding: 12px 16px;}"


def _note(title: str) -> pn.pane.HTML:
    """What a not yet built tab holds: replaced by the tab's content as soon as the tab is opened."""
    return pn.pane.HTML(f'<div class="tab-opening">Opening the {title} tab …</div>', stylesheets=[NOTE_CSS],
                        sizing_mode="stretch_width", css_classes=["tab-opening"])


class LazyTabs(param.Parameterized):
    """A ``pn.Tabs`` (:attr:`tabs`) whose tab ``i`` is built by ``factories[i]()`` on first use.

    Parameters
    ----------
    titles : sequence of str
        The tab titles.
    factories : sequence of callables
        ``factories[i]()`` returns tab ``i``'s content (a viewer or a Panel object), built once.
    first : int
        The tab shown (and built) at once.
    on_built : callable, optional
        ``on_built(lazy, i, view)`` after tab ``i`` of ``lazy`` (this object) was built and put in its tab.
    later : bool
        Build the first tab (and the tabs opened later) in steps once the page has loaded
        (:meth:`build_soon`), not now: for a served page.  Without a server the steps run at once.
    **tabs_params
        Passed to ``pn.Tabs`` (``dynamic=True`` is set: hidden tabs are not sent to the page either).
    """

    built_count = param.Integer(default=0, doc="How many tabs are built so far.")

    def __init__(self, titles: Sequence[str], factories: Sequence[Callable], first: int = 0,
                 on_built: Callable | None = None, later: bool = False, **tabs_params):
        super().__init__()
        if len(titles) != len(factories):
            raise ValueError(f"{len(titles)} titles for {len(factories)} factories: allowed one title per factory")
        if not 0 <= first < len(titles):
            raise ValueError(f"first = {first} is not a tab: allowed 0 .. {len(titles) - 1}")
        self.titles, self.factories = list(titles), list(factories)
        self._views: list = [None] * len(self.titles)
        self._placed = [False] * len(self.titles)  # tab i holds its content (not the note)
        self._on_built = on_built
        self._waiting: dict = {}  # i -> callables waiting for tab i (when_built)
        self._soon: set = set()  # tabs whose build in steps is under way
        self._steps: dict = {}  # i -> fill steps of tab i still to run (placed, not yet whole)
        self.later = bool(later)
        first_view = None if self.later else self._build(first)
        objects = [(t, first_view if i == first and first_view is not None else _note(t))
                   for i, t in enumerate(self.titles)]
        self.tabs = pn.Tabs(*objects, active=first, **{**tabs_params, "dynamic": True})
        # after Panel's own watcher rendered the note of the newly active tab: the tab's content replaces it
        self.tabs.param.watch(lambda e: self.build_soon(e.new) if self.later else self.view(e.new), "active")
        if first_view is not None:
            self._placed[first] = True
            self._steps[first] = []
            self._finish(first)
        else:
            self.build_soon(first)

    def _check(self, i: int) -> None:
        if not 0 <= i < len(self._views):
            raise IndexError(f"tab {i} does not exist: allowed 0 .. {len(self._views) - 1}")

    def _build(self, i: int):
        view = self.factories[i]()
        self._views[i] = view
        self.built_count += 1
        return view

    def _place(self, i: int, in_steps: bool = False) -> None:
        """Put tab ``i``'s content (built) in its tab; ``in_steps``: without its heavy parts, whose fill steps
        (the tab's ``fill_steps()``) wait in ``_steps``."""
        fill = getattr(self._views[i], "fill_steps", None) if in_steps else None
        self._steps[i] = list(fill()) if fill is not None else []
        self._placed[i] = True
        self.tabs[i] = (self.titles[i], self._views[i])

    def _finish(self, i: int) -> None:
        """Tab ``i``'s remaining fill steps now, then tell ``on_built`` and the waiting callers (once)."""
        while self._steps.get(i):
            self._steps[i].pop(0)()
        if i in self._steps:
            del self._steps[i]
            self._done(i)

    def _done(self, i: int) -> None:
        if self._on_built is not None:
            self._on_built(self, i, self._views[i])
        view = self._views[i]
        for fn in self._waiting.pop(i, []):
            pn.state.execute(lambda fn=fn: fn(view), schedule=True)  # a turn of their own on a served page

    def view(self, i: int):
        """Tab ``i``'s content, built now if it was not yet (then shown in its tab, whole)."""
        self._check(i)
        if self._views[i] is None:
            self._build(i)
        if not self._placed[i]:
            self._place(i)
        self._finish(i)
        return self._views[i]

    def build_soon(self, i: int) -> None:
        """Build tab ``i`` in steps, each its own turn of the event loop, once the page has loaded: the tab's
        objects; then its place in the page (its Bokeh models and the message that brings them); then each of
        its fill steps.  Without a server: all at once."""
        self._check(i)
        if self._placed[i] or i in self._soon:
            return
        self._soon.add(i)
        pn.state.onload(lambda: pn.state.execute(lambda: self._soon_build(i), schedule=True))

    def _soon_build(self, i: int) -> None:
        if self._views[i] is None:
            self._build(i)
        pn.state.execute(lambda: self._soon_place(i), schedule=True)

    def _soon_place(self, i: int) -> None:
        self._soon.discard(i)
        if not self._placed[i]:
            self._place(i, in_steps=True)
        pn.state.execute(lambda: self._soon_fill(i), schedule=True)

    def _soon_fill(self, i: int) -> None:
        if self._steps.get(i):
            self._steps[i].pop(0)()
            pn.state.execute(lambda: self._soon_fill(i), schedule=True)
        else:
            self._finish(i)

    def when_built(self, i: int, fn: Callable) -> None:
        """Call ``fn(view)`` once tab ``i`` is built and whole in its tab (now if it is; on a served page in a
        turn of the event loop of its own)."""
        self._check(i)
        if self._placed[i] and i not in self._steps:
            fn(self._views[i])
        else:
            self._waiting.setdefault(i, []).append(fn)

    def is_built(self, i: int) -> bool:
        """True if tab ``i`` is built (it may still wait for its place: :meth:`build_soon`)."""
        return self._views[i] is not None

    def built(self) -> list:
        """The tabs' contents built so far, in tab order."""
        return [v for v in self._views if v is not None]

    def __len__(self) -> int:
        return len(self._views)


class LazyViews(Sequence):
    """``app.views``: the tabs' contents as a sequence that builds a tab when it is read.

    Iterating builds every tab (what a caller reading all views needs); :meth:`built` reads
    only those built so far.
    """

    def __init__(self, lazy: LazyTabs):
        self._lazy = lazy

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self._lazy.view(j) for j in range(len(self))[i]]
        return self._lazy.view(range(len(self))[i])

    def __len__(self) -> int:
        return len(self._lazy)

    def built(self) -> list:
        """The views built so far (no tab is built by this)."""
        return self._lazy.built()
