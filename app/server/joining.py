"""A class that opens its pages at the same moment: spread over the server's processes, built one per turn.

**Over the processes.** With ``--num-procs N``, ``ringlab serve`` accepts one connection per wake-up in each
process (:mod:`ringlab.server.accepting`), so that a class opening the link at once is spread over the
processes instead of the first process to wake taking every waiting connection.  A process with a page to
build still accepted the connections that arrived while it waited between two builds, and took more than its
share (19 and 11 of 30 pages, logged in the server with ``scripts/measure_join_order.py --num-procs 2``):
while it has a new page queued or in the making it now accepts none (:class:`BuildOrder` tells
:func:`ringlab.server.accepting.hold`), so the next page goes to the process that is free first.

**One page built per turn of the event loop.** Bokeh builds a session's page as soon as its connection asks for
one, on the event loop. When thirty connections arrive together, all thirty builds are queued before the first page
can ask for its document, and the event loop runs them back to back: no page got its document before the last one
was built (sampled every 2 s: the event loop busy for 45 s, then all documents sent together). :class:`BuildOrder`
lets one new session be built at a time, and before each build lets the event loop answer what is waiting (a built
page asking for its document, frames, clicks), so the first pages arrive while the others are still being built. It
is a handler of the Bokeh application (Bokeh's public ``Handler``; :func:`order_builds` adds it as the first page
is made): Bokeh awaits the handlers' ``on_session_created`` hooks right before it builds a new session's page, and
builds it in the same turn of the event loop once they return, so the hook waits for its turn and the next turn
(after the build) gives the turn on. A page that is already built or being built is returned at once (Bokeh runs
the hooks of new sessions only). Unlike a replaced ``ApplicationContext.create_session_if_needed``, a page waiting
for its turn already has its (empty) document and session context, made by Bokeh before the hooks; nothing reaches
that document before its build (its page has no connection yet). Measured in the server
(``scripts/measure_join_order.py``, 30 class start link pages, one process): the first, median and last page were
sent their documents after 32.9, 35.5 and 38.4 s with Bokeh's order and after 2.4, 20.1 and 38.0 s with pages built
one per turn (then by a replaced ``create_session_if_needed``). The hook builds in the same order (7 December 2026,
alternated with that replacement, loaded 2-core machine): 0.89 / 16.6 / 40.3 s and 0.32 / 6.0 / 13.0 s against 6.2
/ 16.4 / 34.4 s and 0.50 / 6.9 / 13.1 s; ``ringlab loadtest --students 30 --join-together``, three runs each
alternated: pages ready after 11.4, 8.6, 14.0 s (median) against 20.2, 10.6, 15.2 s, every page of every run with
its plots. Since a page's document is sent with a note in its first tab (:mod:`ringlab.ui.lazy_tabs`), Bokeh's own
order sends all thirty documents sooner (5.7-5.9 s against 1.1 / 11.5 / 21.9 s, one pair), but their tabs then come
together: the pages are ready after 21.1 and 14.9 s (median; last 21.5, 16.6 s) against 11.1 and 12.9 s (last 19.8,
20.5 s) with the order (load test, alternated).

**Each page built once, where its websocket lands.**  A browser asks for the page's address (HTTP) and then
opens the page's websocket: two connections, which with ``--num-procs`` N > 1 may reach two different
processes.  Bokeh builds the page for the first; the second process does not have that session and builds it
again (Bokeh issues 5582, 7091).  In Chromium against two processes, 3 of 6 class start link pages were
built twice (29 November 2026), and the copy nobody shows lives until the server gives up on it.
:func:`reuse_page_template` makes the address answer from one empty page made when the server starts
(Panel's ``reuse_sessions``, as ``panel serve --warm --reuse-sessions`` does): the HTML of a page does not
depend on the page's query, and the page itself is built once, by the process its websocket reaches (6 pages,
6 builds).

``ringlab serve`` calls :func:`order_builds` and (with ``--num-procs`` N > 1) the page template before its
processes start; ``panel serve ... --setup <this file>`` runs this file as the server's setup script, which orders
the builds (add ``--warm --reuse-sessions`` there); one accept per wake-up needs ``ringlab serve``, which makes its
own accept loop (:mod:`ringlab.server.accepting`).
"""
from __future__ import annotations

import asyncio
import weakref

import panel as pn
from bokeh.application import Application
from bokeh.application.handlers import Handler
from panel.io.resources import LOCAL_DIST
from panel.io.session import generate_session
from panel.io.state import set_curdoc, state

