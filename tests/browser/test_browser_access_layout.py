"""Access by layout: on a phone a "Lesson" button at the foot of the window brings the step's question into view
(the lessons panel starts screens below the run) and leads back; the keyboard reaches Start and the first setting
of every live tab before any plot toolbar; from 1024 to 1366 px the Linear theory tab's sigma0 slider stands
beside its curves (level with the growth-rate plot), and stays in view while the page scrolls past them.
Screenshots in ``$RINGLAB_SHOTS`` (default test-artifacts/shots)."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from browser_support import ARTIFACTS, context, new_page

pytestmark = [pytest.mark.slow]
LOAD_MS = 180_000
# the box (page coordinates) of every element matching a selector, through shadow roots
BOXES_JS = """(sel) => { const out = [];
  const walk = (root) => { for (const el of root.querySelectorAll('*')) {
    if (el.matches(sel)) { const r = el.getBoundingClientRect();
      if (r.width > 0 && r.height > 0) out.push({left: r.left, right: r.right, top: r.top + scrollY,
                                                 bottom: r.bottom + scrollY}); }
    if (el.shadowRoot) walk(el.shadowRoot); } };
  walk(document); return out; }"""
# the focused element (through shadow roots): its class, text, and whether it is a plot's (a toolbar button or
# the canvas's event layer), a settings column's or a Start button's
FOCUS_JS = """(where) => { let el = document.activeElement;
  while (el && el.shadowRoot && el.shadowRoot.activeElement) el = el.shadowRoot.activeElement;
  if (!el) return null;
  const inside = (sel) => { for (let e = el; e; e = e.parentElement || (e.getRootNode() && e.getRootNode().host)) {
    if (e.matches && e.matches(sel)) return true; } return false; };
  return {cls: String(el.className || el.tagName), text: (el.textContent || '').trim().slice(0, 40),
          plot: inside('.bk-toolbar, .bk-Toolbar') || /bk-(OnOff|Click)Button|bk-tool-overflow|bk-events/.test(String(el.className)),
          setting: inside(where.settings), start: inside(where.start)}; }"""


def shots() -> Path:
    out = Path(os.environ.get("RINGLAB_SHOTS", ARTIFACTS / "shots"))
    out.mkdir(parents=True, exist_ok=True)
    return out


def boxes(page, sel: str) -> list:
    return page.evaluate(BOXES_JS, sel)


@pytest.mark.timeout(600)
def test_a_phone_reaches_the_lessons_question_with_the_lesson_button(shared_app):
    with context(width=390, height=844, timeout_ms=60_000, is_mobile=True, has_touch=True) as ctx:
        page = new_page(ctx)
        page.goto(shared_app.url, timeout=LOAD_MS)
        page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)
        page.locator(".lesson-next button").first.click()  # step 2: a question to answer
        page.locator("#lesson-step-title", has_text="Step 2.").wait_for()
        page.evaluate("() => scrollTo(0, 0)")
        jump = page.locator(".rl-lesson-jump")
        jump.wait_for(state="visible", timeout=10_000)
        question = boxes(page, "#lesson-question")[0]
        assert question["top"] > 844, question  # the lesson starts screens below the run
        box = jump.bounding_box()
        assert box["y"] + box["height"] <= 844 and box["height"] >= 44, box  # in the window, a finger's size
        assert jump.inner_text().startswith("Lesson")
        page.screenshot(path=str(shots() / "phone-run-lesson-button.png"))
        jump.focus()
        page.keyboard.press("Enter")  # the keyboard as a finger
        page.wait_for_function("() => document.querySelector('.rl-lesson-jump').textContent.startsWith('Back')")
        seen = page.evaluate("""() => { const walk = (root) => { for (const el of root.querySelectorAll('*')) {
            if (el.id === 'lesson-question') return el; if (el.shadowRoot) { const f = walk(el.shadowRoot);
            if (f) return f; } } return null; };
          const r = walk(document).getBoundingClientRect(); return [r.top, r.bottom, innerHeight]; }""")
        assert 0 <= seen[0] and seen[1] <= seen[2], seen  # the whole question on screen
        page.screenshot(path=str(shots() / "phone-lesson.png"))
        jump.click()  # and back to the run
        page.wait_for_function("() => scrollY < 100")
        assert jump.inner_text().startswith("Lesson")
        assert not page.js_errors, page.js_errors[:5]
    with context(width=1280, height=720, timeout_ms=60_000) as ctx:  # the lessons panel beside: no button
        page = new_page(ctx)
        page.goto(shared_app.url, timeout=LOAD_MS)
        page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)
        page.wait_for_timeout(1500)
        assert page.locator(".rl-lesson-jump").is_hidden()


# tab key, what shows it is built, its settings column and Start button
LIVE_TABS = [("linear", "#ro-lambda-zero .ro-value", ".linear-settings", None),
             ("hydro", ".hydro-start", ".hydro-settings", ".hydro-start"),
             ("nbody", ".nbody-start", ".nbody-settings", ".nbody-start"),
             ("saturation", ".sat-add", ".sat-settings", None)]


@pytest.mark.timeout(900)
@pytest.mark.parametrize("width,height", [(1280, 720), (1024, 768)])
def test_the_keyboard_reaches_start_and_the_settings_before_any_plot_toolbar(shared_app, width, height):
    with context(width=width, height=height, timeout_ms=60_000) as ctx:
        for key, ready, settings, start in LIVE_TABS:
            page = new_page(ctx)
            page.goto(f"{shared_app.url}?tab={key}", timeout=LOAD_MS)
            page.locator(ready).first.wait_for(state="visible", timeout=LOAD_MS)
            page.wait_for_timeout(1500)  # the page's access script runs once a second
            seen, first = [], {}
            for i in range(60):
                page.keyboard.press("Tab")
                f = page.evaluate(FOCUS_JS, {"settings": settings, "start": start or "#no-start"})
                seen.append(f)
                for what in ("plot", "setting", "start"):
                    if f and f[what]:
                        first.setdefault(what, i)
                if "plot" in first:
                    break
            trail = [f"{f['cls'][:30]}|{f['text'][:20]}" for f in seen if f]
            assert "plot" in first, (key, trail)
            assert first.get("setting", 99) < first["plot"], (key, width, trail)
            if start:
                assert first.get("start", 99) < first["plot"], (key, width, trail)
            assert not page.js_errors, page.js_errors[:5]
            page.close()


@pytest.mark.timeout(900)
@pytest.mark.parametrize("width,height", [(1024, 768), (1280, 720), (1366, 768)])
def test_the_linear_tabs_settings_stand_beside_its_curves(shared_app, width, height):
    with context(width=width, height=height, timeout_ms=60_000) as ctx:
        page = new_page(ctx)
        page.goto(shared_app.url, timeout=LOAD_MS)
        page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)
        page.wait_for_timeout(2000)  # the plots at their sizes
        slider = page.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-target")
        s = slider.bounding_box()
        plots = sorted(boxes(page, ".bk-Canvas"), key=lambda b: b["top"])
        growth = plots[0]  # the growth-rate plot, the first
        assert s["x"] + s["width"] <= growth["left"], (s, growth)  # beside it, at its left
        assert growth["top"] <= s["y"] <= growth["bottom"], (s, growth)  # level with it
        assert s["y"] + s["height"] <= height, s  # in the first screen
        page.screenshot(path=str(shots() / f"linear-{width}x{height}.png"))
        # scrolled to the third plot, the slider is still on screen (and still beside the curves)
        page.evaluate("(y) => scrollTo(0, y)", plots[2]["top"] - 100)
        page.wait_for_timeout(300)
        s = slider.bounding_box()
        assert 0 <= s["y"] and s["y"] + s["height"] <= height, s
        assert not page.js_errors, page.js_errors[:5]
