"""A notebook pane updated after it was drawn keeps Panel's stylesheets from the installed package (no CDN address)."""
import base64

import panel as pn
import pytest
from bokeh.document import Document
from bokeh.models import ImportedStyleSheet
from panel.io.resources import CDN_DIST, DIST_DIR
from pyviz_comms import Comm

from ringlab.server import installed_css


@pytest.fixture
def own_caches(monkeypatch):
    """Panel's stylesheet caches as this test leaves them are dropped afterwards (they are process-wide)."""
    monkeypatch.setattr(pn.state, "_stylesheets", type(pn.state._stylesheets)())
    yield


def updated_html_pane(inline: bool):
    """An HTML pane drawn for a notebook comm (``inline``: Panel's resources written into the page), then changed
    as a view's status line is: the stylesheets Panel sends with the change."""
    with pn.config.set(inline=inline):
        pane = pn.pane.HTML("before")
        doc = Document()
        model = pane.get_root(doc, Comm())
        doc.add_root(model)
        pane.object = "after"
        assert model.text == "after"
        return [s.url for s in model.stylesheets if isinstance(s, ImportedStyleSheet)]


def test_panel_alone_sends_cdn_addresses_with_an_update(own_caches):
    urls = updated_html_pane(inline=True)  # what the page of an offline notebook asked the CDN for (Panel 1.9.4)
    assert {u.split("?")[0] for u in urls if u.startswith(CDN_DIST)} == {
        f"{CDN_DIST}css/loading.css", f"{CDN_DIST}bundled/theme/default.css", f"{CDN_DIST}bundled/theme/native.css"}


def test_installed_stylesheets_replace_them_with_the_installed_files(own_caches):
    assert installed_css.use_installed_stylesheets()
    assert not installed_css.use_installed_stylesheets()  # once
    urls = updated_html_pane(inline=True)
    assert urls and not [u for u in urls if not u.startswith("data:text/css;base64,")]
    texts = {base64.b64decode(u.split(",", 1)[1]) for u in urls}
    assert texts == {(DIST_DIR / name).read_bytes()
                     for name in ("css/loading.css", "bundled/theme/default.css", "bundled/theme/native.css")}
    again = updated_html_pane(inline=True)  # another notebook output: its own stylesheet models, same files
    assert again == urls


def test_cdn_stays_when_resources_are_not_inline(own_caches):
    installed_css.use_installed_stylesheets()
    urls = updated_html_pane(inline=False)  # pn.extension(inline=False) chooses the CDN again
    assert urls and all(u.startswith(CDN_DIST) for u in urls)


def test_addresses_outside_panel_dist_are_not_touched():
    assert installed_css.data_address("https://example.org/x.css") is None
    assert installed_css.data_address(f"{CDN_DIST}css/no-such-file.css") is None
    assert installed_css.data_address(f"{CDN_DIST}panel.min.js") is None  # stylesheets only
    assert installed_css.data_address(f"{CDN_DIST}css/loading.css?v=1").startswith("data:text/css;base64,")
