"""The Compare tab in headless Debian Chromium: two live runs started with one click.

Opens ``/main?tab=compare`` (the tier's shared app server and Chromium), presses "Start both", and checks
in the page that both runs' orbit counters advance and stay together (within one frame step), that both
space-time images were drawn (their Bokeh sources hold more than one row, both with the same colour mapper),
that the line says which control differs, and that no JavaScript error happened and the server logged no
traceback; then "Pause both".
Screenshots (1280 x 720) go to ``test-artifacts/shots/compare-*.png``.

Run alone with ``python -m pytest -p no:playwright tests/browser/test_browser_compare.py -q``.
Recipe: ``shared/guides/panel-live-app.md``; fixtures as in ``tests/browser/test_browser.py``.
"""
from __future__ import annotations

import re
import time

import pytest

from ringlab.model.compare_presets import PRESETS

from browser_support import ARTIFACTS, CHROMIUM, context, sync_playwright

SHOTS = ARTIFACTS / "shots"

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(sync_playwright is None, reason="playwright Python package not installed"),
    pytest.mark.skipif(not CHROMIUM.exists(), reason=f"{CHROMIUM} not found"),
]

# rows and columns of the image in a named source, and the id of its figure's colour mapper
IMAGE_JS = """
name => {
  for (const doc of Bokeh.documents) {
    const src = doc.get_model_by_name(name);
    if (src) {
      const img = src.data.image[0];
      const shape = img.shape || [img.length, (img[0] || []).length];
      let mapper = null;
      for (const m of doc.all_models) {
        if (m.data_source === src) { mapper = m.glyph.color_mapper.id; }
      }
      let rows = 0;  // rows computed so far (the canvas's rows not computed yet are NaN)
      for (let r = 0; r < shape[0]; r++) if (Number.isFinite(img[r * shape[1]])) rows += 1;
      return {rows: rows, cols: shape[1], dh: src.data.dh[0], mapper: mapper};
    }
  }
  return null;
}
"""
# both runs' orbit readouts from the page's models in one read (two DOM reads may straddle frames)
ORBITS_JS = """
() => {
  const out = {};
  for (const doc of Bokeh.documents) {
    for (const m of doc.all_models) {
      if (typeof m.text !== "string" || !m.text.includes("compare-")) { continue; }
      const t = m.text.replace(/&quot;/g, '"').replace(/&lt;/g, "<").replace(/&gt;/g, ">").replace(/&amp;/g, "&");
      for (const k of ["a", "b"]) {
        const mm = t.match(new RegExp(`id="compare-${k}-orbits">.*?class="ro-value">([0-9.]+)<`));
        if (mm) { out[k] = parseFloat(mm[1]); }
      }
    }
  }
  return out;
}
"""


def wait_status(page, log, text: str, timeout_ms: int = 15_000) -> None:
    """Wait for the status line to contain ``text``; on a timeout say what the page showed instead."""
    try:
        page.locator("#compare-status", has_text=text).wait_for(timeout=timeout_ms)
    except Exception as exc:
        shown = page.evaluate("() => document.querySelector('#compare-status')?.innerText")
        log = log.read_text(errors="replace")[-2000:]
        raise AssertionError(f"status {shown!r}, not {text!r}, after {timeout_ms} ms; orbits "
                             f"{page.evaluate(ORBITS_JS)}; server log ends:\n{log}") from exc


def orbit(page, k: str) -> float:
    text = page.locator(f"#compare-{k}-orbits .ro-value").inner_text().strip()
    return float(re.match(r"[\d.]+", text).group(0))


