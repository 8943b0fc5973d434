"""Projector-first layout: at 1024x768, 1280x720, 1366x768 and 1920x1080 (and on a 390 px phone with
mobile emulation) Start and the main plot of the Hydrodynamics, N-body and Compare tabs lie in the first
screen (the phone: within the first two) and no two panels overlap; presentation mode; the viewport tag.
At every size, the plots of the Hydrodynamics and Linear theory tabs are neither cut off at the side nor
squashed nor overlapping and keep their sizes while the page is idle (over 3 s at 1024x768, 1280x720 and on the
phone, 1 s at the other sizes: a layout that keeps resizing changes within a second), and every tab's header is
reachable without scrolling the tab bar.  Two page loads cover the four desktop sizes: each page is loaded at
one size and then resized to another (as a window moved to the projector).

Screenshots go to test-artifacts/layout/ (1280x720, 1024x768, presentation mode, phone).
"""
from __future__ import annotations

import time

import pytest

from browser_support import ARTIFACTS, emulated_device
from ringlab.main import TABS as TABS_ALL

pytestmark = [pytest.mark.slow]

SHOTS = ARTIFACTS / "layout"
LOAD_MS = 180_000  # a loaded 2-core machine builds the page's models slowly
DESKTOP = [(1024, 768), (1280, 720), (1366, 768), (1920, 1080)]
SHOT_SIZES = {(1024, 768), (1280, 720)}
# per tab: its Start button and its main plot(s)
TABS = {"Hydrodynamics": ("hydro", ".hydro-start", [".hydro-spacetime"]),
        "N-body": ("nbody", ".nbody-start", [".nbody-particles"]),
        "Compare": ("compare", ".compare-start", [".compare-a-spacetime", ".compare-b-spacetime"])}
# panels that must never overlap: the page header, the tab bar, every plot canvas shown, the run buttons and
# status, the readouts, the settings column and the lessons panel (none of them contains another)
PANELS_JS = """
(prefix) => {
  const sel = ['#app-header', '.bk-Canvas', `.${prefix}-start`, `.${prefix}-pause`, `.${prefix}-reset`,
               `#${prefix}-status`, `#${prefix}-readouts`, `.${prefix}-settings`, '.side-panel'];
  const out = [];
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (sel.some((s) => el.matches(s))) {
        const r = el.getBoundingClientRect();
        if (r.width > 0 && r.height > 0) out.push([el.className || el.id, r.left, r.top + scrollY, r.width, r.height]);
      }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  return out;
}
"""


