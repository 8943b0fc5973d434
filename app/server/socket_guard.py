"""The app's websocket handler: a page that goes away leaves no traceback, a malformed message no server detail.

When a browser tab is closed, reloaded or navigated away while the app streams frames, the server may
write to a websocket whose peer has already gone before it has read the page's close frame (the event
loop was busy: another session's page being built, a chunk being delivered).  The first write meets a
connection reset and Tornado closes the stream at once; from then on (Panel 1.9.4, Bokeh 3.9.2, Tornado
6.5):

1. Panel writes a document message as 3 + 2 x (buffers) websocket frames after checking only once that
   the socket is open: the next frame raises ``WebSocketClosedError`` out of an asyncio task nobody
   awaits ("Task exception was never retrieved"), and the futures of the frames already written fail
   unobserved.  :func:`quiet_closed_sockets` gives the event loop an exception handler (asyncio's public
   ``set_exception_handler``) that drops exactly these two errors of a closed socket and hands every other
   one to the handler before it;
2. Tornado keeps handing Bokeh the page's messages that were already received (acknowledgements of
   frames, layout sizes): Bokeh applies each one and answers it on the closed socket ("Failed sending
   message as connection was closed", one line per message).  :class:`AppWSHandler` drops the messages
   of a page whose socket is closing and sends it nothing;
   (Bokeh's ``send_message`` also warns once for the write that finds the reset: not here);
3. Bokeh's keep-alive ping detaches a connection whose socket is closing from its session; Bokeh's
   ``on_close`` then fails ("Uncaught exception GET /main/ws"). :class:`AppWSHandler` only finishes
   the clean-up for such a connection.

An ERROR reply to a malformed message carries :data:`ERROR_TEXT` only: Bokeh puts the exception's repr
and the server's traceback (file paths, library versions) in it, after logging both.

:class:`AppWSHandler` is a subclass of Panel's websocket handler that overrides public methods of Bokeh's
(``on_message``, ``send_message``, ``on_close``) and calls them.  :func:`route_websockets` registers it for
every application of a Bokeh Tornado application with Tornado's public ``Application.add_handlers``, whose
rules come before the application's own routes; ``ringlab serve`` builds its server itself
(:mod:`ringlab.server.class_server`) and calls it.  ``panel serve`` makes its server inside Bokeh, and
neither Bokeh nor Panel lets a setup script reach its Tornado application or choose the websocket handler
(``extra_patterns``/``--plugins`` routes come after the application's routes): under ``panel serve`` the
pages have Bokeh's handler (an ERROR reply with the server's traceback, log lines when a page leaves
mid-stream, a closed tab's runs freed when Bokeh discards the session, 15-30 s later).

The handler also knows the open websockets of each document (:func:`live_connections`: the live runners
stop computing as soon as the socket is closing) and calls :func:`on_page_left` callbacks when the
last one closes (a closed tab frees its runs at once instead of when Bokeh discards the session 15-30 s
later).
"""
from __future__ import annotations

import asyncio
import logging
import weakref

from panel.io.server import WSHandler as PanelWSHandler
from tornado.iostream import StreamClosedError
from tornado.websocket import WebSocketClosedError

ERROR_TEXT = "the server could not handle this message (the server's log has the details)"
_log = logging.getLogger("bokeh.server.views.ws")
_SOCKETS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # document -> WeakSet of its AppWSHandlers
_PAGE_LEFT: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # document -> callbacks for its page leaving
_QUIET_LOOPS: weakref.WeakSet = weakref.WeakSet()  # event loops given quiet_closed_sockets' handler
_INSTALLED: dict[str, bool] = {}


def session_of(conn):
    """The ``ServerSession`` of a Bokeh ``ServerConnection``, None once it was detached (Bokeh's ``session``
    property asserts it is attached)."""
    try:
        return conn.session
    except AssertionError:
        return None


