"""A class that opens its pages at the same moment: spread over the server's processes, built one per turn.

**Over the processes.** With ``--num-procs N``, ``ringlab serve`` accepts one connection per wake-up in each
process (:mod:`ringlab.server.accepting`), so that a class opening the link at once is spread over the
processes instead of the first process to wake taking every waiting connection.  A process with a page to
build still accepted the connections that arrived while it waited between two builds, and took more than its
share (19 and 11 of 30 pages, logged in the server with ``scripts/measure_join_order.py --num-procs 2``):
while it has a new page queued or in the making it now accepts none (:func:`create_session_if_needed` tells
:func:`ringlab.server.accepting.hold`), so the next page goes to the process that is free first.

**One page built per turn of the event loop.**  Bokeh builds a session's page as soon as its connection
asks for one, on the event loop.  When thirty connections arrive together, all thirty builds are queued
before the first page can ask for its document, and the event loop runs them back to back: no page got its
document before the last one was built (sampled every 2 s: the event loop busy for 45 s, then all
documents sent together).  :func:`install_build_order` lets one new session be built at a time, and before
each build lets the event loop answer what is waiting (a built page asking for its document, frames,
clicks), so the first pages arrive while the others are still being built.  A page that is already built
or being built is returned at once, as before.  Measured in the server (``scripts/measure_join_order.py``,
30 class start link pages, one process): the first, median and last page were sent their documents after
32.9, 35.5 and 38.4 s with Bokeh's order and after 2.4, 20.1 and 38.0 s with this one.

**Each page built once, where its websocket lands.**  A browser asks for the page's address (HTTP) and then
opens the page's websocket: two connections, which with ``--num-procs`` N > 1 may reach two different
processes.  Bokeh builds the page for the first; the second process does not have that session and builds it
again (Bokeh issues 5582, 7091).  In Chromium against two processes, 3 of 6 class start link pages were
built twice (29 November 2026), and the copy nobody shows lives until the server gives up on it.
:func:`reuse_page_template` makes the address answer from one empty page made when the server starts
(Panel's ``reuse_sessions``, as ``panel serve --warm --reuse-sessions`` does): the HTML of a page does not
depend on the page's query, and the page itself is built once, by the process its websocket reaches (6 pages,
6 builds).

``ringlab serve`` installs the build order and (with ``--num-procs`` N > 1) the page template before its
processes start; ``panel serve ... --setup <this file>`` runs this file as the server's setup script, which
installs the build order (add ``--warm --reuse-sessions`` there); one accept per wake-up needs ``ringlab serve``,
which makes its own accept loop.
"""
from __future__ import annotations

import asyncio
import weakref

import panel as pn
from bokeh.application import Application
from bokeh.server.contexts import ApplicationContext
from panel.io.resources import LOCAL_DIST
from panel.io.session import generate_session
from panel.io.state import set_curdoc, state

from ringlab.server import accepting, gc_policy
from ringlab.server.library_patch import replace_if_unchanged

# [s] before each page is built, the event loop first answers what is waiting (a few turns of the loop: a built
# page's request for its document has arrived by then); at 0.05 s thirty pages waited 1.5 s in all for nothing
YIELD_S = 0.005
ORIGINAL: dict = {}  # Bokeh's ApplicationContext.create_session_if_needed while install_build_order is installed
# SHA-256 of the source of Bokeh 3.9.2's ApplicationContext.create_session_if_needed (what the wrapper assumes:
# a session id in ``_sessions`` or ``_pending_sessions`` is returned without building)
CREATE_SOURCE_SHA256 = "047e758c152be0f6262e0a7d9fe451dc9e1fd407fe93a63e74f79a7048e1006b"
_BUILD_LOCKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # event loop -> its build lock


async def create_session_if_needed(self, session_id, request=None, token=None):
    """Bokeh's ``ApplicationContext.create_session_if_needed``, one new page at a time per event loop."""
    original = ORIGINAL["create_session_if_needed"]
    if not session_id or session_id in self._sessions or session_id in self._pending_sessions:
        return await original(self, session_id, request, token)
    loop = asyncio.get_running_loop()
    lock = _BUILD_LOCKS.get(loop)
    if lock is None:
        lock = _BUILD_LOCKS.setdefault(loop, asyncio.Lock())
    accepting.hold(loop, +1)  # with one accept per wake-up: no new connection until this page is built
    try:
        async with lock:
            await asyncio.sleep(YIELD_S)  # what waits on the loop (a built page asking for its document) goes first
            session = await original(self, session_id, request, token)
            gc_policy.page_built()  # the new page's objects out of the next pages' garbage collections
            return session
    finally:
        accepting.hold(loop, -1)


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


def install_build_order() -> bool:
    """Put :func:`create_session_if_needed` in place of Bokeh's if Bokeh's is the one it was written for;
    returns True if installed."""
    return replace_if_unchanged(ApplicationContext, "create_session_if_needed", create_session_if_needed,
                                CREATE_SOURCE_SHA256, ORIGINAL)


def uninstall_build_order() -> None:
    """Put Bokeh's method back."""
    if ORIGINAL:
        ApplicationContext.create_session_if_needed = ORIGINAL.pop("create_session_if_needed")


if __name__ != "ringlab.server.joining":  # run as `panel serve --setup` script: the package's module does it, so
    from ringlab.server import joining  # that its state (the replaced method) is the one the server uses

    joining.install_build_order()
