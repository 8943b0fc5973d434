"""A class joining at once (ringlab.server.joining): spread over the server's processes, one page built per turn."""
from __future__ import annotations

import asyncio
import inspect
import runpy
import socket
import time
import types

import panel as pn
import pytest
import tornado.netutil
from panel.io.state import state
from tornado.ioloop import IOLoop

from ringlab.server import joining


@pytest.fixture
def tornado_default():
    before, balancing = tornado.netutil._DEFAULT_BACKLOG, dict(joining._BALANCING)
    yield before
    tornado.netutil._DEFAULT_BACKLOG = before
    joining._BALANCING.clear()
    joining._BALANCING.update(balancing)


def _accepted_per_wakeup() -> int:
    """Connections Tornado's accept handler takes in one wake-up with three waiting."""
    listener = tornado.netutil.bind_sockets(0, "127.0.0.1")[0]
    clients = [socket.create_connection(listener.getsockname()) for _ in range(3)]
    accepted = []

    async def one_wakeup():  # nothing awaited: the loop never polls the socket itself
        remove = tornado.netutil.add_accept_handler(listener, lambda conn, addr: accepted.append(conn))
        handler = IOLoop.current().handlers[listener.fileno()][1]  # the accept handler Tornado registered
        handler(listener, IOLoop.READ)
        remove()

    loop = IOLoop(make_current=False)
    try:
        loop.run_sync(one_wakeup)
    finally:
        loop.close()
        for c in clients + [listener] + accepted:
            c.close()
    return len(accepted)


def test_one_connection_per_wakeup(tornado_default):
    assert tornado_default == 128 and _accepted_per_wakeup() == 3
    assert joining.balance_accepts()
    assert tornado.netutil._DEFAULT_BACKLOG == joining.ACCEPTS_PER_WAKEUP == 1
    assert _accepted_per_wakeup() == 1
    # the listen backlog of new sockets is Tornado's own
    assert inspect.signature(tornado.netutil.bind_sockets).parameters["backlog"].default == 128


def test_runs_as_a_panel_setup_script(tornado_default):
    was = bool(joining.ORIGINAL)
    joining.uninstall_build_order()
    try:
        runpy.run_path(joining.__file__, run_name="panel_setup_module")
        assert tornado.netutil._DEFAULT_BACKLOG == 1
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


def test_a_process_with_a_page_to_build_leaves_new_connections_to_the_others(monkeypatch, tornado_default):
    """With balanced accepts, a process accepts no connection from the moment a new page is queued until the
    last queued page is built; then one per wake-up again.  Without balancing (one process) nothing changes."""
    seen = []

    async def bokeh_create(self, sid, request=None, token=None):
        seen.append((sid, tornado.netutil._DEFAULT_BACKLOG))
        self._sessions[sid] = sid
        return sid

    monkeypatch.setitem(joining.ORIGINAL, "create_session_if_needed", bokeh_create)
    monkeypatch.setattr(joining.gc_policy, "page_built", lambda: None)

    def join(n):
        ctx = types.SimpleNamespace(_sessions={}, _pending_sessions={})

        async def scenario():
            await asyncio.gather(*[joining.create_session_if_needed(ctx, f"p{i}") for i in range(n)])
        asyncio.run(scenario())

    join(2)
    assert seen == [("p0", 128), ("p1", 128)] and tornado.netutil._DEFAULT_BACKLOG == 128
    seen.clear()
    assert joining.balance_accepts()
    join(3)
    assert seen == [("p0", 0), ("p1", 0), ("p2", 0)]
    assert tornado.netutil._DEFAULT_BACKLOG == joining.ACCEPTS_PER_WAKEUP  # all built: accepting again
    tornado.netutil._DEFAULT_BACKLOG = 0
    assert _accepted_per_wakeup() == 0  # Tornado's accept loop honours it at run time


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
