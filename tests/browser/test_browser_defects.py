"""Browser tests of the app's defects that only a real page shows (headless Debian Chromium).

* Enter in "Compare with σ₀" applies the list and the server logs no ``_pending_writes`` traceback;
* the page loads nothing from any host but the app server (offline classroom);
* at 1024x768, 1280x720 and 390x844 there is no horizontal scroll, no two plots overlap and nothing
  keeps resizing (over ~3 s); screenshots go to ``test-artifacts/shots/`` (and ``$RINGLAB_SHOTS`` if set);
* the server log of the whole module holds no "Traceback" and no "ERROR" line.

One server for the module (start-up is slow on a shared machine).  Run alone with
``.venv/bin/python -m pytest -p no:playwright tests/browser/test_browser_defects.py``.
Recipe: ``shared/guides/panel-live-app.md``; fixtures as in ``tests/browser/test_browser.py``.
"""
from __future__ import annotations

import os
import re
from pathlib import Path
from urllib.parse import urlparse

import pytest

from browser_support import ARTIFACTS, chromium, pytestmark, served  # noqa: F401

SHOTS = Path(os.environ.get("RINGLAB_SHOTS", ARTIFACTS / "shots"))
SIZES = [(1024, 768), (1280, 720), (390, 844)]
LOAD_TIMEOUT_MS = 150_000  # the page builds all tabs' models on a loaded 2-core machine

@pytest.fixture(scope="module")
def server():
    """(URL, log path) of one app server for the module; the log is checked for tracebacks at the end."""
    with served("panel-serve-defects.log", check_log=True) as app:
        yield app.url, app.log


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    with chromium(tmp_path_factory.mktemp("profile"), 1280, 720, timeout_ms=20_000) as ctx:
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


def shot(page, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=True)


CANVAS_BOXES_JS = """
() => {
  // every Bokeh plot canvas, also inside shadow roots; only those shown (non-zero size)
  const out = [];
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (el.classList && el.classList.contains('bk-Canvas')) {
        const r = el.getBoundingClientRect();
        if (r.width > 0 && r.height > 0) out.push([r.left + scrollX, r.top + scrollY, r.width, r.height]);
      }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  return out;
}
"""


def overlaps(boxes, tol: float = 2.0):
    bad = []
    for i, (x1, y1, w1, h1) in enumerate(boxes):
        for x2, y2, w2, h2 in boxes[i + 1:]:
            if min(x1 + w1, x2 + w2) - max(x1, x2) > tol and min(y1 + h1, y2 + h2) - max(y1, y2) > tol:
                bad.append(((x1, y1, w1, h1), (x2, y2, w2, h2)))
    return bad


def check_layout(page, name: str, width: int) -> list:
    """Assert: no horizontal scroll, no overlapping plots, sizes stable over ~3 s (a layout that keeps resizing
    changes within a second). Returns the boxes."""
    page.wait_for_timeout(1500)
    shot(page, name)
    sizes = []
    for _ in range(4):
        sizes.append(sorted(tuple(round(v) for v in b[2:]) for b in page.evaluate(CANVAS_BOXES_JS)))
        page.wait_for_timeout(1000)
    scroll_w = page.evaluate("() => document.scrollingElement.scrollWidth")
    inner_w = page.evaluate("() => innerWidth")
    assert scroll_w <= inner_w, f"{name}: horizontal scroll ({scroll_w} px > {inner_w} px)"
    boxes = page.evaluate(CANVAS_BOXES_JS)
    assert boxes, f"{name}: no plot shown"
    assert not overlaps(boxes), f"{name}: overlapping plots {overlaps(boxes)[:3]}"
    for x, _, w, _ in boxes:
        assert x >= -1 and x + w <= width + 1, f"{name}: a plot is cut off at the side ({x:.0f} + {w:.0f} px)"
    assert all(s == sizes[0] for s in sizes), f"{name}: plot sizes change while idle: {sizes}"
    return boxes


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


@pytest.mark.timeout(600)
@pytest.mark.parametrize("width, height", SIZES)
def test_layout_at_projector_and_phone_sizes(server, browser, width, height):
    url, _ = server
    page = open_page(browser, url, width, height)
    boxes = check_layout(page, f"linear-{width}x{height}", width)
    from ringlab.main import TABS
    for title, _ in TABS:  # every tab reachable without scrolling the tab bar (the headers wrap on a phone)
        box = page.locator(".bk-tab", has_text=title).first.bounding_box()
        assert box is not None and box["x"] >= 0 and box["x"] + box["width"] <= width + 1, (title, box)
    if width >= 1024:  # the three linear plots side by side at most two per row, each readable
        assert min(b[2] for b in boxes) >= 380 and min(b[3] for b in boxes) >= 250, boxes
    page.locator(".bk-tab", has_text="Hydrodynamics").click()
    page.locator("#hydro-orbits").wait_for(timeout=LOAD_TIMEOUT_MS)
    page.locator(".bk-Canvas").nth(6).wait_for(timeout=LOAD_TIMEOUT_MS)
    boxes = check_layout(page, f"hydro-{width}x{height}", width)
    # profiles not squashed: every plot at least 280 px wide and 180 px high
    assert min(b[2] for b in boxes) >= min(280, width - 40) and min(b[3] for b in boxes) >= 180, boxes
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
