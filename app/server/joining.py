"""A class that opens its pages at the same moment: spread over the server's processes, each page built once.

**Over the processes.** With ``--num-procs N`` the server's processes share one listening socket.  Tornado
(6.x) accepts up to 128 waiting connections each time the socket becomes readable, so when thirty students
open the link at once the first process to wake takes all of them and builds their pages one after the
other, while the other processes stay idle.  :func:`balance_accepts` makes each process accept one
connection per wake-up: a process busy building a page leaves the next connection to an idle one.  Measured
on the 2-core machine with ``ringlab loadtest --students 30 --join-together --num-procs 2`` (29 November
2026): the pages arrived after 48.0 s (median) and 49.4 s (last) with Tornado's default and after 22.5-30.7 s
and 23.6-32.8 s (three runs) with one connection per wake-up.  The listen backlog (128) is unchanged: only
the accept loop reads this value at run time.  Tornado has no public setting for it: this is the one private
name of a library left here (``tornado.netutil._DEFAULT_BACKLOG``, written once before the fork, only with
``--num-procs`` N > 1); the public way, a listening socket per process with ``SO_REUSEPORT``, needs a server
that binds after forking, which Bokeh's ``Server`` does not do.

**One page built at a time, in steps.**  Bokeh builds a session's page as soon as its connection asks for one,
on the event loop; thirty connections arriving together used to be thirty whole pages built back to back.  The
app now builds only a page's frame when its session starts and the rest in steps, one per turn of the event
loop, one page after the other (:mod:`ringlab.server.build_queue`, started by ``ringlab.main.create_app``):
nothing of Bokeh's is replaced for it.

**Each page built once, where its websocket lands.**  A browser asks for the page's address (HTTP) and then
opens the page's websocket: two connections, which with ``--num-procs`` N > 1 may reach two different
processes.  Bokeh builds the page for the first; the second process does not have that session and builds it
again (Bokeh issues 5582, 7091).  In Chromium against two processes, 3 of 6 class start link pages were
built twice (29 November 2026), and the copy nobody shows lives until the server gives up on it.
:func:`reuse_page_template` makes the address answer from one empty page made when the server starts
(Panel's ``reuse_sessions``, as ``panel serve --warm --reuse-sessions`` does): the HTML of a page does not
depend on the page's query, and the page itself is built once, by the process its websocket reaches (6 pages,
6 builds).

``ringlab serve`` calls both before its processes start (with ``--num-procs`` N > 1); ``panel serve ...
--setup <this file>`` runs this file as the server's setup script (add ``--warm --reuse-sessions`` there).
"""
from __future__ import annotations

import panel as pn
import tornado.netutil
from bokeh.application import Application
from panel.io.resources import LOCAL_DIST
from panel.io.session import generate_session
from panel.io.state import set_curdoc, state

ACCEPTS_PER_WAKEUP = 1
_BALANCING: dict = {}  # {"on": True} once balance_accepts() ran in this process (inherited by forked processes)


def balance_accepts() -> bool:
    """Accept at most :data:`ACCEPTS_PER_WAKEUP` connection each time the listening socket becomes readable
    (in this process and the processes it forks); False if this Tornado has no such setting."""
    if not isinstance(getattr(tornado.netutil, "_DEFAULT_BACKLOG", None), int):
        return False
    tornado.netutil._DEFAULT_BACKLOG = ACCEPTS_PER_WAKEUP
    _BALANCING["on"] = True
    return True


def reuse_page_template(path: str = "/main", title: str | None = None, template: str | None = None) -> None:
    """Answer every request for the page address ``path`` with the HTML of one empty page made now (Panel's
    ``reuse_sessions``); the page of each student is then built when its websocket arrives, by the process it
    reaches.  The template has no content (Bokeh refuses to fork after application code ran; ``panel serve
    --warm --reuse-sessions`` does the same on Python < 3.12): the page's roots arrive with its document.
    Call before the server forks its processes."""
    session = generate_session(Application(), initialize=False)
    if title is not None:
        session.document.title = title
    if template is not None:  # the page's HTML template (``doc.template``: the viewport, the access script)
        session.document.template = template
    with set_curdoc(session.document):
        state._session_key_funcs[path] = lambda request: request.path
        state._sessions[path] = session
        session.block_expiration()  # kept for the life of the server, as panel serve --reuse-sessions keeps it
    pn.config.reuse_sessions = True


def local_stylesheets() -> None:
    """Make the current session's Panel stylesheets load from this server, not from Panel's CDN.

    Panel points a component's stylesheets at the document's template variable ``dist_url``, which it sets when
    it renders the page's HTML for that session; where it is missing it uses ``cdn.holoviz.org``.  A page built
    where its websocket lands (:func:`reuse_page_template`, ``--num-procs`` > 1) never had its HTML rendered, so
    every stylesheet of it came from the CDN (3 of 3 class start link pages with two processes: listpanel.css,
    theme/default.css, button.css, ...).  Here the variable is set as Panel sets it, if missing.  Call before
    the session's components are built; outside a server session it does nothing."""
    doc = state.curdoc
    if doc is None or doc.session_context is None or "dist_url" in doc.template_variables:
        return
    doc.template_variables["dist_url"] = f"{state.rel_path}/{LOCAL_DIST}" if state.rel_path else LOCAL_DIST


if __name__ != "ringlab.server.joining":  # run as `panel serve --setup` script: the package's module does it, so
    from ringlab.server import joining  # that its state is the one the server uses

    joining.balance_accepts()
