"""One connection accepted per wake-up: a class joining at once spread over ``ringlab serve``'s processes.

With ``--num-procs N`` the server's processes share one listening socket.  Tornado's own accept loop
(``HTTPServer.add_sockets``) accepts up to 128 waiting connections each time the socket becomes readable, so
when thirty students open the link at once the first process to wake takes all of them and builds their
pages one after the other while the others stay idle.  :class:`OneAtATime` accepts one connection each
time the socket becomes readable, and none while its process has a new page queued or being built
(:func:`hold`, called by :mod:`ringlab.server.joining`): the next connection waits in the kernel's queue for
a process that is free.  Measured on the 2-core machine with ``ringlab loadtest --students 30
--join-together --num-procs 2`` (29 November 2026): pages after 48.0 s (median) with Tornado's loop, 22.5-30.7
s with one accept per wake-up (three runs).

This accept loop against the one it replaces (Tornado's accept count set to 1 through its private
``_DEFAULT_BACKLOG``), both under ``ringlab serve --num-procs 2``, ``ringlab loadtest --students 30
--join-together``, 7 runs each in pairs, 7 December 2026, load average 1.5-11 from other work: pages ready
(median / last) at best 4.95 / 8.07 s against 4.88 / 7.82 s, and 15-18 of the 32 pages built by each process
in both; the runs of either spread from 5 to 22 s (whichever ran second in a pair was usually slower).

Only public parts: the asyncio loop's ``add_reader``/``remove_reader`` on the listening socket, and each
accepted connection handed to the HTTP server as Tornado's ``TCPServer`` does for plain HTTP (an ``IOStream``
with the server's buffer sizes, then its public ``handle_stream``).  The listen backlog (128) is Tornado's.
"""
from __future__ import annotations

import asyncio
import logging
import socket
import weakref

from tornado.iostream import IOStream

_log = logging.getLogger(__name__)
_ACCEPTORS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # event loop -> its OneAtATime


class OneAtATime:
    """Accept connections on ``sockets`` one per readiness and hand them to ``http_server`` (a Tornado
    ``HTTPServer``, plain HTTP), on the running event loop of the caller of :meth:`start`.

    Parameters
    ----------
    http_server : tornado.httpserver.HTTPServer
        The server that reads the requests (its ``handle_stream``).
    sockets : list of socket.socket
        Listening, non-blocking sockets (``tornado.netutil.bind_sockets``).
    """

    def __init__(self, http_server, sockets):
        self.http_server = http_server
        self.sockets = list(sockets)
        self.loop: asyncio.AbstractEventLoop | None = None
        self.held = 0  # pages queued or being built in this process: while > 0 nothing is accepted
        self.listening = False

    def start(self, loop: asyncio.AbstractEventLoop) -> None:
        """Start accepting on ``loop`` (this process's event loop)."""
        self.loop = loop
        _ACCEPTORS[loop] = self
        self._listen(True)

    def _listen(self, on: bool) -> None:
        if self.loop is None or on == self.listening:
            return
        for sock in self.sockets:
            if on:
                self.loop.add_reader(sock.fileno(), self._ready, sock)
            else:
                self.loop.remove_reader(sock.fileno())
        self.listening = on

    def hold(self, change: int) -> None:
        """Count a page queued (+1) or built (-1); accept nothing while any is."""
        self.held = max(0, self.held + change)
        self._listen(self.held == 0)

    def _ready(self, sock: socket.socket) -> None:
        try:
            connection, address = sock.accept()
        except (BlockingIOError, InterruptedError, ConnectionAbortedError):
            return  # another process took it, or the peer gave up while it waited
        except OSError as exc:  # e.g. too many open files: the connection stays queued for another try
            _log.warning("accept failed: %s", exc)
            return
        try:
            connection.setblocking(False)
            stream = IOStream(connection, max_buffer_size=self.http_server.max_buffer_size,
                              read_chunk_size=self.http_server.read_chunk_size)
            future = self.http_server.handle_stream(stream, address)
            if future is not None:
                asyncio.ensure_future(future)
        except Exception:
            _log.error("error in connection callback", exc_info=True)

    def stop(self) -> None:
        """Stop accepting (the sockets stay open)."""
        self._listen(False)
        self.loop = None


def hold(loop: asyncio.AbstractEventLoop, change: int) -> None:
    """Tell the :class:`OneAtATime` of ``loop``, if any, that a page was queued (+1) or built (-1)."""
    acceptor = _ACCEPTORS.get(loop)
    if acceptor is not None:
        acceptor.hold(change)
