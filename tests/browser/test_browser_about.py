"""The "About / Cite" text is in view when it opens: at 1280 x 720 the button sits at the foot of the lessons panel
(its own scroll area, as tall as the window), and the text opened below the panel's visible bottom, where nothing
showed that anything had opened.  Screenshots in ``$RINGLAB_SHOTS`` (default test-artifacts/shots)."""
from __future__ import annotations

import pytest

from browser_support import context, new_page

from test_browser_access_layout import LOAD_MS, shots

pytestmark = [pytest.mark.slow]
# the window box of the element with the id given, and of the lessons panel (its scroll area), through shadow roots
RECT_JS = """(id) => { const walk = (root, test) => { for (const el of root.querySelectorAll('*')) {
    if (test(el)) return el; if (el.shadowRoot) { const f = walk(el.shadowRoot, test); if (f) return f; } }
    return null; };
  const box = (el) => { if (!el) return null; const r = el.getBoundingClientRect();
    return {top: r.top, bottom: r.bottom, height: r.height}; };
  return {el: box(walk(document, e => e.id === id)),
          side: box(walk(document, e => e.classList && e.classList.contains('side-panel')))}; }"""


@pytest.mark.timeout(300)
def test_the_about_text_opens_in_view(shared_app):
    with context(width=1280, height=720, timeout_ms=60_000) as ctx:
        page = new_page(ctx)
        page.goto(shared_app.url, timeout=LOAD_MS)
        page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)
        button = page.locator(".about-toggle button")
        button.scroll_into_view_if_needed()
        y0 = page.evaluate("() => scrollY")
        button.click()
        page.locator("#about-paper").wait_for(state="visible")
        page.wait_for_timeout(1500)  # the panel's layout and any scrolling settle
        r = page.evaluate(RECT_JS, "about-cite")
        assert r["el"] is not None and 0 <= r["el"]["top"] < 200, r  # the text starts near the top of the window
        for part in ("about-paper", "about-software"):  # (the BibTeX under them is longer than the window's rest)
            r = page.evaluate(RECT_JS, part)
            el, side = r["el"], r["side"]
            assert el is not None and el["height"] > 0, part
            # on the screen, and inside the lessons panel's visible area (its scroll area clips the rest)
            assert 0 <= el["top"] and el["bottom"] <= 720, (part, el)
            assert side["top"] - 1 <= el["top"] and el["bottom"] <= side["bottom"] + 1, (part, el, side)
        assert abs(page.evaluate("() => scrollY") - y0) <= 1  # the lessons panel scrolled, not the tab beside it
        page.screenshot(path=str(shots() / "about-open-1280x720.png"))
        button.click()  # closes again
        page.locator("#about-paper").wait_for(state="hidden")
        assert not page.js_errors, page.js_errors[:5]
