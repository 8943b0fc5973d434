"""Panel's own stylesheets from the Jupyter server in a notebook that loads its resources inline.

With ``pn.config.inline`` a notebook output is rendered with Panel's stylesheets written into it, but a pane that
is updated later (an HTML pane whose text changes: a view's status line, its readouts) sends its whole list of
stylesheets again, and Panel builds that list with the addresses of its CDN host (``cdn.holoviz.org``:
``css/loading.css`` and the theme's ``bundled/theme/default.css`` and ``native.css``; Panel 1.9.4, and its
1.10.0a3 the same: an updated pane's properties go out as Panel makes them, without the inline stylesheets of the
first render).  A notebook without internet then asks the CDN for them with every such update, and the pane loses
those styles.

Panel makes those addresses relative to another place for its files when the document's template variable
``dist_url`` names one (``Document.template_variables``: Bokeh's public dictionary, which Panel's own pages fill
for a Panel server).  Panel's Jupyter server extension, enabled wherever Panel is installed beside JupyterLab or
Jupyter Notebook, serves the installed package's files at ``{base_url}panel_dist/``: :func:`serve_stylesheets`
points a notebook output's document there, so the page loads them from the Jupyter server it already talks to,
never from the network.  The server is the one that started this kernel (its process id is the kernel's
``JPY_PARENT_PID``, its address in its ``jpserver-<pid>.json`` in Jupyter's runtime folder), and it is used only if
it serves Panel's files (one request, once per kernel).  Without such a server (a kernel started by nbclient or an
editor's own notebook front end, a Jupyter server without Panel) the addresses stay Panel's.
"""
from __future__ import annotations

import functools
import json
import os
import urllib.request
from pathlib import Path

import panel as pn

PROBE = "css/loading.css"  # a file of Panel's dist folder every pane's stylesheets name
PROBE_TIMEOUT_S = 2.0  # [s] a Jupyter server answers a static file on this machine in milliseconds


def jupyter_server_info(pid: int | None = None, runtime_dir: str | os.PathLike | None = None) -> dict | None:
    """The ``jpserver-<pid>.json`` of the Jupyter server that started this kernel (``pid``: default the
    ``JPY_PARENT_PID`` that Jupyter gives a kernel it starts) in Jupyter's runtime folder (default:
    ``jupyter_core.paths.jupyter_runtime_dir()``), or None (no such server or file)."""
    if pid is None:
        try:
            pid = int(os.environ.get("JPY_PARENT_PID", ""))
        except ValueError:
            return None
    if runtime_dir is None:
        try:
            from jupyter_core.paths import jupyter_runtime_dir
        except ImportError:
            return None
        runtime_dir = jupyter_runtime_dir()
    try:
        info = json.loads((Path(runtime_dir) / f"jpserver-{pid}.json").read_text())
    except (OSError, ValueError):
        return None
    return info if isinstance(info, dict) and isinstance(info.get("base_url"), str) else None


def dist_url_of(info: dict, timeout_s: float = PROBE_TIMEOUT_S) -> str | None:
    """The address, from the page's origin, of Panel's files on the Jupyter server described by ``info`` (a
    ``jpserver-<pid>.json``: ``base_url``, ``url``), if the server serves them (a request for one, at most
    ``timeout_s`` seconds); else None."""
    base = "/" + info["base_url"].strip("/") + "/" if info["base_url"].strip("/") else "/"
    url = str(info.get("url", ""))
    if not url.startswith(("http://", "https://")):
        return None
    direct = urllib.request.build_opener(urllib.request.ProxyHandler({}))  # the kernel's own server: no proxy
    try:
        with direct.open(url.rstrip("/") + "/panel_dist/" + PROBE, timeout=timeout_s) as reply:
            if reply.status != 200:
                return None
    except (OSError, ValueError):
        return None
    return base + "panel_dist/"


@functools.lru_cache(maxsize=1)
def server_dist_url() -> str | None:
    """:func:`dist_url_of` the Jupyter server that started this kernel (found once per kernel), or None."""
    info = jupyter_server_info()
    return None if info is None else dist_url_of(info)


def serve_stylesheets(doc, dist_url: str | None = None) -> bool:
    """Make the panes of the notebook output ``doc`` name Panel's stylesheets at ``dist_url`` (default:
    :func:`server_dist_url`) when they are updated, while ``pn.config.inline`` is on (``pn.extension(inline=False)``
    chooses the CDN again); returns True if it did.  A document that names a place already keeps it."""
    if doc is None or not pn.config.inline:
        return False
    dist_url = server_dist_url() if dist_url is None else dist_url
    if dist_url is None:
        return False
    doc.template_variables.setdefault("dist_url", dist_url)
    return doc.template_variables["dist_url"] == dist_url
