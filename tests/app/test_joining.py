"""A class joining at once (ringlab.server.joining): spread over the server's processes, one page built per turn."""
from __future__ import annotations

import asyncio
import inspect
import runpy
import socket
import time
import types

import panel as pn
import tornado.netutil
from bokeh.application.handlers import FunctionHandler
from bokeh.server.contexts import ApplicationContext
from panel.io.application import Application as PanelApplication
from panel.io.state import state
from tornado.ioloop import IOLoop
from tornado.iostream import IOStream

from ringlab.server import accepting, joining


class FakeHTTPServer:
    """What OneAtATime uses of Tornado's HTTPServer: its buffer sizes and handle_stream."""
    max_buffer_size, read_chunk_size = None, None

    def __init__(self):
        self.streams = []

    def handle_stream(self, stream, address):
        self.streams.append((stream, address))


def _waiting(n: int):
    listener = tornado.netutil.bind_sockets(0, "127.0.0.1")[0]
    return listener, [socket.create_connection(listener.getsockname()) for _ in range(n)]


def test_one_connection_per_wakeup():
    """Three connections wait: one wake-up of the listening socket accepts one, handed to the HTTP server as a
    Tornado IOStream; the others at the next wake-ups."""
    listener, clients = _waiting(3)
    http = FakeHTTPServer()
    acceptor = accepting.OneAtATime(http, [listener])
    loop = asyncio.new_event_loop()
    try:
        acceptor.start(loop)
        assert acceptor.listening
        acceptor._ready(listener)  # one wake-up
        assert len(http.streams) == 1 and isinstance(http.streams[0][0], IOStream)
        assert http.streams[0][1][0] == "127.0.0.1"
        loop.run_until_complete(asyncio.sleep(0.2))  # the loop polls the socket: one per wake-up, all in time
        assert len(http.streams) == 3
        acceptor.stop()
    finally:
        loop.close()
        for s in [listener, *clients] + [st.socket for st, _ in http.streams]:
            s.close()
    # the listen backlog of new sockets is Tornado's own
    assert inspect.signature(tornado.netutil.bind_sockets).parameters["backlog"].default == 128


def _bokehs_own_session_creation() -> bool:
    return ApplicationContext.create_session_if_needed.__module__ == "bokeh.server.contexts"


def test_runs_as_a_panel_setup_script(monkeypatch):
    monkeypatch.setattr(state, "_on_session_created", [])  # this test's server only
    monkeypatch.setattr(joining, "_ORDERING", {})
    runpy.run_path(joining.__file__, run_name="panel_setup_module")
    assert len(state._on_session_created) == 1  # the pages of the server built one per turn
    assert _bokehs_own_session_creation()  # through Bokeh's public Handler hook, nothing of Bokeh's replaced


def test_the_app_leaves_bokehs_session_creation_alone(monkeypatch):
    """The app's set-up (``ringlab.main.configure``, the ``panel serve`` setup script) orders the builds through
    Bokeh's public application-handler hook: Bokeh's ``ApplicationContext.create_session_if_needed`` stays Bokeh's
    (a Bokeh release that changes it cannot break the lab's session creation)."""
    from ringlab import main

    monkeypatch.setattr(state, "_on_session_created", [])
    monkeypatch.setattr(joining, "_ORDERING", {}, raising=False)
    monkeypatch.setattr(main, "warm_engines", lambda: None)  # the compiled kernels: not this test's concern
    main.configure()
    runpy.run_path(joining.__file__, run_name="panel_setup_module")
    assert _bokehs_own_session_creation()


def _app_context(build, ordered: bool) -> ApplicationContext:
    """Bokeh's application context of an app whose page is ``build(doc)`` (blocking, as the lab's), each page
    giving its application the build order as ``ringlab.main`` does (or not)."""
    def page(doc):
        if ordered:
            assert joining.give_build_order(doc.session_context)
        build(doc)
    return ApplicationContext(PanelApplication(FunctionHandler(page)), io_loop=IOLoop.current())


def _joins(monkeypatch, ordered: bool) -> list:
    """The server's first page, then three pages connecting at once, the first of which asks for its document as soon
    as it is built.  Returns the order of the builds and of that request (Bokeh's own create_session_if_needed, in
    a real event loop)."""
    order, built = [], set()
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: order.append("freeze"))

    def build(doc):
        sid = doc.session_context.id
        order.append(f"build {sid}")
        time.sleep(0.02)  # building a page blocks the event loop
        built.add(sid)

    async def scenario():
        ctx = _app_context(build, ordered)
        first = await ctx.create_session_if_needed("p0")  # the first page of the server adds the order
        joins = [asyncio.ensure_future(ctx.create_session_if_needed(f"p{i}")) for i in range(1, 4)]
        await asyncio.gather(*joins, first_page_asks_for("p1", built, order))
        assert await ctx.create_session_if_needed("p0") is first  # a built page is returned, not built again
        assert sum(isinstance(h, joining.BuildOrder) for h in ctx.application.handlers) == int(ordered)

    asyncio.run(scenario())
    return order


