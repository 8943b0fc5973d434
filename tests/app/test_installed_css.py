"""A notebook pane updated after it was drawn names Panel's stylesheets on the Jupyter server, not on Panel's CDN
(:mod:`ringlab.server.installed_css`), and the views' outputs do so once displayed (:mod:`ringlab.views`)."""
import http.server
import json
import os
import threading

import panel as pn
import pytest
from bokeh.models import ImportedStyleSheet
from bokeh.plotting import figure
from panel.io.resources import CDN_DIST, DIST_DIR
from panel.models.markup import HTML

from ringlab.server import installed_css
from ringlab.ui import tab

PANEL_FILES = {f"{CDN_DIST}css/loading.css", f"{CDN_DIST}bundled/theme/default.css",
               f"{CDN_DIST}bundled/theme/native.css"}


def updated_html_pane(inline: bool, dist_url: str | None = None):
    """An HTML pane displayed as a notebook output (``inline``: Panel's resources written into the page), then
    changed as a view's status line is: the stylesheet addresses Panel sends with the change, and whether
    :func:`installed_css.serve_stylesheets` (with ``dist_url``, after the display) took the output's document."""
    with pn.config.set(inline=inline):
        pn.extension()
        pane = pn.pane.HTML("before")
        plot = figure()  # the output's document, as the views find it: their plots'
        assert pn.Column(pane, pn.pane.Bokeh(plot))._repr_mimebundle_() is not None
        doc = plot.document
        served = installed_css.serve_stylesheets(doc, dist_url) if dist_url else False
        pane.object = "after"
        (model,) = [m for m in doc.select({"type": HTML}) if m.text == "after"]
        return [s.url for s in model.stylesheets if isinstance(s, ImportedStyleSheet)], served


def test_panel_alone_sends_cdn_addresses_with_an_update():
    urls, _ = updated_html_pane(inline=True)  # what the page of an offline notebook asked the CDN for (Panel 1.9.4)
    assert {u.split("?")[0] for u in urls} == PANEL_FILES


def test_an_output_of_a_served_notebook_names_them_on_the_jupyter_server():
    urls, served = updated_html_pane(inline=True, dist_url="/user/ann/panel_dist/")
    assert served and urls and all(u.startswith("/user/ann/panel_dist/") for u in urls), urls
    files = {u.split("?")[0].removeprefix("/user/ann/panel_dist/") for u in urls}
    assert files == {u.removeprefix(CDN_DIST) for u in PANEL_FILES}  # the same files, from the server's Panel
    assert all((DIST_DIR / f).is_file() for f in files)


def test_cdn_stays_when_resources_are_not_inline():
    urls, served = updated_html_pane(inline=False, dist_url="/panel_dist/")  # pn.extension(inline=False): the CDN
    assert not served and urls and all(u.startswith(CDN_DIST) for u in urls)


class PanelFiles(http.server.BaseHTTPRequestHandler):
    """A Jupyter server on a loopback port whose Panel extension serves ``/base/panel_dist/`` (and nothing else)."""

    def do_GET(self):
        ok = self.path == "/base/panel_dist/css/loading.css"
        self.send_response(200 if ok else 404)
        self.end_headers()
        self.wfile.write(b"/* loading */" if ok else b"")

    def log_message(self, *args):
        pass


@pytest.fixture
def jupyter_server(tmp_path):
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), PanelFiles)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    pid = 4242
    info = {"base_url": "/base/", "url": f"http://127.0.0.1:{server.server_port}/base/", "pid": pid}
    (tmp_path / f"jpserver-{pid}.json").write_text(json.dumps(info))
    yield tmp_path, pid, server.server_port
    server.shutdown()
    server.server_close()


def test_the_kernels_jupyter_server_is_found_and_used_if_it_serves_panels_files(jupyter_server, monkeypatch):
    runtime, pid, port = jupyter_server
    info = installed_css.jupyter_server_info(pid, runtime)
    assert info is not None and installed_css.dist_url_of(info) == "/base/panel_dist/"
    without_panel = dict(info, url=f"http://127.0.0.1:{port}/other/")  # a server that answers 404 for Panel's files
    assert installed_css.dist_url_of(without_panel) is None
    assert installed_css.dist_url_of(dict(info, url="")) is None
    assert installed_css.jupyter_server_info(pid + 1, runtime) is None  # another server's kernel
    monkeypatch.setenv("JPY_PARENT_PID", str(pid))
    monkeypatch.setenv("JUPYTER_RUNTIME_DIR", str(runtime))
    assert installed_css.jupyter_server_info() == info
    monkeypatch.delenv("JPY_PARENT_PID")  # a kernel no Jupyter server started (nbclient, an editor)
    assert installed_css.jupyter_server_info() is None
    assert os.environ.get("JPY_PARENT_PID") is None


def test_a_displayed_view_has_its_output_load_them_from_the_jupyter_server(monkeypatch):
    from ringlab.tabs.hydro.view import HydroView
    from ringlab.views import serve_panel_stylesheets

    shown = []
    monkeypatch.setattr(tab, "ON_DISPLAY", [shown.append, serve_panel_stylesheets])
    monkeypatch.setattr(installed_css, "server_dist_url", lambda: "/panel_dist/")
    with pn.config.set(inline=True):
        pn.extension()
        view = HydroView()
        assert view._repr_mimebundle_() is not None
    assert shown == [view]  # each hook once, with the view, after Panel rendered it
    assert view.plots.profile_source.document.template_variables["dist_url"] == "/panel_dist/"
