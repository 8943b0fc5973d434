"""Every tab of the page implements the Tab protocol (ringlab.ui.tab): in its own class body, or by TabBase's
common answers, and the shell (ringlab.main) reaches a tab through it only."""
from __future__ import annotations

import inspect

import pytest

from ringlab import main
from ringlab.live.session import SessionRuns
from ringlab.ui.tab import TAB_METHODS, Tab, TabBase


@pytest.mark.parametrize("title,cls", main.TABS, ids=[t for t, _ in main.TABS])
def test_each_tab_class_implements_the_protocol_itself(title, cls):
    assert issubclass(cls, Tab) and issubclass(cls, TabBase)
    for name in TAB_METHODS:
        owner = next(k for k in cls.__mro__ if name in vars(k))
        assert owner in (cls, TabBase), f"{cls.__name__}.{name} comes from {owner.__name__}, not the tab or TabBase"
        ours = inspect.signature(getattr(Tab, name))
        theirs = inspect.signature(getattr(cls, name))
        assert list(theirs.parameters) == list(ours.parameters), (cls.__name__, name)


def test_protocol_lists_the_methods_the_shell_calls():
    assert set(TAB_METHODS) == {n for n in vars(Tab) if not n.startswith("_") or n == "__panel__"} - {
        "_is_protocol", "_is_runtime_protocol"}


def test_the_shell_builds_shows_and_hides_tabs_through_the_protocol():
    app = main.create_app({"tab": [b"hydro"]})
    hydro = app.views[1]
    assert isinstance(hydro, Tab) and hydro.shown is True and hydro.start_runner() is hydro.runner
    app.tabs.active = 2  # the N-body tab is built and shown, the hydro tab hidden
    nbody = app.views[2]
    assert hydro.shown is False and nbody.shown is True
    app.tabs.active = 0
    linear = app.views[0]
    assert linear.tabs is app.tabs and linear.start_runner() is None and nbody.shown is False
    for view in app.views.built():
        view.__panel__()
    for v in (hydro, nbody):
        v.runner.close()


def test_for_session_registers_live_tabs_with_the_session():
    runs = SessionRuns()
    view = main._make(main.TABS[1][1], runs)
    assert runs.tab("hydro")[0] is view
    view.runner.close()
