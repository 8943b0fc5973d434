"""The teacher's page for one browser session: the dashboard, only with the right key.

``ringlab serve`` serves :func:`teacher_page` at ``/teacher`` with the key it printed;
``panel serve app/main.py app/teacher/page.py`` serves it at ``/page`` with the key of the environment
variable ``RINGLAB_TEACHER_KEY`` (no key set: nobody gets in).  Without the right key the page shows
"Not authorised" and builds nothing else: no dashboard, no periodic callback, no roster read.
"""
from __future__ import annotations


import panel as pn

from ringlab.config import CONFIG
from ringlab.live import roster_store
from ringlab.live.roster import ROSTER
from ringlab.ui.reconnect import Reconnect
from ringlab.server.joining import local_stylesheets
from ringlab.ui.a11y import page_template
from ringlab.teacher.access import GUARD, given_key
from ringlab.teacher.dashboard import DASH_CSS, TeacherDashboard

TITLE = "ringlab: teacher's dashboard"
REFRESH_MS = 1500  # [ms] the dashboard reads the roster this often (a few small strings; nothing if unchanged)


def refused(blocked: bool = False) -> pn.pane.HTML:
    """The whole page for a wrong or missing key (``blocked``: too many wrong keys from this address)."""
    why = ("Too many wrong keys from this computer: try again in a minute." if blocked else
           "This page needs the teacher\'s link printed by <code>ringlab serve</code>.")
    return pn.pane.HTML(f'<div class="dash" id="teacher-refused"><h2>Not authorised</h2><p>{why}</p></div>',
                        stylesheets=[DASH_CSS])


def client_address() -> str:
    """The address of the browser that asked for this page ("local" outside a server session)."""
    doc = pn.state.curdoc
    ctx = getattr(doc, "session_context", None)
    request = getattr(ctx, "request", None)
    return str(getattr(request, "remote_ip", None) or "local")


def teacher_page(key: str | None = None):
    """The page for this session: the dashboard when the address's ``key`` is ``key`` (default: the
    environment's ``RINGLAB_TEACHER_KEY``), else :func:`refused`.  Wrong keys are counted per address
    (:data:`ringlab.teacher.access.GUARD`: logged, and an address over the limit is refused for a while)."""
    local_stylesheets()  # before any component is built (a page built where its websocket landed)
    expected = key if key is not None else CONFIG.teacher_key
    verdict = GUARD.check(given_key(pn.state.session_args), expected, client_address())
    if verdict != "ok":
        return refused(blocked=verdict == "blocked")
    dash = TeacherDashboard()
    if pn.state.curdoc is not None and pn.state.curdoc.session_context is not None:
        roster_store.keep(ROSTER)  # the answers of the class before a restart of the server
        pn.state.curdoc.template = page_template()  # a phone's width; names for Bokeh's checkboxes (ui.a11y)
        pn.state.add_periodic_callback(dash.refresh, period=REFRESH_MS)
    header = pn.pane.HTML(f'<header class="app-header" style="background:#1f4e79;color:#fff;padding:8px 16px">'
                          f'<h1 style="font-size:22px;margin:0">{TITLE}</h1></header>', sizing_mode="stretch_width",
                          margin=0)
    return pn.Column(header, dash, Reconnect(), sizing_mode="stretch_width", margin=0)  # reloads after a restart


def page_factory(key: str):
    """The per-session factory of ``pn.serve`` for a dashboard with ``key`` (a plain function: Panel calls
    functions and methods per session, and would show any other callable, e.g. a ``functools.partial``,
    as an object)."""
    def teacher():
        return teacher_page(key)
    return teacher


if __name__.startswith("bokeh"):  # run by `panel serve app/teacher/page.py`
    pn.extension(sizing_mode="stretch_width", notifications=False)
    teacher_page().servable(title=TITLE)
