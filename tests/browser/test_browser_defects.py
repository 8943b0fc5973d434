"""Browser tests of the app's defects that only a real page shows (headless Debian Chromium).

* Enter in "Compare with σ₀" applies the list and the server logs no ``_pending_writes`` traceback;
* the page loads nothing from any host but the app server (offline classroom);
* the server log holds no "Traceback" and no "ERROR" line (the lines of each test, then the whole log).

The tier's shared app server and Chromium (tests/conftest.py).  Run alone with
``.venv/bin/python -m pytest -p no:playwright tests/browser/test_browser_defects.py``.
Recipe: ``shared/guides/panel-live-app.md``; fixtures as in ``tests/browser/test_browser.py``.
"""
from __future__ import annotations

import re
from urllib.parse import urlparse

import pytest

from browser_support import context, pytestmark  # noqa: F401

LOAD_TIMEOUT_MS = 150_000  # the page builds all tabs' models on a loaded 2-core machine


@pytest.fixture
def server(shared_app):
    """(URL, log path) of the shared app server; the lines of its log written during the test must hold no
    traceback or error (the fixture ``shared_app`` checks them)."""
    return shared_app.url, shared_app.log


@pytest.fixture
def browser():
    with context(1280, 720, timeout_ms=20_000) as ctx:
        yield ctx


def open_page(ctx, url: str, width: int, height: int):
    """A new page of the app at the given viewport; collects JS errors and requests to other hosts."""
    page = ctx.new_page()
    page.set_viewport_size({"width": width, "height": height})
    page.js_errors, page.foreign = [], []
    page.on("pageerror", lambda exc: page.js_errors.append(str(exc)))
    host = urlparse(url).netloc

    def on_request(req):
        u = urlparse(req.url)
        if u.scheme in ("http", "https", "ws", "wss") and u.netloc != host:
            page.foreign.append(req.url)

    page.on("request", on_request)
    page.goto(url, wait_until="commit", timeout=LOAD_TIMEOUT_MS)
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_TIMEOUT_MS)
    page.locator(".bk-Canvas").nth(2).wait_for(timeout=LOAD_TIMEOUT_MS)
    return page


@pytest.mark.timeout(400)
def test_compare_enter_and_offline(server, browser):
    url, _ = server
    page = open_page(browser, url, 1280, 720)
    inp = page.locator(".bk-input-group", has_text="Compare").locator("input")
    inp.fill("100, 250, 600")
    inp.press("Enter")
    page.locator("#linear-key", has_text="σ₀ = 250 kg/m²").wait_for(timeout=20_000)
    key = page.locator("#linear-key").inner_text()
    assert "σ₀ = 100 kg/m²" in key and "σ₀ = 600 kg/m²" in key and "σ₀ = 800 kg/m²" not in key
    page.wait_for_timeout(1000)
    assert not page.foreign, f"requests to other hosts than the app server: {page.foreign}"
    assert not page.js_errors, page.js_errors
    page.close()


def test_no_font_links_in_page_html(server):
    """The HTML itself links no external stylesheet or script (a cheap check, no browser)."""
    import urllib.request
    url, _ = server
    html = urllib.request.urlopen(url, timeout=120).read().decode()
    ext = re.findall(r'(?:href|src)="((?:https?:)?//[^"]+)"', html)
    ext = [u for u in ext if urlparse(u if "//" in u else "http://x").hostname not in ("127.0.0.1", None)]
    assert not ext, ext
