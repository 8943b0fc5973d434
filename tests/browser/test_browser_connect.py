"""Browser test of "connect what the student sees" in headless Debian Chromium.

Sets σ₀ = 0 and the isothermal model in the Linear tab, clicks "Run this in Hydrodynamics", sees
the Hydrodynamics tab with those settings, runs it into the nonlinear phase (e_kin with the
linear-theory slope), opens the Saturation tab and fetches every tutorial link of the page from
the app server itself.  Screenshots at 1280x720 go to ``test-artifacts/shots/connect_*.png``.

The tier's shared app server (tests/browser_support.py) serves the executed tutorials (``make tutorials-html``)
if they are built, else small stand-in pages in a temporary folder, at /docs/tutorials/nb/
(``ringlab.lessons.tutorials.serve_args``).
Run alone with ``.venv/bin/python -m pytest -p no:playwright tests/browser/test_browser_connect.py``.
"""
from __future__ import annotations

import time
from urllib.parse import urljoin

import pytest

from browser_support import ARTIFACTS, context, pytestmark  # noqa: F401

SHOTS = ARTIFACTS / "shots"
LOAD_TIMEOUT_MS = 150_000


@pytest.fixture
def server(shared_app):
    """(URL, documentation site) of the tier's shared app server, which serves the site at /docs and logs no
    traceback or error meanwhile (the fixture ``shared_app``)."""
    return shared_app.url, shared_app.site


def value_of(page, css: str) -> float:
    return float(page.locator(css).inner_text().split()[0])


def test_run_this_in_hydrodynamics(server):
    url, site = server
    t0 = time.perf_counter()
    SHOTS.mkdir(parents=True, exist_ok=True)
    with context(1280, 720, timeout_ms=20_000) as ctx:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(url, wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_TIMEOUT_MS)
        # Linear tab: sigma0 -> 0 (Home key on the slider), isothermal model on
        handle = page.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
        handle.focus()
        handle.press("Home")
        page.locator("#ro-q0 .ro-value", has_text="∞").wait_for()
        page.locator("input[type=checkbox]").first.check()  # the Linear tab's "Isothermal model" box
        page.locator("#linear-model", has_text="tau15, isothermal model").first.wait_for()
        page.locator("#ro-lambda-max .ro-value", has_text="59.04").wait_for()  # tau15 isothermal, sigma0 = 0
        page.wait_for_timeout(500)
        page.screenshot(path=str(SHOTS / "connect_linear.png"))

        page.locator(".carry-hydro button").click()
        page.locator(".bk-tab.bk-active", has_text="Hydrodynamics").wait_for()
        label = page.locator("#hydro-run-label")
        label.wait_for()
        page.wait_for_function("() => true")
        deadline = time.time() + 20
        while "σ₀ = 0" not in label.inner_text() and time.time() < deadline:
            page.wait_for_timeout(200)
        text = label.inner_text()
        assert "σ₀ = 0 kg/m²" in text and "isothermal" in text and "non-isothermal" not in text, text
        assert page.locator(".hydro-isothermal input").is_checked()
        page.wait_for_timeout(500)
        page.screenshot(path=str(SHOTS / "connect_hydro_top.png"))
        # run into the nonlinear phase: the e_kin plot then shows the linear-theory slope and its end
        page.locator(".hydro-start button").click()
        deadline = time.time() + 40
        while value_of(page, "#hydro-orbits .ro-value") < 32 and time.time() < deadline:
            page.wait_for_timeout(500)
        page.locator(".hydro-pause button").click()
        assert value_of(page, "#hydro-orbits .ro-value") >= 20
        page.locator("#hydro-lp-note").wait_for()
        page.wait_for_timeout(1500)  # frames already queued are drawn
        for _ in range(10):  # the note is re-rendered while queued frames arrive: retry
            try:
                page.locator("#hydro-lp-note").evaluate("e => e.scrollIntoView({block: 'end'})", timeout=3000)
                break
            except Exception:
                page.wait_for_timeout(300)
        page.wait_for_timeout(300)
        page.screenshot(path=str(SHOTS / "connect_hydro_ekin.png"))

        hrefs = set()
        for a in page.locator("a.tutorial-link").all():
            hrefs.add(a.get_attribute("href"))
        page.locator(".bk-tab", has_text="Saturation").click()
        page.locator("#sat-lower-note").wait_for()
        page.locator("#sat-lower-note").evaluate("e => e.scrollIntoView({block: 'end'})")
        page.wait_for_timeout(800)
        page.screenshot(path=str(SHOTS / "connect_saturation.png"))
        for a in page.locator("a.tutorial-link").all():
            hrefs.add(a.get_attribute("href"))
        assert {"docs/tutorials/nb/02_hydro_without_self_gravity.html",
                "docs/tutorials/nb/03_self_gravity_sets_the_wavelength.html"} <= hrefs
        for h in hrefs:  # served by the app server itself
            r = page.request.get(urljoin(url, h))
            assert r.status == 200 and r.body() == (site / h.split("/", 1)[1]).read_bytes(), h
        assert not errors, errors
    print(f"browser connect test: {time.perf_counter() - t0:.1f} s")
