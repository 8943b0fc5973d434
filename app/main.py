"""Assemble and serve the ringlab web app: ``panel serve app/main.py``.

Each tab is a (title, factory) pair in :data:`TABS`; a factory takes no
arguments and returns a fresh viewer for one browser session.  Later tabs
("Hydrodynamics", "N-body", "Saturation") are added by appending to TABS.
"""
from __future__ import annotations

import panel as pn

from app.linear_view import LinearView

TABS = [
    ("Linear theory", LinearView),
]

TITLE = "ringlab: viscous overstability in Saturn's rings"


def create_app() -> pn.template.FastListTemplate:
    """The app for one session: a template whose main area holds one tab per entry of TABS."""
    tabs = pn.Tabs(*[(title, factory()) for title, factory in TABS], dynamic=True, sizing_mode="stretch_width")
    return pn.template.FastListTemplate(
        title=TITLE, main=[tabs], accent="#1f4e79", main_layout=None, theme_toggle=False,
    )


if __name__.startswith("bokeh"):  # run by `panel serve`
    pn.extension(sizing_mode="stretch_width", notifications=False)
    create_app().servable()
