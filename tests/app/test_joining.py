"""A class joining at once (ringlab.server.joining): spread over the server's processes, one page built per turn."""
from __future__ import annotations

import inspect
import runpy
import socket
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
    runpy.run_path(joining.__file__, run_name="panel_setup_module")
    assert tornado.netutil._DEFAULT_BACKLOG == 1


def test_nothing_of_bokeh_is_replaced():
    """Pages are built in steps by the app itself (ringlab.server.build_queue): Bokeh's session creation is
    Bokeh's own."""
    from bokeh.server.contexts import ApplicationContext
    assert ApplicationContext.create_session_if_needed.__module__ == "bokeh.server.contexts"
    assert not hasattr(joining, "install_build_order")


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
