"""The Saturation tab's stability boundary lambda_st, the lesson step that opens it and the wave-train card,
in headless Debian Chromium (fixtures ``app_server``, ``browser_page`` of tests/conftest.py).

Lesson 2, step 4 ("Set up this step") must show the Saturation tab for tau15 isothermal with the lambda_st
key entry and the one-line explanation visible; the check accepts the table's value and rejects the
fastest-growing wavelength.  The wave-train card then computes 300 m in the server's compute pool while the
page stays usable (the lesson panel answers clicks meanwhile) and shows the stable verdict.  Screenshots at
1280 x 720 go to ``test-artifacts/shots/saturation_lambda_st*.png``.
"""
from __future__ import annotations

import re
import time

import pytest

from browser_support import ARTIFACTS, pytestmark  # noqa: F401
from ringlab.model.wave_trains import lambda_st_at, load_lambda_st

SHOTS = ARTIFACTS / "shots"


@pytest.mark.xdist_group("browser")
@pytest.mark.slow
@pytest.mark.timeout(600)
def test_lesson_step_opens_saturation_tab_with_lambda_st(app_server, browser_page):
    url, _ = app_server
    page = browser_page
    page.set_viewport_size({"width": 1280, "height": 720})
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.goto(url + "?lesson=2&step=4", timeout=150_000)
    page.locator("#lesson-step-title", has_text="Step 4. Where will the climb stop?").wait_for(timeout=120_000)
    page.locator(".lesson-setup button").click()
    page.locator("#lesson-setup-result.msg-ok").wait_for(timeout=60_000)
    page.locator(".bk-tab.bk-active", has_text="Saturation").wait_for(timeout=20_000)
    key = page.locator("#sat-key-lambda-st")
    key.wait_for(state="visible", timeout=30_000)
    assert "λ_st" in key.inner_text()
    assert "wave trains longer than λst are stable" in page.locator("#sat-st-line").inner_text().replace("\n", "")
    page.locator(".bk-Canvas").first.wait_for(timeout=30_000)
    page.wait_for_timeout(1500)  # the plot draws
    page.screenshot(path=str(SHOTS / "saturation_lambda_st.png"))

    ref = lambda_st_at(load_lambda_st()[0], "tau15", True, 0.0)["lambda_st_m"]
    box = page.locator(".lesson-answer input")
    for value, status in (("60", "wrong"), (f"{ref:.0f}", "correct")):
        box.fill(value)
        box.press("Enter")
        page.wait_for_timeout(200)
        page.locator(".lesson-check button").click()
        page.locator(f'[id^="lesson-feedback-"][id$="-{status}"]').last.wait_for(timeout=30_000)

    # the wave-train card: tau15 isothermal (set by the preset), sigma0 = 0, 300 m
    card_wl = page.locator(".wt-card input").nth(1)
    card_wl.fill("300")
    card_wl.press("Enter")
    page.wait_for_timeout(300)
    t0 = time.perf_counter()
    page.locator(".wt-compute button").click()
    page.locator("#wt-status", has_text=re.compile("Computing|Waiting")).wait_for(timeout=30_000)
    page.locator(".lessons-panel .bk-tab", has_text="Glossary").click()  # the page answers meanwhile
    page.locator("#gloss-lambda_zero").wait_for(timeout=10_000)
    t_click = time.perf_counter() - t0
    page.locator(".lessons-panel .bk-tab", has_text="Lessons").click()
    verdict = page.locator("#wt-verdict .ro-value")
    verdict.wait_for(timeout=300_000)
    t_done = time.perf_counter() - t0
    assert verdict.inner_text().strip() == "stable"
    assert "Computed in" in page.locator("#wt-status").inner_text()
    print(f"glossary answered {t_click:.1f} s after Compute; wave train shown after {t_done:.1f} s")
    page.locator(".wt-card").scroll_into_view_if_needed()
    page.wait_for_timeout(800)
    page.screenshot(path=str(SHOTS / "saturation_lambda_st_wave_train.png"))

    # the non-isothermal model: a line through sigma0 = 0 and 200 and crosses where there is no single boundary
    iso_box = page.locator("input[type=checkbox]").first  # the Saturation tab's "Isothermal model" (dynamic tabs)
    assert iso_box.is_checked()  # set by the lesson's preset
    iso_box.uncheck()
    page.wait_for_timeout(1500)
    page.locator(".bk-Canvas").first.scroll_into_view_if_needed()
    page.mouse.wheel(0, 250)
    page.wait_for_timeout(800)
    page.screenshot(path=str(SHOTS / "saturation_lambda_st_plot.png"))
    assert not page.js_errors, page.js_errors
