"""Assemble and serve the ringlab web app: ``panel serve app/main.py``.

Each tab is a (title, factory) pair in :data:`TABS`; a factory returns a fresh
viewer for one browser session.  Factories that declare a ``runs`` parameter (the
live tabs) get the session's :class:`app.session.SessionRuns`, through which the
Saturation tab reaches the session's hydro run; the others are called without
arguments.
"""
from __future__ import annotations

import panel as pn

from app.hydro_view import HydroView
from app.lessons.view import LessonsPanel
from app.linear_view import LinearView
from app.nbody_view import NBodyView
from app.saturation_view import SaturationView
from app.session import SessionRuns

TABS = [
    ("Linear theory", LinearView),
    ("Hydrodynamics", HydroView),
    ("N-body", NBodyView),
    ("Saturation", SaturationView),
]

TITLE = "ringlab: viscous overstability in Saturn's rings"


def _make(factory, runs):
    params = getattr(factory, "param", None)
    view = factory(runs=runs) if params is not None and "runs" in params else factory()
    runs.views = [*runs.views, view]  # lessons hook: presets reach every tab (app.session.SessionRuns.views)
    return view


def create_app() -> pn.template.FastListTemplate:
    """The app for one session: a template whose main area holds one tab per entry of TABS."""
    runs = SessionRuns()
    tabs = pn.Tabs(*[(title, _make(factory, runs)) for title, factory in TABS], dynamic=True,
                   sizing_mode="stretch_width")
    return pn.template.FastListTemplate(
        title=TITLE, main=[tabs], accent="#1f4e79", main_layout=None, theme_toggle=False,
        sidebar=[LessonsPanel(runs=runs, tabs=tabs)], sidebar_width=360,  # lessons + glossary beside every tab
    )


if __name__.startswith("bokeh"):  # run by `panel serve`
    pn.extension(sizing_mode="stretch_width", notifications=False)
    create_app().servable()