@pytest.mark.timeout(120)
def test_two_live_runs_side_by_side(shared_app):  # shared_app: no traceback in the server's log meanwhile
    t0 = time.perf_counter()
    ARTIFACTS.mkdir(exist_ok=True)
    SHOTS.mkdir(exist_ok=True)
    port, log = shared_app.port, shared_app.log
    phases = {}
    with context(1280, 720, timeout_ms=30_000) as ctx:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(f"http://127.0.0.1:{port}/main?tab=compare", wait_until="commit", timeout=90_000)
        page.locator("#compare-a-orbits .ro-value").wait_for(timeout=90_000)
        phases["page_loaded_s"] = time.perf_counter() - t0
        differs = page.locator("#compare-differs").inner_text()
        assert "differ in one control" in differs and "Surface density" in differs, differs
        assert orbit(page, "a") == 0.0 and orbit(page, "b") == 0.0
        page.locator(".compare-start button").click()
        deadline = time.perf_counter() + 30
        while time.perf_counter() < deadline:
            oa, ob = orbit(page, "a"), orbit(page, "b")
            if oa >= 3.0 and ob >= 3.0:
                break
            page.wait_for_timeout(250)
        assert oa >= 3.0 and ob >= 3.0, f"orbits A {oa}, B {ob} after 30 s"
        phases["hydro_pair_3_orbits_s"] = time.perf_counter() - t0
        for _ in range(5):  # the same frame never shows the runs more than one step (0.5 orbit) apart
            both = page.evaluate(ORBITS_JS)
            assert set(both) == {"a", "b"} and abs(both["a"] - both["b"]) <= 0.5 + 2e-3, both
            page.wait_for_timeout(150)
        page.wait_for_timeout(600)  # the rate-limited image frame after the counters
        img = {k: page.evaluate(IMAGE_JS, f"compare-{k}-image-source") for k in "ab"}
        for k, info in img.items():
            assert info and info["rows"] >= 3 and info["cols"] >= 100, (k, info)
        assert img["a"]["mapper"] == img["b"]["mapper"]  # one colour scale for both
        page.mouse.wheel(0, page.locator("#compare-a-title").bounding_box()["y"] - 4)  # titles to the top
        page.wait_for_timeout(500)
        page.screenshot(path=str(SHOTS / "compare-1280x720.png"))
        phases["first_screenshot_s"] = time.perf_counter() - t0
        page.locator(".compare-pause button").click()
        wait_status(page, log, "Paused: both runs at orbit")
        page.wait_for_timeout(800)  # frames already queued are applied
        a1, b1 = orbit(page, "a"), orbit(page, "b")
        assert a1 == b1  # the run behind caught up with the common clock
        page.wait_for_timeout(800)
        assert (orbit(page, "a"), orbit(page, "b")) == (a1, b1)  # paused: both clocks stand still
        page.screenshot(path=str(SHOTS / "compare-1280x720-full.png"), full_page=True)
        phases["paused_s"] = time.perf_counter() - t0
        # hydrodynamics vs N-body: the preset replaces run B by a live box, both advance together
        select = page.locator(".bk-input-group", has_text="Comparison").locator("select")
        select.select_option(label=PRESETS["engine"].label)
        page.locator("#compare-differs", has_text="N-body").wait_for(timeout=30_000)
        phases["preset_switched_s"] = time.perf_counter() - t0
        page.locator(".compare-start button").click()
        wait_status(page, log, "Running")
        deadline = time.perf_counter() + 30
        while time.perf_counter() < deadline and min(page.evaluate(ORBITS_JS).values()) < 1.1:
            page.wait_for_timeout(250)
        page.locator(".compare-pause button").click()
        wait_status(page, log, "Paused: both runs at orbit")
        page.wait_for_timeout(800)
        both = page.evaluate(ORBITS_JS)
        assert both["a"] == both["b"] >= 1.1, both
        nb = page.evaluate(IMAGE_JS, "compare-b-image-source")
        assert nb["rows"] >= 2 and nb["cols"] == 40, nb  # one row per orbit, 5 m zones in the 200 m box
        phases["nbody_pair_paused_s"] = time.perf_counter() - t0
        page.screenshot(path=str(SHOTS / "compare-nbody-1280x720-full.png"), full_page=True)
        assert not errors, errors
    phases["total_s"] = time.perf_counter() - t0
    print("compare browser test:", {k: round(v, 1) for k, v in phases.items()})
