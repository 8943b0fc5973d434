"""Automatic axis ranges stay in the page: every ``DataRange1d`` of every tab is not synchronised back to the
server (BokehJS recomputes it from the data at each frame; the server never reads it), while the explicit
``Range1d`` axes the server sets keep Bokeh's default (ringlab.ui.figures.quiet_auto_ranges)."""
from __future__ import annotations

from unittest import mock

import panel as pn
from bokeh.document import Document
from bokeh.models import DataRange1d, Range1d

from ringlab import main
from ringlab.main import TABS
from ringlab.ui.figures import new_figure


def test_new_figure_keeps_auto_ranges_in_the_page_and_explicit_ones_synchronised():
    auto = new_figure("t", "x", "y")
    assert isinstance(auto.x_range, DataRange1d) and not auto.x_range.syncable and not auto.y_range.syncable
    fixed = new_figure("t", "x", "y", x_range=Range1d(0, 1))
    assert fixed.x_range.syncable and not fixed.y_range.syncable


def test_no_auto_range_of_any_tab_is_synchronised():
    with mock.patch.object(type(pn.state), "session_args", new=property(lambda self: {})):
        app = main.create_app()
        models = []
        for i in range(len(TABS)):  # each tab built and rendered (the page's tabs render only the one shown)
            doc = Document()
            doc.add_root(pn.panel(app.views[i]).get_root(doc))
            models += list(doc.models)
    try:
        ranges = [m for m in models if isinstance(m, (DataRange1d, Range1d))]
        auto = [m for m in ranges if isinstance(m, DataRange1d)]
        assert len(auto) >= 5, f"expected the tabs' automatic ranges, found {len(auto)}"
        assert not [m for m in auto if m.syncable], "a DataRange1d would echo every frame's range to the server"
        assert any(m.syncable for m in ranges if isinstance(m, Range1d))
    finally:
        for view in app.views.built():
            runner = getattr(view, "runner", None)
            if runner is not None and runner.running:
                runner.pause()
