"""A class joining at once is spread over the server's processes (ringlab.server.accept)."""
from __future__ import annotations

import inspect
import runpy
import socket

import pytest
import tornado.netutil
from tornado.ioloop import IOLoop

from ringlab.server import accept


@pytest.fixture
def tornado_default():
    before = tornado.netutil._DEFAULT_BACKLOG
    yield before
    tornado.netutil._DEFAULT_BACKLOG = before


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
    assert accept.balance_accepts()
    assert tornado.netutil._DEFAULT_BACKLOG == accept.ACCEPTS_PER_WAKEUP == 1
    assert _accepted_per_wakeup() == 1
    # the listen backlog of new sockets is Tornado's own
    assert inspect.signature(tornado.netutil.bind_sockets).parameters["backlog"].default == 128


def test_runs_as_a_panel_setup_script(tornado_default):
    runpy.run_path(accept.__file__, run_name="panel_setup_module")
    assert tornado.netutil._DEFAULT_BACKLOG == 1
