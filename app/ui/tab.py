"""What the app shell (:mod:`ringlab.main`) calls on a tab: the :class:`Tab` protocol.

Every tab class of the lab defines each of these methods itself (a test checks the class bodies), and the
shell calls nothing else on a tab: it builds the tab for a session (:meth:`Tab.for_session`), hands it the
page's ``pn.Tabs`` (:meth:`Tab.set_tabs`), tells it whether it is the tab shown (:meth:`Tab.set_shown`),
presses the Start of its run for a class start link (:meth:`Tab.start_runner`) and lays it out
(``__panel__``).  A new tab implements the protocol and is listed in ``ringlab.main.TABS``.
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

TAB_METHODS = ("for_session", "set_tabs", "set_shown", "start_runner", "__panel__")


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

    def __panel__(self):
        """The tab's layout (a Panel object)."""