from ringlab.server import accepting, gc_policy

_ORDERING: dict = {}  # {"on": True} once order_builds() registered its session-created callback
# [s] before each page is built, the event loop first answers what is waiting (a few turns of the loop: a built
# page's request for its document has arrived by then); at 0.05 s thirty pages waited 1.5 s in all for nothing
YIELD_S = 0.005
BUILD_ORDER = {"on": True}  # False: order_builds() adds nothing (Bokeh's order, an A/B: scripts/measure_join_order.py)
_BUILD_LOCKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # event loop -> its build lock


class BuildOrder(Handler):
    """A Bokeh application handler that adds nothing to a page: its ``on_session_created`` hook lets one new page
    of the application be built at a time per event loop, each after a turn in which the loop answered what was
    waiting (:data:`YIELD_S`), and freezes each built page's objects out of the next garbage collections."""

    def modify_document(self, doc) -> None:
        return None  # the page is the other handlers' (the app's script or function)

    async def on_session_created(self, session_context) -> None:
        loop = asyncio.get_running_loop()
        lock = _BUILD_LOCKS.get(loop)
        if lock is None:
            lock = _BUILD_LOCKS.setdefault(loop, asyncio.Lock())
        accepting.hold(loop, +1)  # with one accept per wake-up: none until this page is built
        try:
            await lock.acquire()
        except BaseException:
            accepting.hold(loop, -1)
            raise
        try:
            await asyncio.sleep(YIELD_S)  # what waits on the loop (a built page asking for its document) goes first
        except BaseException:
            _built(loop, lock)
            raise
        # Bokeh builds the page as soon as the hooks return, awaiting nothing: the next turn comes after the build
        loop.call_soon(_built, loop, lock)


def _built(loop, lock) -> None:
    lock.release()
    accepting.hold(loop, -1)
    gc_policy.page_built()  # the new page's objects out of the next pages' garbage collections


def order_builds() -> bool:
    """Have the new pages of this server's Panel applications built one per turn (:class:`BuildOrder`), from the
    first page on: Panel runs its session-created callbacks before Bokeh runs the application's hooks, and this
    one gives the session's application the handler.  Call before the server starts (``ringlab serve``, a ``panel
    serve --setup`` script); idempotent.  False (nothing done) if ``BUILD_ORDER["on"]`` is False."""
    if not BUILD_ORDER["on"]:
        return False
    if not _ORDERING:
        pn.state.on_session_created(lambda session_context: give_build_order(session_context))
        _ORDERING["on"] = True
    return True


def give_build_order(session_context=None) -> bool:
    """Give the Bokeh application of a server session (default: the current document's) a :class:`BuildOrder`
    handler, once; its new pages from the next one on are built one per turn (``ringlab.main`` calls it for each
    page: without :func:`order_builds`, from the second page on).  True if the application has the handler (False
    outside a server session, or with ``BUILD_ORDER["on"]`` False)."""
    if session_context is None:
        session_context = getattr(pn.state.curdoc, "session_context", None)
    try:
        app = session_context.server_context.application_context.application
    except AttributeError:  # not a server session (a notebook, a test, Panel's warm-up or template page)
        return False
    if any(isinstance(h, BuildOrder) for h in app.handlers):
        return True
    if not BUILD_ORDER["on"]:
        return False
    app.add(BuildOrder())
    return True


def reuse_page_template(path: str = "/main", title: str | None = None, template: str | None = None) -> None:
    """Answer every request for the page address ``path`` with the HTML of one empty page made now (Panel's
    ``reuse_sessions``); the page of each student is then built when its websocket arrives, by the process it
    reaches.  The template has no content (Bokeh refuses to fork after application code ran; ``panel serve
    --warm --reuse-sessions`` does the same on Python < 3.12): the page's roots arrive with its document.
    Call before the server forks its processes.

    Panel's public setting alone (``pn.config.reuse_sessions = True``, ``pn.serve(reuse_sessions=...)``) does not
    do this: it keeps the first real page requested at an address as that process's template, for the life of
    the server (a student's page, with its run), and every request that reaches a process before that first page
    is built builds a page of its own there (a class arriving at once: all of them, in the process of the HTTP
    request, which their websockets may not reach: built twice again).  ``pn.serve(warm=True)`` destroys its
    warm-up page; only Panel's command line (``panel serve --warm --reuse-sessions``) keeps an empty one made
    before the fork, in the same two places of Panel's state that this function fills."""
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
    from ringlab.server import joining  # that its state (the balance) is the one the server uses

    joining.order_builds()
