"""The note a page shows when its browser's previous hydro run is no longer on the server, and the
"Set up this step" button it offers (the lessons' current step, :attr:`ringlab.live.session.SessionRuns.setup_step`).

A run that left with its page is kept for a grace period (:mod:`ringlab.live.parking`); after it, or after a
server restart, the page says so instead of opening empty without a word (:mod:`ringlab.lessons.resume`).
The note goes when a run starts.
"""
from __future__ import annotations

import html

import panel as pn

from ringlab.ui.style import CSS


class GoneNote:
    """``note`` (an HTML pane, id ``hydro-gone``) and ``button`` ("Set up this step", class ``hydro-setup-step``),
    hidden until :meth:`show`; hidden again when ``runner`` starts running."""

    def __init__(self, runner, runs):
        self.runs = runs
        self.note = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(2, 10), visible=False)
        self.button = pn.widgets.Button(label="Set up this step", color="primary", width=200,
                                        css_classes=["hydro-setup-step"], visible=False)
        self.button.on_click(self._setup)
        runner.param.watch(lambda e: e.new and self.hide(), "running")

    def show(self, text: str) -> None:
        self.note.object = (f'<div class="msg-warn" id="hydro-gone">{html.escape(text)} Start again here, or '
                            'set up the lesson\'s step:</div>')
        self.note.visible = True
        self.button.visible = self.runs is not None and self.runs.setup_step is not None

    def hide(self) -> None:
        self.note.visible = self.button.visible = False

    def _setup(self, *_) -> None:
        self.hide()
        if self.runs is not None and self.runs.setup_step is not None:
            self.runs.setup_step()
