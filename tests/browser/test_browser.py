"""End-to-end test of the web app in headless Debian Chromium (Playwright, no bundled browser).

Starts ``panel serve app/main.py`` on a free loopback port, opens the page, checks the
linear-theory readouts against ``ringcore.linear.summary`` and moves the sigma0 slider with
the keyboard.  Screenshots and timings go to ``test-artifacts/`` (git-ignored).

Run alone with ``.venv/bin/python -m pytest -p no:playwright -m browser tests/browser/test_browser.py``.
Recipe: ``shared/guides/panel-live-app.md`` ("A real-browser test that works here").
"""
from __future__ import annotations

import json
import time

import pytest

from ringcore import linear, params

from browser_support import ARTIFACTS, expect, pytestmark, readout_m, wait_readout_change  # noqa: F401



@pytest.mark.timeout(120)
def test_linear_tab_in_browser(app_server, browser_page):
    url, t_live = app_server
    page = browser_page
    timings = {"server_start_to_liveness_s": t_live}

    t0 = time.perf_counter()
    page.goto(url, timeout=150_000)  # building the page's models takes 20-40 s on a loaded machine
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=30_000)
    page.locator(".bk-Canvas").nth(2).wait_for(timeout=30_000)  # all three Bokeh figures laid out
    timings["page_load_to_first_plot_s"] = time.perf_counter() - t0
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-initial.png"), full_page=True)

    # defaults: tau15, non-isothermal, sigma0 = 400 kg/m^2 -> readouts equal the CLI's summary
    ref = linear.summary(params.get("tau15", 400.0))
    assert readout_m(page, "ro-lambda-zero") == pytest.approx(ref.lambda_zero_m, rel=1e-3)
    assert readout_m(page, "ro-lambda-max") == pytest.approx(ref.lambda_max_growth_m, rel=1e-3)
    assert page.locator("#ro-q0 .ro-value").inner_text().strip() == f"{ref.Q0:.2f}"

    # keyboard on the sigma0 slider: End -> 1000 kg/m^2, Home -> 0 (no self-gravity, no lambda_zero)
    handle = page.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
    handle.focus()
    old = page.locator("#ro-lambda-zero .ro-value").inner_text().strip()
    handle.press("End")
    timings["slider_to_readout_s"] = wait_readout_change(page, "ro-lambda-zero", old)
    assert readout_m(page, "ro-lambda-zero") == pytest.approx(
        linear.summary(params.get("tau15", 1000.0)).lambda_zero_m, rel=1e-3)
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-sigma0-1000.png"), full_page=True)

    old = page.locator("#ro-lambda-zero .ro-value").inner_text().strip()
    handle.press("Home")
    timings["slider_home_to_readout_s"] = wait_readout_change(page, "ro-lambda-zero", old)
    assert page.locator("#ro-lambda-zero .ro-value").inner_text().strip() == "—"
    assert page.locator("#ro-q0 .ro-value").inner_text().strip() == "∞"

    # st99 exists only as an isothermal model: choosing it switches the model, with a note
    select = page.locator("select").first
    select.select_option(value=select.locator("option", has_text="st99").get_attribute("value"))
    note = page.locator("#linear-note")
    note.wait_for(timeout=10_000)
    assert "isothermal" in note.inner_text() and "st99" in note.inner_text()
    page.locator("#linear-model", has_text="st99").wait_for(timeout=10_000)
    iso_box = page.locator("input[type=checkbox]").first  # the Linear tab's "Isothermal model" box
    expect(iso_box).to_be_checked(timeout=10_000)

    # unticking "Isothermal model" by hand gives a message next to the controls, not a traceback
    iso_box.uncheck()
    msg = page.locator("#linear-message")
    msg.wait_for(timeout=10_000)
    assert "isothermal" in msg.inner_text() and "st99" in msg.inner_text()
    page.screenshot(path=str(ARTIFACTS / "linear-invalid.png"), full_page=True)
    page.locator("input[type=checkbox]").first.check()
    msg.wait_for(state="hidden", timeout=10_000)
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-st99-isothermal.png"), full_page=True)

    (ARTIFACTS / "browser-timings.json").write_text(json.dumps(timings, indent=2))
    print("timings:", timings)
    assert not page.js_errors, f"JavaScript errors on the page: {page.js_errors}"
