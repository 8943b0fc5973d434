"""The HTTP routes ``ringlab serve`` adds to Panel's: the documentation site at ``/docs`` and Panel's
component resources at ``/components``, each a subclass of Panel's own handler registered through
``pn.serve(extra_patterns=...)`` (routes given there come before Panel's own, so they answer first).

* ``/docs/<path>``: as Panel's static handler, but a path Tornado cannot look up on disk (a NUL byte, an
  over-long name) is "404 Not Found" instead of a "500 Internal Server Error" with a traceback in the log.
* ``/docs`` (no slash): redirected to ``/docs/`` (the site's index; relative links resolve below it), and that
  to ``/docs/tutorials/nb/`` when only the tutorial pages are built (``make tutorials-html``), looked at per
  request: ``make app`` builds the site in the background while the lab already runs.
* ``/components/<module>/<class>/<attribute>/<path>``: Panel serves a file a component lists among its
  resources, and imports ``<module>`` to find the component: any installed module, named by the address.
  Here only a module already imported by the server, of the packages :data:`COMPONENT_PACKAGES`, is looked
  at; any other address is 404 and nothing is imported.
"""
from __future__ import annotations

import sys

from panel.io.resources import COMPONENT_PATH
from panel.io.server import AuthenticatedStaticFileHandler, ComponentResourceHandler
from tornado.web import HTTPError, RedirectHandler

COMPONENT_PACKAGES = ("ringlab", "panel", "bokeh")  # the app's own components and the libraries it draws with
MAX_PATH = 1024  # characters of a path looked up at all


def bad_path(path: str) -> bool:
    """True for a path no file of ours has: control characters (NUL included) or more than MAX_PATH characters."""
    return len(path) > MAX_PATH or any(ord(c) < 32 or ord(c) == 127 for c in path)


class DocsHandler(AuthenticatedStaticFileHandler):
    """Panel's static-file handler, with 404 for paths that cannot name a file (see module docstring), and the
    site's first page looked up at each request (a site built while the server runs is served at once)."""

    def initialize(self, path: str, default_filename: str | None = None, start=None) -> None:
        super().initialize(path, default_filename)
        self.start = start

    async def get(self, path: str, include_body: bool = True) -> None:
        first = self.start(self.root) if (self.start is not None and path == "") else ""
        if first:  # a site of the tutorial pages only: its index is below
            self.redirect(f"{self.request.path.rstrip('/')}/{first}", permanent=False)
            return
        await super().get(path, include_body)

    def parse_url_path(self, url_path: str) -> str:
        if bad_path(url_path):
            raise HTTPError(404)
        return super().parse_url_path(url_path)

    def validate_absolute_path(self, root: str, absolute_path: str) -> str | None:
        try:
            return super().validate_absolute_path(root, absolute_path)
        except (ValueError, OSError):  # e.g. "embedded null byte", "File name too long"
            raise HTTPError(404) from None


def component_module_allowed(module: str) -> bool:
    """True when ``module`` is already imported and belongs to one of :data:`COMPONENT_PACKAGES`."""
    return module in sys.modules and module.split(".")[0] in COMPONENT_PACKAGES


class OwnComponentsHandler(ComponentResourceHandler):
    """Panel's component resource handler for the app's own (already imported) modules only."""

    def parse_url_path(self, path: str) -> str:
        module = path.split("/", 1)[0]
        if bad_path(path) or not component_module_allowed(module):
            raise HTTPError(404)
        return super().parse_url_path(path)


def patterns(static_dirs: dict, start=None) -> list:
    """``extra_patterns`` for ``pn.serve``: :class:`DocsHandler` for every ``{route: folder}`` of ``static_dirs``
    (serve these instead of passing ``static_dirs``; the folder may appear later, while the server runs), the
    bare ``/route`` redirected to ``/route/``, and that to ``/route/<start(folder)>`` when ``start(folder)`` is
    not empty at the time of the request (a site whose first page is not its index), and
    :class:`OwnComponentsHandler` at ``/components``."""
    out = []
    for route, folder in static_dirs.items():
        route = route.strip("/")
        out.append((rf"/{route}", RedirectHandler, {"url": f"/{route}/", "permanent": False}))
        out.append((rf"/{route}/(.*)", DocsHandler, {"path": folder, "default_filename": "index.html", "start": start}))
    out.append((rf"/{COMPONENT_PATH}(.*)", OwnComponentsHandler, {}))
    return out
