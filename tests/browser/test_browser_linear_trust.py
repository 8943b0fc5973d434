"""The Linear tab in Chromium: during a mouse drag of the sigma0 slider the readouts, marker key and
legend name the same sigma0 as the thick curve; at sigma0 = 1000 (Q0 = 0.80) a warning is shown and the
"Run this in Hydrodynamics" button is disabled with its reason."""
from __future__ import annotations

import re

import pytest

from ringcore import linear, params

from browser_support import ARTIFACTS, pytestmark, readout_m, wait_readout_change  # noqa: F401


@pytest.mark.xdist_group("browser")
@pytest.mark.timeout(180)
def test_drag_moves_readouts_with_the_curve_and_q0_warning(app_server, browser_page):
    url, _ = app_server
    page = browser_page
    page.goto(url, timeout=150_000)
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=60_000)
    page.locator(".bk-Canvas").nth(2).wait_for(timeout=30_000)
    handle = page.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
    box = handle.bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    old = page.locator("#ro-lambda-zero .ro-value").inner_text().strip()
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + 60, y, steps=6)  # still held: a drag (value changes, value_throttled not yet)
    wait_readout_change(page, "ro-lambda-zero", old)
    page.wait_for_timeout(1500)  # let the last preview arrive
    key = page.locator("#linear-key").inner_text()
    m = re.search(r"σ₀ = ([\d.]+) kg/m² \(current\)", key)
    assert m, key
    s = float(m.group(1))
    lz = linear.lambda_zero(params.get("tau15", s))
    assert readout_m(page, "ro-lambda-zero") == pytest.approx(lz, rel=1e-3)
    assert f"= {lz:.4g} m" in key  # the λ_zero marker's label
    page.screenshot(path=str(ARTIFACTS / "linear-drag.png"), full_page=True)
    page.mouse.up()

    handle.focus()
    handle.press("End")  # sigma0 = 1000 kg/m^2: Q0 = 0.80
    warning = page.locator("#linear-q0-warning")
    warning.wait_for(timeout=15_000)
    assert "Q0 = 0.80 < 1" in warning.inner_text().replace("\n", "")
    why = page.locator("#linear-carry-why-hydro")
    why.wait_for(timeout=15_000)
    assert "Hydrodynamics cannot run these settings" in why.inner_text()
    assert page.locator(".carry-hydro button").is_disabled()
    assert not page.locator(".carry-nbody button").is_disabled()
    page.screenshot(path=str(ARTIFACTS / "linear-q0-warning.png"), full_page=True)
    assert page.js_errors == []
