"""On a phone (390 x 844) the live tabs read in the order a student works: the "Lesson" button (in the first
screen, the page's first control after the skip link), then the run's controls (Start, Pause, ...), then the
settings, then the plots.  The settings used to come after every plot and readout (a phone scrolled past the whole
run to change sigma0).  Measured with the page positions of the elements; screenshots in ``$RINGLAB_SHOTS``
(default test-artifacts/shots)."""
from __future__ import annotations

import pytest

from browser_support import context, new_page

from test_browser_access_layout import LOAD_MS, boxes, shots

pytestmark = [pytest.mark.slow]
PHONE = dict(width=390, height=844, timeout_ms=60_000, is_mobile=True, has_touch=True)
TABS = {"hydro": ("#hydro-status", ".hydro-settings"), "nbody": ("#nbody-status", ".nbody-settings")}
# the page box of the shown button whose text is the argument (through shadow roots)
BUTTON_JS = """(text) => { const walk = (root) => { for (const el of root.querySelectorAll('*')) {
    if (el.tagName === 'BUTTON' && el.textContent.trim() === text) { const r = el.getBoundingClientRect();
      if (r.width > 0) return {top: r.top + scrollY, bottom: r.bottom + scrollY}; }
    if (el.shadowRoot) { const f = walk(el.shadowRoot); if (f) return f; } } return null; };
  return walk(document); }"""
# the Lesson button's place among the body's children, and the app's first root's
ORDER_JS = """() => { const kids = Array.from(document.body.children);
  const jump = document.querySelector('.rl-lesson-jump');
  const app = kids.findIndex(el => el.tagName !== 'SCRIPT' && !el.classList.contains('rl-skip') && el !== jump);
  return [kids.indexOf(jump), app]; }"""


@pytest.mark.timeout(600)
@pytest.mark.parametrize("tab", sorted(TABS))
def test_a_phone_reads_lesson_button_then_run_controls_then_settings_then_plots(shared_app, tab):
    status, settings = TABS[tab]
    with context(**PHONE) as ctx:
        page = new_page(ctx)
        page.goto(f"{shared_app.url}?tab={tab}", timeout=LOAD_MS)
        page.locator(status).wait_for(timeout=LOAD_MS)
        jump = page.locator(".rl-lesson-jump")
        jump.wait_for(state="visible", timeout=10_000)
        page.evaluate("() => scrollTo(0, 0)")
        box = jump.bounding_box()
        assert box["y"] + box["height"] <= 844, box  # in the first screen
        where, app = page.evaluate(ORDER_JS)
        assert 0 <= where < app, (where, app)  # read (and reached by Tab) before the tabs
        assert page.evaluate("() => document.documentElement.scrollWidth") <= 390  # nothing wider than the phone
        start, pause = page.evaluate(BUTTON_JS, "Start"), page.evaluate(BUTTON_JS, "Pause")
        sets = boxes(page, settings)
        plots = boxes(page, ".bk-Canvas")
        assert start and pause and sets and plots, (start, pause, sets, plots)
        assert abs(start["top"] - pause["top"]) < 5  # on one row
        y_start, y_settings, y_plot = start["top"], sets[0]["top"], min(p["top"] for p in plots)
        page.screenshot(path=str(shots() / f"phone-order-{tab}.png"), full_page=True)
        assert y_start < y_settings < y_plot, dict(start=y_start, settings=y_settings, first_plot=y_plot)
        assert sets[0]["bottom"] <= y_plot + 1  # the whole settings column before the first plot
        assert not page.js_errors, page.js_errors[:5]
