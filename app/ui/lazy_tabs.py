"""Tabs whose content is built when first needed (:class:`LazyTabs`), so opening a page costs little.

A page of the lab has six tabs; building all of them (their runners, figures and data) cost 1.6-1.9 s of
server CPU per page, which a class joining at once waits for.  ``pn.Tabs(dynamic=True)`` only defers
sending a hidden tab to the browser, not building it in Python.  Here each tab is a factory: the tab
shown first is built at once, the others hold a one-line note until they are opened (``active``) or
asked for by :meth:`LazyTabs.view` (a lesson, the teacher's "send everyone", "Run this in ...").
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
        ``on_built(lazy, i, view)`` after tab ``i`` of ``lazy`` (this object) was built.
    **tabs_params
        Passed to ``pn.Tabs`` (``dynamic=True`` is set: hidden tabs are not sent to the page either).
    """

    built_count = param.Integer(default=0, doc="How many tabs are built so far.")

    def __init__(self, titles: Sequence[str], factories: Sequence[Callable], first: int = 0,
                 on_built: Callable | None = None, **tabs_params):
        super().__init__()
        if len(titles) != len(factories):
            raise ValueError(f"{len(titles)} titles for {len(factories)} factories: allowed one title per factory")
        if not 0 <= first < len(titles):
            raise ValueError(f"first = {first} is not a tab: allowed 0 .. {len(titles) - 1}")
        self.titles, self.factories = list(titles), list(factories)
        self._views: list = [None] * len(self.titles)
        self._on_built = on_built
        first_view = self._build(first)
        objects = [(t, first_view if i == first else _note(t)) for i, t in enumerate(self.titles)]
        self.tabs = pn.Tabs(*objects, active=first, **{**tabs_params, "dynamic": True})
        # after Panel's own watcher rendered the note of the newly active tab: the tab's content replaces it
        self.tabs.param.watch(lambda e: self.view(e.new), "active")
        if on_built is not None:
            on_built(self, first, first_view)

    def _build(self, i: int):
        view = self.factories[i]()
        self._views[i] = view
        self.built_count += 1
        return view

    def view(self, i: int):
        """Tab ``i``'s content, built now if it was not yet (then shown in its tab)."""
        if not 0 <= i < len(self._views):
            raise IndexError(f"tab {i} does not exist: allowed 0 .. {len(self._views) - 1}")
        if self._views[i] is None:
            view = self._build(i)
            self.tabs[i] = (self.titles[i], view)
            if self._on_built is not None:
                self._on_built(self, i, view)
        return self._views[i]

    def is_built(self, i: int) -> bool:
        """True if tab ``i`` is built."""
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
