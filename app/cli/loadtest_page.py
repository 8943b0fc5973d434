"""A simulated page's connection to a Panel server for ``ringlab loadtest``: Bokeh's websocket protocol spoken
over a Tornado websocket with Bokeh's public protocol classes (no browser, no ``bokeh.client`` session).

:class:`PageSession` opens the websocket as a page does (a session id and its token, the page address's query
arguments), waits for the server's ACK, asks for the document (:meth:`PageSession.request`), sends the changes made
to its document (acknowledgements, clicks, slider moves) as PATCH-DOC messages and hands each message it reads
(:meth:`PageSession.read`) to its reader, which applies a patch (:meth:`PageSession.apply`) or only scans it.
"""
from __future__ import annotations

from bokeh.client.websocket import WebSocketClientConnectionWrapper
from bokeh.document.events import DocumentPatchedEvent
from bokeh.protocol import Protocol
from bokeh.protocol.receiver import Receiver
from bokeh.util.strings import format_url_query_arguments
from bokeh.util.token import generate_jwt_token, generate_session_id
from tornado.httpclient import HTTPRequest
from tornado.websocket import websocket_connect

MAX_MESSAGE_SIZE = 20 * 1024 * 1024  # bytes: a message of the server may be this long (Bokeh's client's default)


class PageSession:
    """One page's websocket session with the Bokeh server at ``url`` (``ws://.../main/ws``), driven on the IOLoop
    ``loop`` (its blocking calls run the loop until they are done).

    Parameters
    ----------
    url : str
        The application's websocket address.
    loop : tornado.ioloop.IOLoop
        The loop that reads and writes this session's websocket.
    arguments : dict or None
        The page address's query arguments (``?tab=...``), seen by the application as the request's.
    timeout_s : float
        Seconds the websocket handshake may take (a browser waits minutes for a page; Tornado's default 20 s is
        exceeded by a server building many pages at once).

    Raises RuntimeError if the server refuses the connection or closes it before its ACK.
    """

    def __init__(self, url: str, loop, arguments: dict | None = None, timeout_s: float = 300.0):
        self.loop = loop
        self.id = generate_session_id()
        self.protocol = Protocol()
        self.receiver = Receiver(self.protocol)
        self.document = None
        request = HTTPRequest(format_url_query_arguments(url, arguments), connect_timeout=timeout_s,
                              request_timeout=timeout_s)
        try:
            self.socket = loop.run_sync(lambda: websocket_connect(
                request, subprotocols=["bokeh", generate_jwt_token(self.id)], max_message_size=MAX_MESSAGE_SIZE))
        except Exception as e:
            raise RuntimeError(f"could not open a page's websocket at {url}: {e!r}") from e
        self.conn = WebSocketClientConnectionWrapper(self.socket)
        ack = loop.run_sync(self.read)
        if ack is None or ack.msgtype != "ACK":
            raise RuntimeError(f"the server at {url} did not acknowledge the page's websocket "
                               f"({'closed' if ack is None else ack.msgtype})")

    async def read(self):
        """The server's next message (a ``bokeh.protocol`` message), None once the websocket has closed."""
        while True:
            fragment = await self.socket.read_message()
            if fragment is None:
                return None
            message = await self.receiver.consume(fragment)
            if message is not None:
                return message

    def request(self, msgtype: str):
        """Send a request (``"PULL-DOC-REQ"``) and run the loop until its reply (None: the websocket closed);
        messages that arrive before the reply are not for a page without a document yet, and are dropped."""
        msg = self.protocol.create(msgtype)

        async def ask():
            await msg.send(self.conn)
            while True:
                reply = await self.read()
                if reply is None or reply.header.get("reqid") == msg.header["msgid"]:
                    return reply

        return self.loop.run_sync(ask)

    def attach(self, doc) -> None:
        """Make ``doc`` this page's document: its changes made here go to the server from now on (those applied
        from the server's messages do not go back)."""
        if self.document is not None:
            self.document.remove_on_change(self._changed)
        self.document = doc
        doc.on_change(self._changed)

    def _changed(self, event) -> None:
        if event.setter is self or not isinstance(event, DocumentPatchedEvent):
            return
        self.loop.add_callback(self.protocol.create("PATCH-DOC", [event]).send, self.conn)

    def apply(self, message) -> None:
        """Apply a PATCH-DOC message of the server to this page's document."""
        message.apply_to_document(self.document, self)

    def close(self) -> None:
        """Close the websocket (the close frame goes out when the loop next runs)."""
        self.conn.close(1000, "the page closed")
