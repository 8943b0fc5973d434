"""Cleanup when a browser session ends: its page left (websocket closed) or Bokeh destroyed it."""
from __future__ import annotations

import panel as pn

from ringlab.server import socket_guard


def on_session_end(callback) -> None:
    """Call ``callback`` when this browser session's page leaves (its websocket closes,
    :func:`ringlab.server.socket_guard.on_page_left`) and again when Bokeh destroys the session (no-op outside a
    server session); ``callback`` must be idempotent."""
    doc = pn.state.curdoc
    if doc is not None and doc.session_context is not None:
        socket_guard.on_page_left(doc, callback)
        pn.state.on_session_destroyed(lambda ctx: callback())
