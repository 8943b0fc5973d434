"""What the app shell (:mod:`ringlab.main`) calls on a tab: the :class:`Tab` protocol.

Every tab class of the lab derives from :class:`TabBase` (the protocol's common answers, each said in its
docstring) and defines in its own body what differs (a test checks each method is the tab's or the base's), and
the shell calls nothing else on a tab: it builds the tab for a session (:meth:`Tab.for_session`), hands it the
page's ``pn.Tabs`` (:meth:`Tab.set_tabs`), tells it whether it is the tab shown (:meth:`Tab.set_shown`),
presses the Start of its run for a class start link (:meth:`Tab.start_runner`), lays it out (``__panel__``) and, in a
served page, may have its heavy parts come after the rest (:meth:`Tab.fill_steps`).  A new tab derives from
:class:`TabBase`, overrides what differs and is listed in ``ringlab.main.TABS``.
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

TAB_METHODS = ("for_session", "set_tabs", "set_shown", "start_runner", "fill_steps", "__panel__")


@runtime_checkable
class Tab(Protocol):
    """A tab of the lab's page, as the app shell uses it."""

    @classmethod
    def for_session(cls, runs) -> "Tab":
        """The tab for one browser session; ``runs`` is the session's
        :class:`ringlab.live.session.SessionRuns` (a tab without live runs may ignore it)."""

    def set_tabs(self, tabs) -> None:
        """The page's ``pn.Tabs`` (a tab that shows other tabs, e.g. "Run this in ...", keeps it)."""

    def set_shown(self, shown: bool) -> None:
        """Whether this is the tab shown now (a live tab draws its frames only while it is)."""

    def start_runner(self) -> Any | None:
        """The runner whose ``start()`` a class start link (``?tab=...&autostart=1``) presses, or None."""

    def fill_steps(self) -> list:
        """Take the heavy parts out of the layout (not shown yet; each leaves a note) and return the callables
        that put them back, one by one: a served page runs each in a turn of the server's event loop of its own
        after the rest of the tab reached the page (``ringlab.ui.lazy_tabs``).  Called at most once; a layout
        nobody asks is whole.  Empty: nothing comes later."""

    def __panel__(self):
        """The tab's layout (a Panel object)."""


# Called with a tab each time it is displayed as a notebook output (after Panel rendered it): ringlab.views adds the
# one that has the output load Panel's stylesheets from the Jupyter server (this layer may not import the server's).
ON_DISPLAY: list = []


class TabBase:
    """The :class:`Tab` protocol's common answers, for a tab class to derive from (before ``pn.viewable.Viewer``)
    and override where it differs: built with the session's runs, shows no other tab, streams nothing (so being
    shown changes nothing), has no run to start, laid out whole as its ``_layout``."""

    def _repr_mimebundle_(self, include=None, exclude=None):
        """IPython's display of the tab: Panel's notebook output, then each of :data:`ON_DISPLAY` with the tab."""
        bundle = super()._repr_mimebundle_(include, exclude)
        for hook in list(ON_DISPLAY):
            hook(self)
        return bundle

    @classmethod
    def for_session(cls, runs):
        """This tab with the session's runs."""
        return cls(runs=runs)

    def set_tabs(self, tabs) -> None:
        """This tab shows no other tab."""
        return None

    def set_shown(self, shown: bool) -> None:
        """Nothing streams here: what the tab shows does not depend on its being shown."""
        return None

    def start_runner(self):
        """None: no run to start."""
        return None

    def fill_steps(self) -> list:
        """Nothing comes later: the layout stays whole."""
        return []

    def __panel__(self):
        return self._layout