async def first_page_asks_for(sid, built, order):
    while sid not in built:
        await asyncio.sleep(0)
    order.append(f"{sid} gets its document")


def test_first_page_gets_its_document_before_the_others_are_built(monkeypatch):
    assert _joins(monkeypatch, ordered=False) == ["build p0", "build p1", "build p2", "build p3",
                                                  "p1 gets its document"]
    # each new page's objects are frozen out of the garbage collector's scans once it is built
    order = _joins(monkeypatch, ordered=True)
    assert order[:2] == ["build p0", "build p1"]  # the first page of the server adds the order as it is built
    assert sorted(order[2:4]) == ["freeze", "p1 gets its document"]  # the turn after p1's build
    assert order[4:] == ["build p2", "freeze", "build p3", "freeze"]


def test_order_builds_outside_a_server_session_does_nothing():
    assert not joining.give_build_order() and not joining.give_build_order(types.SimpleNamespace())


def test_ordered_from_the_first_page_when_set_up_before_the_server(monkeypatch):
    """``order_builds()`` (a setup script, ``ringlab serve``): Panel's session-created callback gives the
    application its build order before the first page is built, so a class arriving at once is ordered from the
    first page on."""
    monkeypatch.setattr(state, "_on_session_created", [])  # this test's server only
    monkeypatch.setattr(joining, "_ORDERING", {})
    monkeypatch.setitem(joining.BUILD_ORDER, "on", False)
    assert not joining.order_builds() and state._on_session_created == []  # off (the A/B's Bokeh order)
    monkeypatch.setitem(joining.BUILD_ORDER, "on", True)
    assert joining.order_builds() and joining.order_builds() and len(state._on_session_created) == 1
    order, built = [], set()
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: order.append("freeze"))

    def build(doc):
        order.append(f"build {doc.session_context.id}")
        time.sleep(0.02)
        built.add(doc.session_context.id)

    async def scenario():
        ctx = _app_context(build, ordered=False)
        joins = [asyncio.ensure_future(ctx.create_session_if_needed(f"p{i}")) for i in range(3)]
        await asyncio.gather(*joins, first_page_asks_for("p0", built, order))
        assert sum(isinstance(h, joining.BuildOrder) for h in ctx.application.handlers) == 1

    asyncio.run(scenario())
    assert order[0] == "build p0" and sorted(order[1:3]) == ["freeze", "p0 gets its document"]
    assert order[3:] == ["build p1", "freeze", "build p2", "freeze"]


def test_a_process_with_a_page_to_build_leaves_new_connections_to_the_others(monkeypatch):
    """With one accept per wake-up, a process accepts no connection from the moment a new page is queued until the
    last queued page is built; then one per wake-up again.  Without its accept loop (one process) nothing changes."""
    seen = []
    listener, clients = _waiting(1)
    acceptor = accepting.OneAtATime(FakeHTTPServer(), [listener])
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: None)

    def join(n, balanced):
        async def scenario():
            ctx = _app_context(lambda doc: seen.append((doc.session_context.id, acceptor.listening)), ordered=True)
            await ctx.create_session_if_needed("first")
            seen.clear()
            if balanced:
                acceptor.start(asyncio.get_running_loop())
            await asyncio.gather(*[ctx.create_session_if_needed(f"p{i}") for i in range(n)])
            await asyncio.sleep(0)  # the turn after the last build
            listening = acceptor.listening
            acceptor.stop()
            return listening
        return asyncio.run(scenario())

    try:
        join(2, balanced=False)
        assert seen == [("p0", False), ("p1", False)]  # no accept loop of ours on this event loop
        seen.clear()
        assert join(3, balanced=True)  # all built: accepting again
        assert seen == [("p0", False), ("p1", False), ("p2", False)] and acceptor.held == 0
    finally:
        for s in [listener, *clients]:
            s.close()


def test_the_page_address_answers_from_one_empty_template():
    """With several server processes, the page's address is answered from one page made at start-up (Panel's
    reuse_sessions), which holds no content and never expires; the students' pages are built at their websocket."""
    before = pn.config.reuse_sessions
    try:
        joining.reuse_page_template("/main-test", "a title")
        session = state._sessions["/main-test"]
        assert pn.config.reuse_sessions is True
        assert session.document.roots == [] and session.document.title == "a title"
        assert state._session_key_funcs["/main-test"](types.SimpleNamespace(path="/main-test")) == "/main-test"
        assert session.expiration_blocked
    finally:
        pn.config.reuse_sessions = before
        state._sessions.pop("/main-test", None)
        state._session_key_funcs.pop("/main-test", None)

