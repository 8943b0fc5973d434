"""Every plot a student can save as a PNG says in itself which line is which: Bokeh's save tool saves the figure's
canvas, so a key in the page beside a plot is missing from the file ("the PNG export has no legend").

A figure showing more than one data series (glyphs reading different sources or columns, or a multi-line) has a
Legend drawn in the figure, and each of its visible line or marker glyphs is an entry of it; every save tool names
its file (Bokeh otherwise asks for a name, offering "bokeh_plot").
"""
from __future__ import annotations

from unittest import mock

import panel as pn
import pytest
from bokeh.document import Document
from bokeh.models import GlyphRenderer, Image, Legend, MultiLine, SaveTool

from ringlab import main
from ringlab.main import TABS

COORDS = ("x", "y", "xs", "ys")


def _series(r: GlyphRenderer):
    """What a glyph draws: its source and the columns of its coordinates (a line and its dots: one series)."""
    g = r.glyph
    cols = tuple(getattr(g, c) for c in COORDS if isinstance(getattr(g, c, None), str))
    return id(r.data_source), cols


@pytest.fixture(scope="module")
def saved_figures():
    """(tab, figure) for every figure with a save tool, in every tab (each built and rendered into a document)."""
    out = []
    with mock.patch.object(type(pn.state), "session_args", new=property(lambda self: {})):
        app = main.create_app()
        try:
            for i in range(len(TABS)):
                doc = Document()
                doc.add_root(pn.panel(app.views[i]).get_root(doc))
                for m in doc.models:
                    tools = getattr(getattr(m, "toolbar", None), "tools", ())
                    if any(isinstance(t, SaveTool) for t in tools):
                        out.append((i, m))
        finally:
            for view in app.views.built():
                runner = getattr(view, "runner", None)
                if runner is not None and getattr(runner, "running", False):
                    runner.pause()
    return out


def test_every_save_tool_names_its_file(saved_figures):
    assert len(saved_figures) >= 25
    for tab, fig in saved_figures:
        for tool in fig.toolbar.tools:
            if isinstance(tool, SaveTool):
                assert (tool.filename or "").startswith("ringlab-"), (tab, fig.title.text, tool.filename)


def test_every_saved_plot_of_several_lines_names_them_in_a_legend_drawn_in_the_plot(saved_figures):
    checked = 0
    for tab, fig in saved_figures:
        drawn = [r for r in fig.renderers if isinstance(r, GlyphRenderer) and r.visible
                 and not isinstance(r.glyph, Image)]
        several = len({_series(r) for r in drawn}) > 1 or any(isinstance(r.glyph, MultiLine) for r in drawn)
        if not several:
            continue
        checked += 1
        where = (tab, fig.title.text)
        legends = [obj for side in ("center", "below", "above", "left", "right") for obj in getattr(fig, side)
                   if isinstance(obj, Legend) and obj.visible]
        assert legends, f"no legend drawn in {where}"
        listed = {id(r) for leg in legends for item in leg.items for r in item.renderers}
        missing = [type(r.glyph).__name__ for r in drawn if id(r) not in listed]
        assert not missing, f"{where}: {missing} not in the legend"
        for leg in legends:
            for item in leg.items:
                label = item.label  # a fixed text (Value) or one entry per value of a source column (Field)
                assert label is not None and (getattr(label, "value", None) or getattr(label, "field", None)), where
    assert checked >= 10  # the tabs' multi-series plots (linear curves, PSDs with markers, Compare, Figure 20, ...)


def test_every_axis_gives_its_unit_or_says_it_is_a_ratio_or_normalised(saved_figures):
    """A saved plot's axes say what their numbers are in: a unit in brackets, a ratio of two quantities, or the
    normalisation of a spectrum ("PSD" alone left a student to guess)."""
    from bokeh.models import Axis

    bad = []
    for tab, fig in saved_figures:
        for ax in fig.select({"type": Axis}):
            label = ax.axis_label or ""
            if label and not ("[" in label or "/" in label or "maximum = 1" in label):
                bad.append((TABS[tab][0], fig.title.text, label))
    assert not bad, bad
