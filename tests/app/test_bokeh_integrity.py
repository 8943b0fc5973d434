"""Every part of a page passes Bokeh's integrity check without a warning: a served page runs the check on
each document it sends, and each warning is a line in the server's log -- five per class start link page
(Start, Pause, Step, Reset and Restore with a width but no height in Bokeh's "fixed" sizing mode, W-1005)
were 150 lines for a class of 30."""
from __future__ import annotations

from unittest import mock

import panel as pn
from bokeh.core.validation.check import check_integrity
from bokeh.document import Document

from ringlab import main
from ringlab.main import TABS


def test_the_page_and_every_tab_pass_bokehs_integrity_check():
    with mock.patch.object(type(pn.state), "session_args", new=property(lambda self: {})):
        app = main.create_app()
        doc = Document()
        doc.add_root(app.get_root(doc))  # the page: the shown tab and the lessons panel
        models = list(doc.models)
        for i in range(len(TABS)):  # each tab built and rendered (the page renders only the one shown)
            d = Document()
            d.add_root(pn.panel(app.views[i]).get_root(d))
            models += list(d.models)
    try:
        assert len(models) > 500
        issues = check_integrity(models)
        found = [f"{w.code} {w.name}: {w.extra}" for w in issues.warning + issues.error]
        assert not found, found
    finally:
        for view in app.views.built():
            runner = getattr(view, "runner", None)
            if runner is not None and getattr(runner, "running", False):
                runner.pause()
