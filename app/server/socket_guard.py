"""A page that goes away while frames stream must leave no traceback in the server log.

When a browser tab is closed, reloaded or navigated away while the app streams frames, the
server may write to a websocket whose peer has already gone before it has read the page's
close frame (the event loop was busy: another session's page being built, a chunk being
delivered).  The first write meets a connection reset and Tornado closes the stream at once;
from then on three library code paths misbehave (Panel 1.9.4, Bokeh 3.9.2, Tornado 6.5; the
same code is on Panel's and Bokeh's main branches):

1. ``panel.io.document.dispatch_tornado`` writes one document message as 3 + 2 x (buffers)
   websocket frames after checking only once that the socket is open: the next frame raises
   ``WebSocketClosedError`` out of ``_dispatch_msgs``, an asyncio task nobody awaits ("Task
   exception was never retrieved" and a traceback), and the futures of the frames already
   written fail unobserved (a second traceback);
2. Tornado keeps handing Bokeh the page's messages that were already received (acknowledgements
   of frames, layout sizes): Bokeh applies each one and answers it on the closed socket ("Failed
   sending message as connection was closed", one line per message; also for an answer whose
   write is the one that finds the connection reset);
3. Bokeh's keep-alive ping (every 37 s) finds the socket closing and detaches the connection from
   its session while those messages are still being handled: each of them then fails with
   ``AssertionError`` ("error handling message" and a traceback), and so does Bokeh's own
   ``on_close`` when the handler finally closes ("Uncaught exception GET /main/ws").

:func:`install` (called by every :class:`ringlab.live.session.SessionRuns`, i.e. once per server process
in practice; idempotent) makes all three quiet at their source: a message is written frame by
frame and stops at the first frame refused, its futures ending quietly; messages of a page whose
socket is closing are dropped instead of applied and answered, and an answer that cannot reach
the page is dropped without a warning; an ERROR answer to a malformed message carries a short text and no
traceback (:func:`short_error`; Bokeh logs the traceback); ``on_close`` of a connection
already detached only finishes the clean-up.  Nothing else changes: an open page gets exactly the
same frames in the same order, and other errors still propagate.  :func:`live_connections` lets
the live runners stop computing as soon as the socket is closing, before Bokeh notices.
"""
from __future__ import annotations

import asyncio
import json
import logging
import weakref

from ringlab.server import fast_defaults, fast_patch
from ringlab.server.fast_patch import patch_doc_message

_INSTALLED: dict[str, bool] = {}
ORIGINALS: dict = {}  # the library functions replaced (for tests)


def socket_open(conn) -> bool:
    """True while a Bokeh ``ServerConnection``'s websocket can still be written to (a socket that is
    not Tornado's, e.g. Panel on Django, counts as open: Bokeh's own count decides for it)."""
    socket = getattr(conn, "_socket", None)
    if not hasattr(socket, "ws_connection"):
        return True
    ws = socket.ws_connection
    return ws is not None and not ws.is_closing()


def live_connections(doc) -> int | None:
    """Connections of ``doc``'s server session whose websocket is open (None: not a server session)."""
    ctx = getattr(doc, "session_context", None)
    session = getattr(ctx, "_session", None)
    conns = getattr(session, "_subscribed_connections", None)
    if conns is None:
        n = getattr(session, "connection_count", None)
        return n if isinstance(n, int) else None
    return sum(socket_open(c) for c in list(conns))


def _guard_panel_dispatch() -> bool:
    import panel.io.document as pdoc
    from tornado.iostream import StreamClosedError
    from tornado.websocket import WebSocketClosedError, WebSocketHandler

    original = getattr(pdoc, "dispatch_tornado", None)
    if original is None:
        return False
    ORIGINALS["dispatch_tornado"] = original

    async def quiet(fut):
        try:
            await fut
        except (WebSocketClosedError, StreamClosedError):
            pass  # the page has gone; its session logs one line when freed

    def dispatch_tornado(conn, events=None, msg=None):
        socket = conn._socket
        if not socket_open(conn):
            return []
        if msg is None:
            if not events:
                return []
            msg = patch_doc_message(conn.protocol, events)  # Bokeh's message, its reference table kept
        frames = [(msg.header_json, False), (msg.metadata_json, False), (msg.content_json, False)]
        for buffer in msg._buffers:
            frames += [(json.dumps(buffer.ref), False), (buffer.to_bytes(), True)]
        futures = []
        for data, binary in frames:
            try:
                fut = WebSocketHandler.write_message(socket, data, binary=binary)
            except WebSocketClosedError:
                break  # the page went away in the middle of this message: the rest cannot be sent
            futures.append(asyncio.ensure_future(quiet(fut)))
        return futures

    dispatch_tornado.__doc__ = original.__doc__
    pdoc.dispatch_tornado = dispatch_tornado
    return True