class AppWSHandler(PanelWSHandler):
    """Panel's websocket handler, quiet about a page that has gone and terse in its ERROR replies."""

    def gone(self) -> bool:
        """True once this websocket is closing or closed, or Bokeh detached its connection."""
        ws = self.ws_connection
        conn = self.connection
        return ws is None or ws.is_closing() or (conn is not None and session_of(conn) is None)

    async def on_message(self, fragment):
        if self.gone():
            return None  # a message of a page that has gone: nobody sees its effect or can read the answer
        return await super().on_message(fragment)

    async def send_message(self, message):
        if self.gone():
            return None  # on_close runs anyway; the session logs one line when its run is freed
        session = session_of(self.connection) if self.connection is not None else None
        if session is not None:  # the first message sent is the ACK, right after the connection is made
            _SOCKETS.setdefault(session.document, weakref.WeakSet()).add(self)
        short_error(message)
        try:  # Bokeh's send_message, minus its warning for a write that finds the page gone
            await message.send(self)
        except WebSocketClosedError:
            pass  # the page went away during this write; on_close runs anyway
        return None

    def on_close(self):
        conn = self.connection
        session = session_of(conn) if conn is not None else None
        if conn is not None and session is None:  # detached by the keep-alive ping already
            _log.info("WebSocket connection closed: code=%s, reason=%r", self.close_code, self.close_reason)
            self.application.client_lost(conn)
            return None
        result = super().on_close()
        if session is not None:
            _page_left(session.document)
        return result


def short_error(message) -> None:
    """An ERROR reply to a page carries :data:`ERROR_TEXT` only (Bokeh's protocol handler has logged the
    exception and its traceback already)."""
    content = getattr(message, "content", None)
    if getattr(message, "msgtype", None) == "ERROR" and isinstance(content, dict):
        content["text"], content["traceback"] = ERROR_TEXT, None


def live_connections(doc) -> int | None:
    """Websockets of ``doc``'s page that are open (None: not a server session, or no :class:`AppWSHandler`
    has served it yet: its page has not connected, or the server uses Bokeh's handler)."""
    if getattr(doc, "session_context", None) is None or doc not in _SOCKETS:
        return None
    return sum(not h.gone() for h in list(_SOCKETS[doc]))


def on_page_left(doc, callback) -> None:
    """Call ``callback()`` on the event loop (``doc`` current) as soon as the last websocket of ``doc``'s
    page closes (only with :class:`AppWSHandler`; Bokeh's session-destroyed callbacks come later anyway)."""
    _PAGE_LEFT.setdefault(doc, []).append(callback)


def _page_left(doc) -> None:
    if live_connections(doc):
        return  # another connection of the session is still open
    for cb in _PAGE_LEFT.pop(doc, []):
        try:
            doc.add_next_tick_callback(cb)
        except Exception:  # the document is being destroyed: its session-end callbacks free the runs
            pass


def quiet_closed_sockets(loop: asyncio.AbstractEventLoop) -> None:
    """Let ``loop`` drop the never-retrieved ``WebSocketClosedError``/``StreamClosedError`` of a page that
    has gone (item 1 above); any other error goes to the handler that was there (or asyncio's default)."""
    if loop in _QUIET_LOOPS:
        return
    previous = loop.get_exception_handler()

    def handler(lp, context):
        if isinstance(context.get("exception"), (WebSocketClosedError, StreamClosedError)):
            return
        if previous is not None:
            previous(lp, context)
        else:
            lp.default_exception_handler(context)

    loop.set_exception_handler(handler)
    _QUIET_LOOPS.add(loop)


def route_websockets(tornado_app) -> list[str]:
    """Make :class:`AppWSHandler` the websocket handler of every application of ``tornado_app`` (a Bokeh
    ``BokehTornado`` not yet serving): a rule ahead of the application's own routes, with the arguments Bokeh
    gives its handler there.  Returns the websocket paths routed (none if this Bokeh's handler is not the
    one :class:`AppWSHandler` extends)."""
    routed = []
    for rule in tornado_app.wildcard_router.rules:
        pattern = getattr(rule.matcher, "regex", None)
        if isinstance(rule.target, type) and issubclass(AppWSHandler, rule.target) and pattern is not None \
                and pattern.pattern.endswith("/ws$"):
            routed.append((pattern.pattern, AppWSHandler, dict(rule.target_kwargs)))
    if routed:
        tornado_app.add_handlers(r".*", routed)
        _INSTALLED["handler"] = True
    return [path for path, _, _ in routed]


def install() -> dict:
    """Install :func:`quiet_closed_sockets` where an event loop runs (idempotent).  Returns what is installed
    (name -> bool): ``handler``, whether a server of this process routes its websockets to
    :class:`AppWSHandler` (:func:`route_websockets`), and ``quiet_loop``."""
    try:
        quiet_closed_sockets(asyncio.get_running_loop())
        _INSTALLED["quiet_loop"] = True
    except RuntimeError:  # no running loop yet (before the server starts): the first session installs it
        pass
    return {"handler": bool(_INSTALLED.get("handler")), "quiet_loop": bool(_INSTALLED.get("quiet_loop"))}
