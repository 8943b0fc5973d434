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
from panel.io.state import state
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


def test_runs_as_a_panel_setup_script():
    was = bool(joining.ORIGINAL)
    joining.uninstall_build_order()
    try:
        runpy.run_path(joining.__file__, run_name="panel_setup_module")
        from bokeh.server.contexts import ApplicationContext
        assert ApplicationContext.create_session_if_needed is joining.create_session_if_needed
    finally:
        joining.uninstall_build_order()
        if was:
            joining.install_build_order()


def _joins(monkeypatch, wrapped: bool) -> list:
    """Three pages connect at once; the first page asks for its document as soon as it is built.  Returns
    the order of the builds (blocking, as Bokeh's) and of that request."""
    order = []

    async def bokeh_create(self, sid, request=None, token=None):
        if sid not in self._sessions:
            order.append(f"build {sid}")
            time.sleep(0.02)  # building a page blocks the event loop
            self._sessions[sid] = sid
        return self._sessions[sid]

    monkeypatch.setitem(joining.ORIGINAL, "create_session_if_needed", bokeh_create)
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: order.append("freeze"))
    create = joining.create_session_if_needed if wrapped else bokeh_create
    ctx = types.SimpleNamespace(_sessions={}, _pending_sessions={})

    async def first_page_asks():
        while "p0" not in ctx._sessions:
            await asyncio.sleep(0)
        order.append("p0 gets its document")

    async def scenario():
        joins = [asyncio.ensure_future(create(ctx, f"p{i}")) for i in range(3)]
        await asyncio.gather(*joins, first_page_asks())
        assert await create(ctx, "p0") == "p0"  # a built page is returned, not built again

    asyncio.run(scenario())
    return order


def test_first_page_gets_its_document_before_the_others_are_built(monkeypatch):
    assert _joins(monkeypatch, wrapped=False) == ["build p0", "build p1", "build p2", "p0 gets its document"]
    # each new page's objects are frozen out of the garbage collector's scans once it is built
    assert _joins(monkeypatch, wrapped=True) == ["build p0", "freeze", "p0 gets its document", "build p1", "freeze",
                                                 "build p2", "freeze"]


def test_installed_with_this_bokeh():
    assert joining.install_build_order()
    from bokeh.server.contexts import ApplicationContext
    assert ApplicationContext.create_session_if_needed is joining.create_session_if_needed


def test_a_process_with_a_page_to_build_leaves_new_connections_to_the_others(monkeypatch):
    """With one accept per wake-up, a process accepts no connection from the moment a new page is queued until the
    last queued page is built; then one per wake-up again.  Without it (one process) nothing changes."""
    seen = []
    listener, clients = _waiting(1)
    acceptor = accepting.OneAtATime(FakeHTTPServer(), [listener])

    async def bokeh_create(self, sid, request=None, token=None):
        seen.append((sid, acceptor.listening))
        self._sessions[sid] = sid
        return sid

    monkeypatch.setitem(joining.ORIGINAL, "create_session_if_needed", bokeh_create)
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: None)

    def join(n, balanced):
        ctx = types.SimpleNamespace(_sessions={}, _pending_sessions={})

        async def scenario():
            if balanced:
                acceptor.start(asyncio.get_running_loop())
            await asyncio.gather(*[joining.create_session_if_needed(ctx, f"p{i}") for i in range(n)])
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