@pytest.fixture
def server(shared_app):
    """URL of the tier's shared app server (tests/conftest.py)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    return shared_app.url


def new_context(browser, **kw):
    """A fresh context of the shared Chromium (``kw``: viewport or a device's settings)."""
    ctx = browser.new_context(**kw)
    ctx.set_default_timeout(30_000)
    return ctx


def settle(page, quiet_ms: int = 500, timeout_ms: int = 6000) -> None:
    """Wait until the plots have settled at their sizes: the canvas boxes unchanged over ``quiet_ms`` (read every
    250 ms), at most ``timeout_ms`` (a layout that never settles is caught by :func:`check_plots`)."""
    last, since, t0 = None, time.monotonic(), time.monotonic()
    while (time.monotonic() - t0) * 1000 < timeout_ms:
        now = sorted(tuple(round(v) for v in b) for b in page.evaluate(CANVAS_BOXES_JS))
        if now != last:
            last, since = now, time.monotonic()
        elif now and (time.monotonic() - since) * 1000 >= quiet_ms:
            return
        page.wait_for_timeout(250)


def open_tab(page, url: str, key: str, start: str):
    page.goto(f"{url}?tab={key}", timeout=LOAD_MS)
    page.locator(start).first.wait_for(state="visible", timeout=LOAD_MS)
    page.locator(".bk-Canvas").first.wait_for(timeout=LOAD_MS)
    settle(page)


def walk_tabs(page, url: str | None):
    """Yield (title, key, start) for each tab of TABS shown in turn, at the top of the page: the first opened
    by its link (``?tab=``: one page load) unless ``url`` is None (the page is already loaded: after a resize),
    the others by a click on their header."""
    for i, (tab, (key, start, _)) in enumerate(TABS.items()):
        if i == 0 and url is not None:
            open_tab(page, url, key, start)
        else:
            page.locator(".bk-tab", has_text=tab).first.click()
            page.locator(start).first.wait_for(state="visible", timeout=LOAD_MS)
            page.evaluate("() => window.scrollTo(0, 0)")
            settle(page)
        yield tab, key, start


# every Bokeh plot canvas shown (non-zero size), also inside shadow roots: [x, y, width, height]
CANVAS_BOXES_JS = """
() => {
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


def check_plots(page, name: str, width: int, min_w: float, min_h: float, stable: bool = True) -> list:
    """Every plot shown lies within the page's width, is at least ``min_w`` x ``min_h`` px and overlaps no other
    plot; with ``stable``, no plot changes size over 3 s of an idle page (else over 1 s).  Returns the boxes."""
    sizes = []
    for _ in range(3 if stable else 1):
        sizes.append(sorted(tuple(round(v) for v in b[2:]) for b in page.evaluate(CANVAS_BOXES_JS)))
        page.wait_for_timeout(1000)
    boxes = page.evaluate(CANVAS_BOXES_JS)
    sizes.append(sorted(tuple(round(v) for v in b[2:]) for b in boxes))
    assert boxes, f"{name}: no plot shown"
    for x, _, w, _ in boxes:
        assert x >= -1 and x + w <= width + 1, f"{name}: a plot is cut off at the side ({x:.0f} + {w:.0f} px)"
    assert min(b[2] for b in boxes) >= min_w and min(b[3] for b in boxes) >= min_h, f"{name}: squashed {boxes}"
    bad = overlaps([("plot", *b) for b in boxes])
    assert not bad, f"{name}: overlapping plots {bad[:3]}"
    assert all(sz == sizes[0] for sz in sizes), f"{name}: plot sizes change while idle: {sizes}"
    return boxes


def check_linear_tab_and_tab_bar(page, width: int, stable: bool = True) -> None:
    """The Linear theory tab's plots (side by side, at most two per row, on a screen of 1024 px or more) and every
    tab's header within the page's width."""
    page.locator(".bk-tab", has_text="Linear theory").first.click()
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)
    page.evaluate("() => window.scrollTo(0, 0)")
    settle(page)
    wide = width >= 1024
    check_plots(page, f"linear {width}", width, 380 if wide else 0, 250 if wide else 0, stable)
    for title, _ in TABS_ALL:  # the headers wrap on a phone
        b = page.locator(".bk-tab", has_text=title).first.bounding_box()
        assert b is not None and b["x"] >= 0 and b["x"] + b["width"] <= width + 1, (title, b)


def box(page, sel: str) -> dict:
    b = page.locator(sel).first.bounding_box()
    assert b is not None, f"{sel} not shown"
    return b


def overlaps(panels, tol: float = 2.0) -> list:
    bad = []
    for i, (n1, x1, y1, w1, h1) in enumerate(panels):
        for n2, x2, y2, w2, h2 in panels[i + 1:]:
            if min(x1 + w1, x2 + w2) - max(x1, x2) > tol and min(y1 + h1, y2 + h2) - max(y1, y2) > tol:
                bad.append((n1, n2))
    return bad


def check_first_screen(page, tab: str, screens: int, height: int, shown: float = 1.0) -> dict:
    """Start and the tab's main plots inside the first ``screens`` screens (a plot: at least the fraction
    ``shown`` of it on a desktop, its top on a phone); no overlapping panels; the page not scrolled
    sideways.  Returns the positions."""
    key, start, plots = TABS[tab]
    out = {"start": box(page, start)}
    limit = screens * height
    assert out["start"]["y"] >= 0 and out["start"]["y"] + out["start"]["height"] <= limit, (tab, out)
    for sel in plots:
        b = out[sel] = box(page, sel)
        end = b["y"] + (shown * b["height"] if screens == 1 else 0)
        assert b["y"] >= 0 and end <= limit + 1, f"{tab}: {sel} at y = {b['y']:.0f}..{b['y'] + b['height']:.0f} px, " \
                                                f"first screen(s) end at {limit} px"
    bad = overlaps(page.evaluate(PANELS_JS, key))
    assert not bad, f"{tab}: overlapping panels {bad[:4]}"
    assert page.evaluate("() => document.scrollingElement.scrollWidth <= innerWidth"), f"{tab}: sideways scroll"
    return out


def check_desktop_size(page, url: str | None, width: int, height: int) -> None:
    """The first-screen, plot and lessons-panel checks of every tab at one desktop size (``url``: load the page,
    None: the page was resized to this size)."""
    shot = (width, height) in SHOT_SIZES
    for tab, key, _ in walk_tabs(page, url):
        pos = check_first_screen(page, tab, 1, height)
        print(f"{width}x{height} {tab}: " + ", ".join(f"{k} y={v['y']:.0f}..{v['y'] + v['height']:.0f}"
                                                      for k, v in pos.items()))
        if key == "hydro":  # profiles not squashed: every plot at least 280 px wide and 180 px high
            check_plots(page, f"hydro {width}x{height}", width, 280, 180, shot)
        # the lessons panel stands beside the tabs with its question in view
        q = box(page, "#lesson-question")
        assert q["x"] > pos["start"]["x"] and q["y"] + q["height"] <= height, q
        if shot:
            page.screenshot(path=str(SHOTS / f"{key}-{width}x{height}.png"))
    page.mouse.wheel(0, 1500)  # the lessons panel stays in view while the page scrolls (sticky)
    page.wait_for_timeout(500)
    q = box(page, "#lesson-question")
    assert 0 <= q["y"] and q["y"] + q["height"] <= height, f"question scrolled away: {q}"
    check_linear_tab_and_tab_bar(page, width, shot)
    if shot:
        page.screenshot(path=str(SHOTS / f"linear-{width}x{height}.png"))
    page.evaluate("() => window.scrollTo(0, 0)")


# each page is loaded at one projector size and then resized to a second one (a lecturer who moves the window
# to the projector): every desktop size is checked, with two page loads instead of four
LOAD_THEN_RESIZE = [(DESKTOP[0], DESKTOP[2]), (DESKTOP[1], DESKTOP[3])]


@pytest.mark.timeout(900)
@pytest.mark.parametrize("loaded, resized", LOAD_THEN_RESIZE, ids=lambda wh: f"{wh[0]}x{wh[1]}")
def test_run_controls_and_main_plots_in_the_first_screen(server, browser, loaded, resized):
    ctx = new_context(browser, viewport={"width": loaded[0], "height": loaded[1]})
    try:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        check_desktop_size(page, server, *loaded)
        page.set_viewport_size({"width": resized[0], "height": resized[1]})
        page.locator(".bk-tab", has_text="Linear theory").first.wait_for(state="visible")
        settle(page)
        check_desktop_size(page, None, *resized)
        assert not errors, errors
    finally:
        ctx.close()


@pytest.mark.timeout(900)
def test_phone_with_mobile_emulation_gets_one_column(server, browser):
    device = emulated_device("iPhone 13")
    ctx = new_context(browser, **device)
    height = device["viewport"]["height"]
    try:
        page = ctx.new_page()
        for tab, key, _ in walk_tabs(page, server):
            # the viewport tag: the page is laid out 390 CSS px wide, not as a shrunk 980 px desktop page
            assert page.evaluate("() => innerWidth") == 390
            # three screens: on a phone the live tabs read Start, their settings, then the plots (the settings
            # come before the plots they change: tests/browser/test_browser_phone_order.py); two before that
            pos = check_first_screen(page, tab, 3, height)
            print(f"phone {tab}: " + ", ".join(f"{k} y={v['y']:.0f}" for k, v in pos.items()))
            page.screenshot(path=str(SHOTS / f"{key}-phone.png"))
            if key == "hydro":
                check_plots(page, "hydro phone", 390, 280, 180)
        check_linear_tab_and_tab_bar(page, 390)
        page.screenshot(path=str(SHOTS / "linear-phone.png"))
    finally:
        ctx.close()


FONT_JS = """(id) => {
  const find = (root) => { for (const el of root.querySelectorAll('*')) {
      if (el.id === id) return el; if (el.shadowRoot) { const f = find(el.shadowRoot); if (f) return f; } }
    return null; };
  return parseFloat(getComputedStyle(find(document)).fontSize);
}"""


@pytest.mark.timeout(600)
def test_presentation_mode_larger_text_no_side_panel(server, browser):
    ctx = new_context(browser, viewport={"width": 1280, "height": 720})
    try:
        page = ctx.new_page()
        open_tab(page, server, "hydro", ".hydro-start")
        normal = page.evaluate(FONT_JS, "hydro-status")
        assert page.locator(".side-panel").is_visible()
        page.goto(f"{server}?tab=hydro&present=1", timeout=LOAD_MS)
        page.locator(".hydro-start").first.wait_for(state="visible", timeout=LOAD_MS)
        page.locator(".bk-Canvas").first.wait_for(timeout=LOAD_MS)
        settle(page)
        big = page.evaluate(FONT_JS, "hydro-status")
        assert big >= 1.25 * normal, (normal, big)
        assert not page.locator(".side-panel").is_visible()
        page.screenshot(path=str(SHOTS / "hydro-presentation-1280x720.png"))
        # the larger text moves the plot down a little: its top in the first screen, 95 % of it shown
        pos = check_first_screen(page, "Hydrodynamics", 1, 720, shown=0.95)
        print("presentation 1280x720: " + ", ".join(f"{k} y={v['y']:.0f}..{v['y'] + v['height']:.0f}"
                                                   for k, v in pos.items()))
        st = pos[".hydro-spacetime"]  # the run reaches the right edge: no lessons panel beside it
        assert st["x"] + st["width"] > 1150, st
        page.locator(".present-toggle button").click()  # the toggle turns it off again
        page.locator(".side-panel").wait_for(state="visible", timeout=30_000)
        page.wait_for_timeout(1000)
        assert page.evaluate(FONT_JS, "hydro-status") == pytest.approx(normal)
    finally:
        ctx.close()
