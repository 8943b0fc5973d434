"""Panel's own stylesheets from the installed package in a notebook that loads its resources inline.

With ``pn.config.inline`` a notebook output is rendered with Panel's stylesheets written into it, but a pane that
is updated later (an HTML pane whose text changes: a view's status line, its readouts) sends its whole list of
stylesheets again, and Panel builds that list with the addresses of its CDN host (``cdn.holoviz.org``:
``css/loading.css`` and the theme's ``bundled/theme/default.css`` and ``native.css``; Panel 1.9.4; the first one
is made with the relative address of a Panel server and moved to the CDN later).  A notebook
without internet then asks the CDN for them with every such update, and the pane loses those styles.

Panel looks each stylesheet address up in a cache per document (``pn.state._stylesheets``: document -> {address:
``ImportedStyleSheet``}) before it makes a new one.  :func:`use_installed_stylesheets` gives every document a cache
that answers an address on Panel's CDN with the same file of the installed package, as a ``data:`` address: the
page loads it from the notebook's own message, never from the network.  Private API of Panel (<1.10, pinned), as
:mod:`ringlab.server.kernel`.
"""
from __future__ import annotations

import base64
import functools
import weakref

import panel as pn
from bokeh.models import ImportedStyleSheet
from panel.io.resources import CDN_DIST, DIST_DIR, LOCAL_DIST


@functools.lru_cache(maxsize=64)
def data_address(url: str) -> str | None:
    """The ``data:`` address of the installed file that ``url`` (an address on Panel's CDN, or the relative address
    Panel gives it when it serves its files itself, with or without a ``?v=`` query) names; None for any other
    address or a file the package does not have."""
    prefix = next((p for p in (CDN_DIST, LOCAL_DIST) if isinstance(url, str) and url.startswith(p)), None)
    if prefix is None:
        return None
    path = DIST_DIR / url[len(prefix):].split("?")[0]
    if path.suffix != ".css" or not path.is_file():
        return None
    return "data:text/css;base64," + base64.b64encode(path.read_bytes()).decode("ascii")


class InstalledSheets(dict):
    """One document's stylesheet cache (address -> ``ImportedStyleSheet``) in which an address on Panel's CDN maps
    to a stylesheet of the installed file (while ``pn.config.inline`` is on); other addresses as Panel stores them."""

    def _installed(self, url) -> bool:
        if not pn.config.inline or data_address(url) is None:
            return False
        sheet = dict.get(self, url)
        if sheet is None or sheet.url != data_address(url):
            dict.__setitem__(self, url, ImportedStyleSheet(url=data_address(url)))  # one model per document
        return True

    def __contains__(self, url) -> bool:
        return self._installed(url) or dict.__contains__(self, url)

    def __getitem__(self, url):
        self._installed(url)
        return dict.__getitem__(self, url)

    def get(self, url, default=None):
        return self[url] if url in self else default

    def __setitem__(self, url, sheet) -> None:
        if not self._installed(url):  # Panel stores the CDN stylesheet it made: the installed one stays
            dict.__setitem__(self, url, sheet)

    def __bool__(self) -> bool:
        return True  # Panel looks a stylesheet up only in a non-empty cache ("if cache and url in cache")


class InstalledCaches(weakref.WeakKeyDictionary):
    """``pn.state._stylesheets`` (document -> its stylesheet cache) whose every document has an
    :class:`InstalledSheets` from the start (Panel makes a plain dict for a document it has not seen)."""

    def _cache(self, doc) -> InstalledSheets:
        cache = self.data.get(weakref.ref(doc))
        if not isinstance(cache, InstalledSheets):
            cache = InstalledSheets(cache or {})
            weakref.WeakKeyDictionary.__setitem__(self, doc, cache)
        return cache

    def __contains__(self, doc) -> bool:
        try:
            self._cache(doc)
        except TypeError:  # None or another object without weak references
            return False
        return True

    def __getitem__(self, doc):
        try:
            return self._cache(doc)
        except TypeError:
            raise KeyError(doc) from None

    def get(self, doc, default=None):
        return self[doc] if doc in self else default

    def __setitem__(self, doc, cache) -> None:
        own = self._cache(doc)
        if cache is not own:
            for url, sheet in dict(cache).items():
                own[url] = sheet


def use_installed_stylesheets() -> bool:
    """Make Panel's stylesheet caches answer addresses on its CDN with the installed files (see the module);
    returns True if it did now, False if they already do."""
    if isinstance(pn.state._stylesheets, InstalledCaches):
        return False
    caches = InstalledCaches()
    for doc, cache in list(pn.state._stylesheets.items()):
        caches[doc] = cache
    pn.state._stylesheets = caches
    return True