def _guard_bokeh_handler() -> bool:
    import bokeh.server.views.ws as ws_module
    from bokeh.server.views.ws import WSHandler
    from tornado.websocket import WebSocketClosedError

    on_message, handle, on_close = WSHandler.on_message, WSHandler._handle, WSHandler.on_close
    send_message = WSHandler.send_message
    ORIGINALS.update(on_message=on_message, _handle=handle, on_close=on_close, send_message=send_message)
    log = logging.getLogger("bokeh.server.views.ws")

    def gone(self) -> bool:
        ws = self.ws_connection
        conn = self.connection
        return ws is None or ws.is_closing() or (conn is not None and conn._session is None)

    async def guarded_on_message(self, fragment):
        if gone(self):
            return None  # a message of a page that has gone: nobody sees its effect or can read the answer
        return await on_message(self, fragment)

    async def guarded_handle(self, message):
        if gone(self):
            return None
        return await handle(self, message)

    async def guarded_send_message(self, message):
        # as Bokeh's, minus its warning per message that can no longer reach a page that has gone
        # (its handler's on_close runs anyway; the session logs one line when its run is freed)
        if gone(self):
            return None
        short_error(message)
        try:
            if ws_module._message_test_port is not None:
                ws_module._message_test_port.sent.append(message)
            await message.send(self)
        except WebSocketClosedError:
            pass
        return None

    def guarded_on_close(self):
        conn = self.connection
        if conn is not None and conn._session is None:  # detached by the keep-alive ping already
            log.info("WebSocket connection closed: code=%s, reason=%r", self.close_code, self.close_reason)
            self.application.client_lost(conn)
            return None
        session = getattr(conn, "_session", None)
        result = on_close(self)
        if session is not None:
            _page_left(session.document)
        return result

    guarded_on_message.__doc__, guarded_handle.__doc__ = on_message.__doc__, handle.__doc__
    guarded_on_close.__doc__, guarded_send_message.__doc__ = on_close.__doc__, send_message.__doc__
    WSHandler.on_message, WSHandler._handle, WSHandler.on_close = guarded_on_message, guarded_handle, guarded_on_close
    WSHandler.send_message = guarded_send_message
    return True


ERROR_TEXT = "the server could not handle this message (the server's log has the details)"


def short_error(message) -> None:
    """An ERROR reply to a page carries :data:`ERROR_TEXT` only: Bokeh puts the exception's repr and the
    server's traceback (file paths, library versions) in it; its protocol handler has logged both already."""
    content = getattr(message, "content", None)
    if getattr(message, "msgtype", None) == "ERROR" and isinstance(content, dict):
        content["text"], content["traceback"] = ERROR_TEXT, None


_PAGE_LEFT = weakref.WeakKeyDictionary()  # document -> callbacks for the moment its page leaves


def on_page_left(doc, callback) -> None:
    """Call ``callback()`` on the event loop (``doc`` current) as soon as the last websocket of ``doc``'s
    session closes: a closed tab frees its runs at once, paused ones too (a running one also notices
    at its next chunk), instead of when Bokeh discards the session 15-30 s later."""
    _PAGE_LEFT.setdefault(doc, []).append(callback)


def _page_left(doc) -> None:
    if live_connections(doc):
        return  # another connection of the session is still open
    for cb in _PAGE_LEFT.pop(doc, []):
        try:
            doc.add_next_tick_callback(cb)
        except Exception:  # the document is being destroyed: its session-end callbacks free the runs
            pass


def install() -> dict:
    """Install the guards (and Bokeh's defaults cached per model class, :mod:`ringlab.server.fast_defaults`) once
    per process; returns which are installed (name -> bool)."""
    if not _INSTALLED:
        _INSTALLED["panel_dispatch"] = _guard_panel_dispatch()
        _INSTALLED["scheduled_writes"] = fast_patch.install_scheduled_writes()
        _INSTALLED["fast_apply"] = fast_patch.install_fast_apply()
        _INSTALLED["bokeh_handler"] = _guard_bokeh_handler()
        _INSTALLED["fast_defaults"] = fast_defaults.install()
    return dict(_INSTALLED)
