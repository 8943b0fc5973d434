"""The server of ``ringlab serve``, built from Bokeh's, Panel's and Tornado's public parts.

``pn.serve`` makes its Bokeh server inside Bokeh's ``Server``, which binds, forks and accepts with Tornado's
defaults and keeps its Tornado application to itself.  Built here as Bokeh documents for an explicit set-up
(``BokehTornado`` + Tornado ``HTTPServer`` + ``BaseServer``), with what ``pn.serve`` adds for the app
(Panel's applications, index page, favicon, component resources, ``/liveness``), two things become possible
without touching either library:

- the app's websocket handler routed ahead of Bokeh's (:func:`ringlab.server.socket_guard.route_websockets`,
  Tornado's ``add_handlers``);
- with N > 1 processes, one connection accepted per wake-up (:class:`ringlab.server.accepting.OneAtATime`):
  the sockets are bound before the fork (Tornado's ``bind_sockets``), the processes forked with Tornado's
  ``fork_processes``, and each accepts on its own event loop.

Not reproduced (``ringlab serve`` never used them): OAuth and basic auth, the admin page, autoreload,
Flask apps, ``--warm``, ``session_history``, SSL, Unix sockets, a URL prefix, and Panel's registry of the
servers ``pn.serve`` started (``panel serve`` does not fill it either).
"""
from __future__ import annotations

import signal
from pathlib import Path

from bokeh.core.validation import silence
from bokeh.core.validation.warnings import EMPTY_LAYOUT
from bokeh.resources import server_url
from bokeh.server.server import BaseServer
from bokeh.server.tornado import BokehTornado
from bokeh.server.util import bind_sockets, create_hosts_allowlist
from bokeh.util.browser import view
from panel.config import config
from panel.io.application import build_applications
from panel.io.liveness import LivenessHandler
from panel.io.resources import DIST_DIR
from panel.io.server import INDEX_HTML, get_static_routes
from tornado import process
from tornado.httpserver import HTTPServer
from tornado.ioloop import IOLoop

from ringlab.server import socket_guard
from ringlab.server.accepting import OneAtATime


def tornado_app(apps: dict, title: dict, address: str | None, port: int, origins: list[str],
                extra_patterns: list) -> BokehTornado:
    """Bokeh's Tornado application for the Panel apps ``apps`` (slug -> function) served on ``address``:``port``,
    as ``pn.serve`` makes it, with the app's websocket handler routed
    (:func:`ringlab.server.socket_guard.route_websockets`)."""
    silence(EMPTY_LAYOUT, True)
    applications = build_applications(apps, title=title)
    patterns = list(extra_patterns) + get_static_routes({})  # ours first: they answer before Panel's
    patterns.append((r"/liveness", LivenessHandler, dict(applications=applications)))
    app = BokehTornado(applications, extra_websocket_origins=create_hosts_allowlist(origins, port),
                       absolute_url=server_url(address, port), prefix="", index=INDEX_HTML,
                       ico_path=str(Path(DIST_DIR) / "images" / "favicon.ico"), extra_patterns=patterns,
                       cookie_path=config.cookie_path, cookie_secret=config.cookie_secret)
    if not socket_guard.route_websockets(app):
        raise RuntimeError("the app's websocket handler found no websocket route of Bokeh's to take over")
    return app


def serve(apps: dict, *, port: int, address: str, origins: list[str], num_procs: int = 1,
          title: dict | None = None, extra_patterns=(), show: bool = False) -> None:
    """Serve the Panel apps ``apps`` (slug -> function returning the page) on ``address``:``port`` in
    ``num_procs`` processes (forked here; with more than one, one accept per wake-up) until the event loop is
    stopped (SIGINT).  Blocks; in the forked processes, returns when their loop stops."""
    sockets, port = bind_sockets(address, port)
    app = tornado_app(apps, title or {}, address, port, origins, list(extra_patterns))
    http_server = HTTPServer(app, xheaders=False)
    if num_procs > 1:
        if not all(ctx.application.safe_to_fork for ctx in app.applications.values()):
            raise RuntimeError("application code has run before the server processes were forked (as Bokeh's "
                               "Server refuses: the processes would share its state)")
        process.fork_processes(num_procs)  # the parent stays in here until every forked process has ended
    loop = IOLoop.current()
    if num_procs > 1:
        OneAtATime(http_server, sockets).start(loop.asyncio_loop)
    else:
        http_server.add_sockets(sockets)
    server = BaseServer(loop, app, http_server)

    def stop(*_):  # Ctrl-C: stop the loop from the loop (as pn.serve does)
        loop.asyncio_loop.call_soon_threadsafe(loop.stop)

    signal.signal(signal.SIGINT, stop)
    server.start()
    if show and process.task_id() in (None, 0):  # one browser tab, not one per process
        view(f"http://{address if address not in ('0.0.0.0', '::') else 'localhost'}:{port}/main")
    loop.start()
